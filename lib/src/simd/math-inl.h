// Vector math shared by the SIMD lanes of the projections (simd/<projection>-inl.h): fast
// ratio and atan2, angle wrapping, Taylor polynomials, the closed frame test.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_MATH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_MATH_INL_H_
#undef PANOPROJ_SIMD_MATH_INL_H_
#else
#define PANOPROJ_SIMD_MATH_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <array>
#include <type_traits>

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DD = hn::ScalableTag<double>;
using VD = hn::Vec<DD>;
using MD = hn::Mask<DD>;

constexpr double kPiF = 3.14159265358979323846;

// num / den. Float lanes: the 14-bit reciprocal estimate and one Newton step (within 2 ulp;
// a division takes several times longer); double lanes divide.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V Ratio(D d, V num, V den) {
  if constexpr (std::is_same_v<hn::TFromD<D>, float> && HWY_TARGET != HWY_SCALAR) {
    const V r0 = hn::ApproximateReciprocal(den);
    const V r1 = hn::Mul(r0, hn::NegMulAdd(den, r0, hn::Set(d, 2.0f)));  // r (2 - den r)
    return hn::Mul(num, r1);
  } else {
    return hn::Div(num, den);
  }
}

// atan2(y, x) from the smaller-over-larger ratio in [0, 1], Highway's atan polynomial for that
// range (the reduction inside hn::Atan would cost a second division), and a quadrant fix-up
// (Highway 1.0.3 has no Atan2); 0 where x = y = 0. kXNonNegative: x >= 0 is known (no fix-up).
template <bool kXNonNegative = false, class D, class V = hn::Vec<D>>
HWY_INLINE V Atan2(D d, V y, V x) {
  using T = hn::TFromD<D>;
  const V zero = hn::Zero(d);
  const V ax = hn::Abs(x), ay = hn::Abs(y);
  const auto swap = hn::Lt(ax, ay);
  const V num = hn::IfThenElse(swap, ax, ay), den = hn::IfThenElse(swap, ay, ax);
  const auto both_zero = hn::Eq(den, zero);
  V a = hn::impl::AtanImpl<T>().AtanPoly(d, Ratio(d, num, hn::IfThenElse(both_zero, hn::Set(d, T(1)), den)));
  a = hn::IfThenElse(swap, hn::Sub(hn::Set(d, T(0.5 * kPiF)), a), a);  // [0, pi/2]
  if (!kXNonNegative) a = hn::IfThenElse(hn::Lt(x, zero), hn::Sub(hn::Set(d, T(kPiF)), a), a);  // [0, pi]
  a = hn::IfThenElse(hn::Lt(y, zero), hn::Neg(a), a);
  return hn::IfThenElse(both_zero, zero, a);
}

// An angle in (-3 pi, 3 pi) brought into [-pi, pi), as wrap_pi.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V WrapPi(D d, V a) {
  using T = hn::TFromD<D>;
  const V pi = hn::Set(d, T(kPiF)), two_pi = hn::Set(d, T(2 * kPiF));
  a = hn::IfThenElse(hn::Not(hn::Lt(a, pi)), hn::Sub(a, two_pi), a);
  return hn::IfThenElse(hn::Lt(a, hn::Neg(pi)), hn::Add(a, two_pi), a);
}

// Taylor coefficients (-1)^k / (2k + first)!, k = 0 .. N-1: sin(x)/x with first = 1, cos(x) with
// first = 0, as polynomials in q = x^2.
template <int N>
constexpr std::array<float, N> TaylorInQ(int first) {
  std::array<float, N> c{};
  double f = 1.0;  // (2k + first)!
  for (int i = 2; i <= first; ++i) f *= i;
  for (int k = 0; k < N; ++k) {
    c[k] = static_cast<float>((k % 2 ? -1.0 : 1.0) / f);
    f *= (2.0 * k + first + 1) * (2.0 * k + first + 2);
  }
  return c;
}

template <size_t N, class D, class V = hn::Vec<D>>
HWY_INLINE V Horner(D d, const std::array<float, N>& c, V q) {
  V acc = hn::Set(d, c[N - 1]);
  for (size_t k = N - 1; k-- > 0;) acc = hn::MulAdd(acc, q, hn::Set(d, c[k]));
  return acc;
}

// v in the closed [0, extent] with FramedBounds' slack (1e-9 of the extent).
template <class D, class V = hn::Vec<D>>
HWY_INLINE hn::Mask<D> Within(D d, V v, hn::TFromD<D> extent) {
  using T = hn::TFromD<D>;
  const V slack = hn::Set(d, T(1e-9) * extent);
  return hn::And(hn::Not(hn::Lt(v, hn::Neg(slack))), hn::Not(hn::Gt(v, hn::Add(hn::Set(d, extent), slack))));
}

// (px, py) in the closed frame [0, width] x [0, height], as above.
template <class D, class V = hn::Vec<D>>
HWY_INLINE hn::Mask<D> InFrame(D d, V px, V py, hn::TFromD<D> width, hn::TFromD<D> height) {
  return hn::And(Within(d, px, width), Within(d, py, height));
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
