// Hammer's vector forms (lanes in hammer.hpp), for float and double lanes.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_HAMMER_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_HAMMER_INL_H_
#undef PANOPROJ_SIMD_HAMMER_INL_H_
#else
#define PANOPROJ_SIMD_HAMMER_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include "simd/hammer.hpp"
#include "simd/map_frame-inl.h"
#include "simd/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// hammer.hpp's closed-form inverse: the unit vector (XW k, Y k, cos c) with k = sqrt(1 - rho^2/4),
// cos c = 1 - rho^2/2 gives sin phi = Y k, cos phi = |(XW k, cos c)| and lambda W = atan2(XW k,
// cos c); valid for rho^2 <= 4 and |lambda| <= lam_max.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void TargetRay(D d, const simd::HammerRays<T>& p, V px, V py, V& x, V& y, V& z, M& ok, M&) {
  V X, Y;
  PlanePoint(d, p.plane, px, py, X, Y);
  const V xw = hn::Mul(X, hn::Set(d, p.w));
  const V rho2 = hn::MulAdd(xw, xw, hn::Mul(Y, Y));
  const V k = hn::Sqrt(hn::Max(hn::NegMulAdd(rho2, hn::Set(d, T(0.25)), hn::Set(d, T(1))), hn::Zero(d)));
  const V cos_c = hn::NegMulAdd(rho2, hn::Set(d, T(0.5)), hn::Set(d, T(1)));
  const V a = hn::Mul(xw, k);
  const V lam = hn::Mul(Atan2(d, a, cos_c), hn::Set(d, p.inv_w));
  ok = hn::And(hn::Not(hn::Gt(rho2, hn::Set(d, T(4)))), hn::Not(hn::Gt(hn::Abs(lam), hn::Set(d, p.lam_max))));
  const V cp = hn::Sqrt(hn::MulAdd(a, a, hn::Mul(cos_c, cos_c)));
  const V lon = hn::Add(lam, hn::Set(d, p.plane.lon0));
  x = hn::Mul(cp, hn::Sin(d, lon));
  y = hn::Neg(hn::Mul(Y, k));
  z = hn::Mul(cp, hn::Cos(d, lon));
}

// As a source, the plane point of the ray's angles (MapAngles): d = sqrt(2 / (1 + cos phi
// cos(lambda W))), X = d cos phi sin(lambda W) / W, Y = d sin phi.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void Forward(D d, const simd::HammerSource<T>& s, V lam, V, V, V cp, V sp, V, V& X, V& Y, M&) {
  const V lw = hn::Mul(lam, hn::Set(d, s.w));
  const V dd = hn::Sqrt(hn::Div(hn::Set(d, T(2)), hn::MulAdd(cp, hn::Cos(d, lw), hn::Set(d, T(1)))));
  X = hn::Mul(hn::Mul(dd, cp), hn::Mul(hn::Sin(d, lw), hn::Set(d, s.inv_w)));
  Y = hn::Mul(dd, sp);
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
