// Aitoff's vector form as a source (lanes in aitoff.hpp), for float and double lanes.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_AITOFF_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_AITOFF_INL_H_
#undef PANOPROJ_SIMD_AITOFF_INL_H_
#else
#define PANOPROJ_SIMD_AITOFF_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <limits>

#include "simd/aitoff.hpp"
#include "simd/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// aitoff.hpp: h = sin^2(phi/2) + cos phi sin^2(lambda/4) = sin^2(alpha/2), written without
// cancellation: sin^2(phi/2) = y^2 / (2 n (n + |(x, z)|)), sin^2(lambda/4) = sin^2(lambda/2) /
// (2 (1 + cos(lambda/2))). g = alpha / sin alpha = asin(r) / (r sqrt(1 - h)), r = sqrt(h);
// X = 2 cos phi sin(lambda/2) g, Y = sin phi g. Float lanes: coarse where 1 - h < coarse_rest
// (g grows as 1 / sqrt(1 - h) towards the outline's antipode, and with it the error).
// (The plane point of the ray's angles, MapAngles.)
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void Forward(D d, const simd::AitoffSource<T>& s, V lam, V h2, V n, V cp, V sp, V y, V& X, V& Y,
                        M& coarse) {
  const V one = hn::Set(d, T(1));
  const V half = hn::Mul(lam, hn::Set(d, T(0.5)));
  const V sl = hn::Sin(d, half), cl = hn::Cos(d, half);
  const V s2 = hn::Div(hn::Mul(y, y), hn::Mul(hn::Set(d, T(2)), hn::Mul(n, hn::Add(n, hn::Sqrt(h2)))));
  const V s4 = hn::Div(hn::Mul(sl, sl), hn::Mul(hn::Set(d, T(2)), hn::Add(one, cl)));
  const V hh = hn::Min(one, hn::MulAdd(cp, s4, s2));
  const V r = hn::Sqrt(hh), rest = hn::Sub(one, hh);
  const M tiny = hn::Lt(r, hn::Set(d, T(1e-4)));
  // asin(r) / r: the series 1 + r^2 / 6 below 1e-4 (error < r^4 3/40).
  const V a_over_r = hn::IfThenElse(tiny, hn::MulAdd(hh, hn::Set(d, T(1.0 / 6)), one),
                                    hn::Div(hn::Asin(d, r), hn::IfThenElse(tiny, one, r)));
  const V gg = hn::Div(a_over_r, hn::Sqrt(hn::Max(rest, hn::Set(d, std::numeric_limits<T>::min()))));
  X = hn::Mul(hn::Mul(hn::Set(d, T(2)), cp), hn::Mul(sl, gg));
  Y = hn::Mul(sp, gg);
  coarse = hn::Lt(rest, hn::Set(d, s.coarse_rest));
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
