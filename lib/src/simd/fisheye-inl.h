// A fisheye's vector forms (lanes in fisheye.hpp), for float and double lanes.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_FISHEYE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_FISHEYE_INL_H_
#undef PANOPROJ_SIMD_FISHEYE_INL_H_
#else
#define PANOPROJ_SIMD_FISHEYE_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <limits>
#include <type_traits>

#include "simd/fisheye.hpp"
#include "simd/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Float lanes without inverse or direct trigonometry, from the law at radius r (r^2 = r2;
// clamped as the double form) and g = g_max: with k = sin(psi) / r,
//   equidistant  psi = g r:            k = g sinc(psi), cos psi, Taylor series in psi^2 <= pi^2
//                                      (10 and 11 terms: truncation < 1e-8);
//   equisolid    sin(psi/2) = s = g r/2: k = g sqrt(1 - s^2), cos psi = 1 - 2 s^2;
//   orthographic sin psi = s = g r:    k = g, cos psi = sqrt(1 - s^2);
//   stereographic tan(psi/2) = t = g r/2: k = g / (1 + t^2), cos psi = (1 - t^2) / (1 + t^2).
// coarse where sqrt(1 - s^2) loses float precision (s > 0.98, as the double form's arcsines).
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void FisheyeRayFloat(D d, const simd::FisheyeRays<float>& p, V u, V v, V r2, V& x, V& y, V& z, M& ok,
                                M& coarse) {
  static constexpr auto kSinc = TaylorInQ<10>(1);
  static constexpr auto kCos = TaylorInQ<11>(0);
  const V one = hn::Set(d, 1.0f), gv = hn::Set(d, p.g_max);
  coarse = hn::Lt(one, hn::Zero(d));  // none
  V q = hn::Mul(hn::Mul(gv, gv), r2);  // (g r)^2
  if (p.clip) {  // inside the circle, the law at min(r, 1)
    ok = hn::Not(hn::Gt(r2, one));
    q = hn::Mul(hn::Mul(gv, gv), hn::Min(r2, one));
  } else {  // wherever the law has an inverse: g r <= law_max
    const V limit2 = hn::Set(d, p.law_max * p.law_max);
    ok = hn::Not(hn::Gt(q, limit2));
    q = hn::Min(q, limit2);
  }
  V k, cz;
  switch (p.law) {
    case FisheyeModel::Equisolid: {
      const V s2 = hn::Mul(q, hn::Set(d, 0.25f));
      coarse = hn::Gt(s2, hn::Set(d, 0.98f * 0.98f));
      k = hn::Mul(gv, hn::Sqrt(hn::Max(hn::Sub(one, s2), hn::Zero(d))));
      cz = hn::NegMulAdd(hn::Set(d, 2.0f), s2, one);
      break;
    }
    case FisheyeModel::Orthographic:
      coarse = hn::Gt(q, hn::Set(d, 0.98f * 0.98f));
      k = gv;
      cz = hn::Sqrt(hn::Max(hn::Sub(one, q), hn::Zero(d)));
      break;
    case FisheyeModel::Stereographic: {
      const V t2 = hn::Mul(q, hn::Set(d, 0.25f));
      const V inv = hn::Div(one, hn::Add(one, t2));
      k = hn::Mul(gv, inv);
      cz = hn::Mul(hn::Sub(one, t2), inv);
      break;
    }
    default:  // equidistant
      k = hn::Mul(gv, Horner(d, kSinc, q));
      cz = Horner(d, kCos, q);
      break;
  }
  x = hn::Mul(k, u);
  y = hn::Mul(k, v);
  z = cz;
}

// The ray (sin psi u / r, sin psi v / r, cos psi) of pixel centres (px, py), psi the law's
// inverse at g_max r; at r = 0 the axis.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void TargetRay(D d, const simd::FisheyeRays<T>& p, V px, V py, V& x, V& y, V& z, M& ok, M& coarse) {
  const V u = hn::Mul(hn::Sub(px, hn::Set(d, p.cx)), hn::Set(d, p.inv_rx));
  const V v = hn::Mul(hn::Sub(py, hn::Set(d, p.cy)), hn::Set(d, p.inv_ry));
  const V r2 = hn::MulAdd(u, u, hn::Mul(v, v));
  if constexpr (std::is_same_v<T, float>) {
    FisheyeRayFloat(d, p, u, v, r2, x, y, z, ok, coarse);
    return;
  }
  const V r = hn::Sqrt(r2);
  // Clipped: inside the circle, the law at min(r, 1). Not clipped: wherever the law has an
  // inverse (g r <= law_max, with the same slack as Fisheye::inverse_law).
  V gv = hn::Mul(r, hn::Set(d, p.g_max));
  if (p.clip) {
    ok = hn::Not(hn::Gt(r, hn::Set(d, T(1.0 + 1e-9))));
    gv = hn::Mul(hn::Min(r, hn::Set(d, T(1))), hn::Set(d, p.g_max));
  } else {
    ok = hn::Not(hn::Gt(gv, hn::Set(d, p.law_max * T(1.0 + 1e-9))));
    gv = hn::Min(gv, hn::Set(d, p.law_max));
  }
  V psi;
  switch (p.law) {
    case FisheyeModel::Equisolid:
      psi = hn::Mul(hn::Set(d, T(2)), hn::Asin(d, hn::Min(hn::Mul(gv, hn::Set(d, T(0.5))), hn::Set(d, T(1)))));
      break;
    case FisheyeModel::Orthographic: psi = hn::Asin(d, hn::Min(gv, hn::Set(d, T(1)))); break;
    case FisheyeModel::Stereographic: psi = hn::Mul(hn::Set(d, T(2)), hn::Atan(d, hn::Mul(gv, hn::Set(d, T(0.5))))); break;
    default: psi = gv; break;  // equidistant
  }
  const V k = hn::Div(hn::Sin(d, psi), hn::Max(r, hn::Set(d, std::numeric_limits<T>::min())));
  x = hn::Mul(k, u);
  y = hn::Mul(k, v);
  z = hn::Cos(d, psi);
}

// Fisheye::to_pixel: psi = atan2(s, z), position = centre + (rx_g, ry_g) k (x, y) with k =
// law(psi) / s, s = |(x, y)|, n = |ray|: equidistant psi / s (1 / z on the axis), equisolid
// 2 sin(psi/2) / s = 1 / sqrt(n (n + z) / 2), orthographic sin psi / s = 1 / n, stereographic
// 2 tan(psi/2) / s = 2 / (n + z). Refused beyond psi_max, the law's limit, and the frame.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void SourcePixel(D d, const simd::FisheyeSource<T>& s, V x, V y, V z, V& sx, V& sy, M& ok, M& coarse) {
  const V zero = hn::Zero(d);
  const V s2 = hn::MulAdd(x, x, hn::Mul(y, y));
  const V sv = hn::Sqrt(s2), n = hn::Sqrt(hn::MulAdd(z, z, s2));
  const V psi = Atan2(d, sv, z);
  ok = hn::And(hn::Not(hn::Gt(psi, hn::Set(d, s.psi_max))), hn::Not(hn::Gt(psi, hn::Set(d, s.psi_limit))));
  // n + z; behind the camera (z < 0) double lanes, which have no coarse fallback, take
  // s^2 / (n - z) (the same, without cancellation).
  V npz = hn::Add(n, z);
  if constexpr (sizeof(T) == 8) npz = hn::IfThenElse(hn::Lt(z, zero), hn::Div(s2, hn::Sub(n, z)), npz);
  V k;
  switch (s.law) {
    case FisheyeModel::Equisolid: k = hn::Div(hn::Set(d, T(1)), hn::Sqrt(hn::Mul(hn::Mul(n, npz), hn::Set(d, T(0.5))))); break;
    case FisheyeModel::Orthographic: k = hn::Div(hn::Set(d, T(1)), n); break;
    case FisheyeModel::Stereographic:
      ok = hn::And(ok, hn::Lt(psi, hn::Set(d, T(kPiF))));
      k = hn::Div(hn::Set(d, T(2)), npz);
      break;
    default: {  // equidistant
      const M axis = hn::Eq(sv, zero);
      k = hn::Div(hn::IfThenElse(axis, hn::Set(d, T(1)), psi), hn::IfThenElse(axis, z, sv));
      break;
    }
  }
  // (s / n is small on the axis too, where k = psi / s -> 1 / z is well conditioned: only
  // behind, z < 0.)
  coarse = hn::Or(hn::Lt(npz, hn::Mul(hn::Set(d, s.coarse_npz), n)),
                  hn::And(hn::Lt(sv, hn::Mul(hn::Set(d, s.coarse_s), n)), hn::Lt(z, zero)));
  sx = hn::MulAdd(hn::Mul(k, x), hn::Set(d, s.rx_g), hn::Set(d, s.cx));
  sy = hn::MulAdd(hn::Mul(k, y), hn::Set(d, s.ry_g), hn::Set(d, s.cy));
  ok = hn::And(ok, InFrame(d, sx, sy, s.width, s.height));
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
