// The longitude-axis forms' vector forms (lanes in longitude_axis.hpp), for float and double
// lanes. Rays are not normalized: atan2 and ratios are scale-invariant.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_LONGITUDE_AXIS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_LONGITUDE_AXIS_INL_H_
#undef PANOPROJ_SIMD_LONGITUDE_AXIS_INL_H_
#else
#define PANOPROJ_SIMD_LONGITUDE_AXIS_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include "simd/longitude_axis.hpp"
#include "simd/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Equirect rays (cos lat sin lon, -sin lat, cos lat cos lon); cylindrical (sin lon, -t, cos lon)
// with t linear in y (not normalized). Every pixel has one.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void TargetRay(D d, const simd::AxisRays<T>& p, V px, V py, V& x, V& y, V& z, M&, M&) {
  const V lon = hn::MulAdd(px, hn::Set(d, p.lon_per_px), hn::Set(d, p.lon_first));
  if (p.cylinder) {
    x = hn::Sin(d, lon);
    y = hn::MulSub(py, hn::Set(d, p.fall), hn::Set(d, p.top));  // -t = -(top - py fall)
    z = hn::Cos(d, lon);
    return;
  }
  const V lat = hn::NegMulAdd(py, hn::Set(d, p.fall), hn::Set(d, p.top));
  const V cl = hn::Cos(d, lat);
  x = hn::Mul(cl, hn::Sin(d, lon));
  y = hn::Neg(hn::Sin(d, lat));
  z = hn::Mul(cl, hn::Cos(d, lon));
}

// x from the ray's (x, z): wrapped into [0, W) on a full circle, else refused beyond the span
// (LongitudeAxis::to_x) and the frame.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void LongitudeX(D d, const simd::AxisSource<T>& s, V x, V z, V& sx, M& ok) {
  const V lon = s.lon0 != T(0) ? WrapPi(d, hn::Sub(Atan2(d, x, z), hn::Set(d, s.lon0))) : Atan2(d, x, z);
  sx = hn::MulAdd(lon, hn::Set(d, s.px_per_lon), hn::Set(d, s.half_width));
  if (s.full) {
    // Full circle: keep x in [0, W) (the seam's far side is 0).
    sx = hn::IfThenElse(hn::Not(hn::Lt(sx, hn::Set(d, s.width))), hn::Sub(sx, hn::Set(d, s.width)), sx);
    sx = hn::Max(sx, hn::Zero(d));
    ok = hn::Eq(sx, sx);
  } else {
    ok = hn::And(hn::Not(hn::Gt(hn::Abs(lon), hn::Set(d, s.half_span))), Within(d, sx, s.width));
  }
}

// y from the ray's y and h2 = x^2 + z^2. coarse: float lanes near a pole (cos^2(latitude) =
// h2 / n^2 < coarse_cos2), where the longitude divides the ray's absolute error by cos(latitude)
// (a cylinder's height by cos^2).
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void LatitudeY(D d, const simd::AxisSource<T>& s, V y, V h2, V& sy, M& ok, M& coarse) {
  coarse = hn::Lt(h2, hn::Mul(hn::Set(d, s.coarse_cos2), hn::MulAdd(y, y, h2)));
  const V h = hn::Sqrt(h2);
  if (!s.cylinder) {
    sy = hn::Mul(hn::Sub(hn::Set(d, s.top), Atan2<true>(d, hn::Neg(y), h)), hn::Set(d, s.px_per_unit));
    // A full sphere's latitude is always in the frame.
    ok = s.full_sphere ? hn::Eq(sy, sy) : Within(d, sy, s.height);
  } else {  // height on the unit cylinder; the poles are at infinity
    const M off_pole = hn::Gt(h, hn::Zero(d));
    sy = hn::Mul(hn::Sub(hn::Div(hn::Neg(y), hn::IfThenElse(off_pole, h, hn::Set(d, T(1)))), hn::Set(d, s.top)),
                 hn::Set(d, s.px_per_unit));
    ok = hn::And(off_pole, Within(d, sy, s.height));
  }
}

template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void SourcePixel(D d, const simd::AxisSource<T>& s, V x, V y, V z, V& sx, V& sy, M& ok, M& coarse) {
  M ok_x;
  LongitudeX(d, s, x, z, sx, ok_x);
  LatitudeY(d, s, y, hn::MulAdd(x, x, hn::Mul(z, z)), sy, ok, coarse);
  ok = hn::And(ok, ok_x);
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
