// Double-precision vector geometry of the SIMD pairs (see simd_geometry.hpp), shared by the map
// builder (simd_geometry.cpp) and the fused converter (simd_sampler.cpp). Rays are not normalized:
// both sources' to_pixel are scale-invariant (atan2; ratios to the depth).
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_GEOMETRY_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_GEOMETRY_INL_H_
#undef PANOPROJ_SIMD_GEOMETRY_INL_H_
#else
#define PANOPROJ_SIMD_GEOMETRY_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "geometry/simd_geometry.hpp"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DD = hn::ScalableTag<double>;
using VD = hn::Vec<DD>;
using MD = hn::Mask<DD>;

constexpr double kPiF = 3.14159265358979323846;

// The geometry below is written once for float and double lanes (D); its parameters come from
// SimdGeometry in the lane type (params<T>()).

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

// A fisheye target's rays in float lanes without inverse or direct trigonometry, from the law at
// radius r (r^2 = r2; clamped as TargetRay does) and g = law(psi_max): with k = sin(psi) / r,
//   equidistant  psi = g r:            k = g sinc(psi), cos psi, Taylor series in psi^2 <= pi^2
//                                      (10 and 11 terms: truncation < 1e-8);
//   equisolid    sin(psi/2) = s = g r/2: k = g sqrt(1 - s^2), cos psi = 1 - 2 s^2;
//   orthographic sin psi = s = g r:    k = g, cos psi = sqrt(1 - s^2);
//   stereographic tan(psi/2) = t = g r/2: k = g / (1 + t^2), cos psi = (1 - t^2) / (1 + t^2).
// coarse where sqrt(1 - s^2) loses float precision (s > 0.98, as TargetRay's arcsines).
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void FisheyeRayFloat(D d, const SimdGeometry& g, V u, V v, V r2, V& x, V& y, V& z, M& ok, M& coarse) {
  static constexpr auto kSinc = TaylorInQ<10>(1);
  static constexpr auto kCos = TaylorInQ<11>(0);
  const V one = hn::Set(d, 1.0f), gv = hn::Set(d, g.pf.d[4]);
  coarse = hn::Lt(one, hn::Zero(d));  // none
  V q = hn::Mul(hn::Mul(gv, gv), r2);  // (g r)^2
  if (g.pf.d[5] != 0.0f) {  // clipped: inside the circle, the law at min(r, 1)
    ok = hn::Not(hn::Gt(r2, one));
    q = hn::Mul(hn::Mul(gv, gv), hn::Min(r2, one));
  } else {  // wherever the law has an inverse: g r <= limit
    const V limit2 = hn::Set(d, g.pf.d[6] * g.pf.d[6]);
    ok = hn::Not(hn::Gt(q, limit2));
    q = hn::Min(q, limit2);
  }
  V k, cz;
  switch (g.law) {
    case 1: {
      const V s2 = hn::Mul(q, hn::Set(d, 0.25f));
      coarse = hn::Gt(s2, hn::Set(d, 0.98f * 0.98f));
      k = hn::Mul(gv, hn::Sqrt(hn::Max(hn::Sub(one, s2), hn::Zero(d))));
      cz = hn::NegMulAdd(hn::Set(d, 2.0f), s2, one);
      break;
    }
    case 2:
      coarse = hn::Gt(q, hn::Set(d, 0.98f * 0.98f));
      k = gv;
      cz = hn::Sqrt(hn::Max(hn::Sub(one, q), hn::Zero(d)));
      break;
    case 3: {
      const V t2 = hn::Mul(q, hn::Set(d, 0.25f));
      const V inv = hn::Div(one, hn::Add(one, t2));
      k = hn::Mul(gv, inv);
      cz = hn::Mul(hn::Sub(one, t2), inv);
      break;
    }
    default:
      k = hn::Mul(gv, Horner(d, kSinc, q));
      cz = Horner(d, kCos, q);
      break;
  }
  x = hn::Mul(k, u);
  y = hn::Mul(k, v);
  z = cz;
}

// The rays of pixel centres (px, py) for the target. coarse: lanes where float lanes would be
// ill-conditioned (an arcsine argument near 1: d asin/da = 1/sqrt(1 - a^2)).
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void TargetRay(D d, const SimdGeometry& g, V px, V py, V& x, V& y, V& z, M& ok, M& coarse) {
  using T = hn::TFromD<D>;
  const T* p = g.params<T>().d;
  ok = hn::Eq(px, px);  // all true
  coarse = hn::Not(ok);
  x = y = z = hn::Zero(d);
  switch (g.dst) {
    case SimdGeometry::Dst::Pinhole: {
      // The rotated ray u R[:, 0] + v R[:, 1] + R[:, 2] ([4..12], column by column).
      const V u = hn::Mul(hn::Sub(px, hn::Set(d, p[2])), hn::Set(d, p[0]));
      const V v = hn::Mul(hn::Sub(py, hn::Set(d, p[3])), hn::Set(d, p[1]));
      x = hn::MulAdd(v, hn::Set(d, p[7]), hn::MulAdd(u, hn::Set(d, p[4]), hn::Set(d, p[10])));
      y = hn::MulAdd(v, hn::Set(d, p[8]), hn::MulAdd(u, hn::Set(d, p[5]), hn::Set(d, p[11])));
      z = hn::MulAdd(v, hn::Set(d, p[9]), hn::MulAdd(u, hn::Set(d, p[6]), hn::Set(d, p[12])));
      return;
    }
    case SimdGeometry::Dst::Equirect: {
      const V lon = hn::MulAdd(px, hn::Set(d, p[6]), hn::Set(d, p[8]));
      const V lat = hn::NegMulAdd(py, hn::Set(d, p[7]), hn::Set(d, p[4]));
      const V cl = hn::Cos(d, lat);
      x = hn::Mul(cl, hn::Sin(d, lon));
      y = hn::Neg(hn::Sin(d, lat));
      z = hn::Mul(cl, hn::Cos(d, lon));
      return;
    }
    case SimdGeometry::Dst::Cylindrical: {
      // (sin lon, -t, cos lon), t = tan(lat) linear in y (not normalized).
      const V lon = hn::MulAdd(px, hn::Set(d, p[6]), hn::Set(d, p[8]));
      x = hn::Sin(d, lon);
      y = hn::MulSub(py, hn::Set(d, p[7]), hn::Set(d, p[4]));  // -t = -(t_top - py dt)
      z = hn::Cos(d, lon);
      return;
    }
    case SimdGeometry::Dst::Hammer: {
      // Hammer.hpp's closed-form inverse: the unit vector (XW k, Y k, cos c) with
      // k = sqrt(1 - rho^2/4), cos c = 1 - rho^2/2 gives sin phi = Y k, cos phi = |(XW k, cos c)|
      // and lambda W = atan2(XW k, cos c); valid for rho^2 <= 4 and |lambda| <= pi (+ slack).
      const V X = hn::MulAdd(px, hn::Set(d, p[1]), hn::Set(d, p[0]));
      const V Y = hn::NegMulAdd(py, hn::Set(d, p[3]), hn::Set(d, p[2]));
      const V xw = hn::Mul(X, hn::Set(d, p[4]));
      const V rho2 = hn::MulAdd(xw, xw, hn::Mul(Y, Y));
      const V k = hn::Sqrt(hn::Max(hn::NegMulAdd(rho2, hn::Set(d, T(0.25)), hn::Set(d, T(1))), hn::Zero(d)));
      const V cos_c = hn::NegMulAdd(rho2, hn::Set(d, T(0.5)), hn::Set(d, T(1)));
      const V a = hn::Mul(xw, k);
      const V lam = hn::Mul(Atan2(d, a, cos_c), hn::Set(d, p[5]));
      ok = hn::And(hn::Not(hn::Gt(rho2, hn::Set(d, T(4)))), hn::Not(hn::Gt(hn::Abs(lam), hn::Set(d, p[7]))));
      const V cp = hn::Sqrt(hn::MulAdd(a, a, hn::Mul(cos_c, cos_c)));
      const V lon = hn::Add(lam, hn::Set(d, p[6]));
      x = hn::Mul(cp, hn::Sin(d, lon));
      y = hn::Neg(hn::Mul(Y, k));
      z = hn::Mul(cp, hn::Cos(d, lon));
      return;
    }
    case SimdGeometry::Dst::Bonne: {
      // bonne.hpp's inverse: [0] xmin, [1] plane units per pixel in x, [2] ymax, [3] in y, [6]
      // lon0, [8] |phi1|, [9] the mirror sign, [10] tan, [11] cot, [12] 1 for the 1/rho form.
      const V one = hn::Set(d, T(1));
      const V X = hn::MulAdd(px, hn::Set(d, p[1]), hn::Set(d, p[0]));
      const V Y = hn::Mul(hn::NegMulAdd(py, hn::Set(d, p[3]), hn::Set(d, p[2])), hn::Set(d, p[9]));
      const V p1 = hn::Set(d, p[8]);
      V phi, rec;  // latitude, and rho E (lambda cos phi)
      if (p[12] != T(0)) {
        const V t = hn::Set(d, p[10]);
        const V a = hn::NegMulAdd(t, Y, one);
        const V tx = hn::Mul(t, X);
        const V root = hn::Sqrt(hn::MulAdd(tx, tx, hn::Mul(a, a)));
        const V num = hn::NegMulAdd(t, hn::MulAdd(X, X, hn::Mul(Y, Y)), hn::Add(Y, Y));
        phi = hn::Add(p1, hn::Div(num, hn::Add(one, root)));
        rec = hn::Mul(root, p[10] > T(1e-150) ? hn::Div(Atan2(d, tx, a), t) : X);
      } else {
        const V cy = hn::Sub(hn::Set(d, p[11]), Y);
        const V rho = hn::Sqrt(hn::MulAdd(X, X, hn::Mul(cy, cy)));
        phi = hn::Sub(hn::Add(hn::Set(d, p[11]), p1), rho);
        rec = hn::Mul(rho, Atan2(d, X, cy));
      }
      const V half_pi = hn::Set(d, T(0.5 * kPiF));
      ok = hn::Not(hn::Gt(hn::Abs(phi), hn::Set(d, T(0.5 * kPiF * (1.0 + kEdgeSlack)))));
      phi = hn::Min(half_pi, hn::Max(hn::Neg(half_pi), phi));
      const V cp = hn::Cos(d, phi);
      const hn::Mask<D> pole = hn::Not(hn::Gt(cp, hn::Set(d, T(1e-15))));
      const V lam = hn::IfThenElseZero(hn::Not(pole), hn::Div(rec, hn::IfThenElse(pole, one, cp)));
      ok = hn::And(ok, hn::Not(hn::Gt(hn::Abs(lam), hn::Set(d, T(kPiF * (1.0 + kEdgeSlack))))));
      const V lon = hn::Add(lam, hn::Set(d, p[6]));
      x = hn::Mul(cp, hn::Sin(d, lon));
      y = hn::Neg(hn::Mul(hn::Sin(d, phi), hn::Set(d, p[9])));
      z = hn::Mul(cp, hn::Cos(d, lon));
      return;
    }
    case SimdGeometry::Dst::CubeFace: {
      const V a = hn::MulSub(hn::Sub(px, hn::Set(d, p[1])), hn::Set(d, p[12]), hn::Set(d, T(1)));
      const V b = hn::MulSub(hn::Sub(py, hn::Set(d, p[2])), hn::Set(d, p[12]), hn::Set(d, T(1)));
      x = hn::MulAdd(b, hn::Set(d, p[9]), hn::MulAdd(a, hn::Set(d, p[6]), hn::Set(d, p[3])));
      y = hn::MulAdd(b, hn::Set(d, p[10]), hn::MulAdd(a, hn::Set(d, p[7]), hn::Set(d, p[4])));
      z = hn::MulAdd(b, hn::Set(d, p[11]), hn::MulAdd(a, hn::Set(d, p[8]), hn::Set(d, p[5])));
      return;
    }
    case SimdGeometry::Dst::Fisheye: {
      const V u = hn::Mul(hn::Sub(px, hn::Set(d, p[0])), hn::Set(d, p[2]));
      const V v = hn::Mul(hn::Sub(py, hn::Set(d, p[1])), hn::Set(d, p[3]));
      const V r2 = hn::MulAdd(u, u, hn::Mul(v, v));
      if constexpr (std::is_same_v<T, float>) {
        FisheyeRayFloat(d, g, u, v, r2, x, y, z, ok, coarse);
        return;
      }
      const V r = hn::Sqrt(r2);
      // Clipped: inside the circle, the law at min(r, 1). Not clipped: wherever the law has an
      // inverse (g r <= p[6], with the same slack as Fisheye::inverse_law).
      V gv = hn::Mul(r, hn::Set(d, p[4]));
      if (p[5] != T(0)) {
        ok = hn::Not(hn::Gt(r, hn::Set(d, T(1.0 + 1e-9))));
        gv = hn::Mul(hn::Min(r, hn::Set(d, T(1))), hn::Set(d, p[4]));
      } else {
        ok = hn::Not(hn::Gt(gv, hn::Set(d, p[6] * T(1.0 + 1e-9))));
        gv = hn::Min(gv, hn::Set(d, p[6]));
      }
      V psi;
      switch (g.law) {
        case 1: psi = hn::Mul(hn::Set(d, T(2)), hn::Asin(d, hn::Min(hn::Mul(gv, hn::Set(d, T(0.5))), hn::Set(d, T(1))))); break;
        case 2: psi = hn::Asin(d, hn::Min(gv, hn::Set(d, T(1)))); break;
        case 3: psi = hn::Mul(hn::Set(d, T(2)), hn::Atan(d, hn::Mul(gv, hn::Set(d, T(0.5))))); break;
        default: psi = gv; break;
      }
      // (sin psi u / r, sin psi v / r, cos psi); at r = 0 the direction is the axis.
      const V k = hn::Div(hn::Sin(d, psi), hn::Max(r, hn::Set(d, std::numeric_limits<T>::min())));
      x = hn::Mul(k, u);
      y = hn::Mul(k, v);
      z = hn::Cos(d, psi);
      return;
    }
  }
}

// v in the closed [0, extent] with FramedBounds' slack (1e-9 of the extent).
template <class D, class V = hn::Vec<D>>
HWY_INLINE hn::Mask<D> Within(D d, V v, hn::TFromD<D> extent) {
  using T = hn::TFromD<D>;
  const V slack = hn::Set(d, T(1e-9) * extent);
  return hn::And(hn::Not(hn::Lt(v, hn::Neg(slack))), hn::Not(hn::Gt(v, hn::Add(hn::Set(d, extent), slack))));
}

// Longitude-axis sources (equirect, cylindrical), x from the ray's (x, z): wrapped into [0, W)
// on a full circle, else refused beyond the span (LongitudeAxis::to_x) and the frame.
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void LongitudeX(D d, const SimdGeometry& g, V x, V z, V& sx, M& ok) {
  using T = hn::TFromD<D>;
  const T* s = g.params<T>().s;
  const V lon = s[2] != T(0) ? WrapPi(d, hn::Sub(Atan2(d, x, z), hn::Set(d, s[2]))) : Atan2(d, x, z);
  sx = hn::MulAdd(lon, hn::Set(d, s[6]), hn::Set(d, s[8]));
  if (s[10] != T(0)) {
    // Full circle: keep x in [0, W) (the seam's far side is 0).
    sx = hn::IfThenElse(hn::Not(hn::Lt(sx, hn::Set(d, s[0]))), hn::Sub(sx, hn::Set(d, s[0])), sx);
    sx = hn::Max(sx, hn::Zero(d));
    ok = hn::Eq(sx, sx);
  } else {
    ok = hn::And(hn::Not(hn::Gt(hn::Abs(lon), hn::Set(d, s[11]))), Within(d, sx, s[0]));
  }
}

// Their y from the ray's y and h2 = x^2 + z^2. coarse: float lanes near a pole (cos^2(latitude)
// = h2 / n^2 < s[9]), where the longitude divides the ray's absolute error by cos(latitude).
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void LatitudeY(D d, const SimdGeometry& g, V y, V h2, V& sy, M& ok, M& coarse) {
  using T = hn::TFromD<D>;
  const T* s = g.params<T>().s;
  coarse = hn::Lt(h2, hn::Mul(hn::Set(d, s[9]), hn::MulAdd(y, y, h2)));
  const V h = hn::Sqrt(h2);
  if (g.src == SimdGeometry::Src::Equirect) {
    sy = hn::Mul(hn::Sub(hn::Set(d, s[4]), Atan2<true>(d, hn::Neg(y), h)), hn::Set(d, s[7]));
    // A full sphere's latitude is always in the frame ([12] = 1).
    ok = s[12] != T(0) ? hn::Eq(sy, sy) : Within(d, sy, s[3]);
  } else {  // height on the unit cylinder; the poles are at infinity
    const M off_pole = hn::Gt(h, hn::Zero(d));
    sy = hn::Mul(hn::Sub(hn::Div(hn::Neg(y), hn::IfThenElse(off_pole, h, hn::Set(d, T(1)))), hn::Set(d, s[4])),
                 hn::Set(d, s[7]));
    ok = hn::And(off_pole, Within(d, sy, s[3]));
  }
}

// Source pixel of ray (x, y, z). coarse: lanes where float lanes would err by more than
// SimdGeometry::kFloatTolerance (near a pole the longitude divides the ray's absolute error by
// cos(latitude), a cylinder's height by cos^2: lanes with cos^2(latitude) < s[9]).
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void SourcePixel(D d, const SimdGeometry& g, V x, V y, V z, V& sx, V& sy, M& ok, M& coarse) {
  using T = hn::TFromD<D>;
  const T* s = g.params<T>().s;
  const V zero = hn::Zero(d);
  auto in_frame = [&](V px, V py) { return hn::And(Within(d, px, s[0]), Within(d, py, s[3])); };
  if (g.src == SimdGeometry::Src::Equirect || g.src == SimdGeometry::Src::Cylindrical) {
    M ok_x;
    LongitudeX(d, g, x, z, sx, ok_x);
    LatitudeY(d, g, y, hn::MulAdd(x, x, hn::Mul(z, z)), sy, ok, coarse);
    ok = hn::And(ok, ok_x);
    return;
  }
  if (g.src == SimdGeometry::Src::Pinhole) {
    // x = cx + fx x / z, y = cy + fy y / z for z > 0. Float lanes err by f eps (1 + t^2) with
    // t^2 = (x^2 + y^2) / z^2: coarse beyond s[9].
    const M pos = hn::Gt(z, zero);
    const V inv = hn::Div(hn::Set(d, T(1)), hn::IfThenElse(pos, z, hn::Set(d, T(1))));
    sx = hn::MulAdd(hn::Mul(x, inv), hn::Set(d, s[1]), hn::Set(d, s[4]));
    sy = hn::MulAdd(hn::Mul(y, inv), hn::Set(d, s[2]), hn::Set(d, s[5]));
    ok = hn::And(pos, in_frame(sx, sy));
    coarse = hn::Gt(hn::MulAdd(x, x, hn::Mul(y, y)), hn::Mul(hn::Set(d, s[9]), hn::Mul(z, z)));
    return;
  }
  if (g.src == SimdGeometry::Src::Fisheye) {
    // Fisheye::to_pixel: psi = atan2(|(x, y)|, z), r = law(psi) / g along (x, y) / |(x, y)|:
    // position = centre + (rx, ry) k (x, y) with k = law(psi) / (g s), s = |(x, y)|, n = |ray|:
    //   equidistant k = psi / (g s) (1 / (g z) on the axis), equisolid 2 sin(psi/2) / s =
    //   1 / sqrt(n (n + z) / 2), orthographic sin psi / s = 1 / n, stereographic
    //   2 tan(psi/2) / s = 2 / (n + z). Refused beyond psi_max (clipped), the law's limit, and
    //   the frame. Float lanes: coarse near psi = pi (n + z or s small), where they lose digits.
    const V s2 = hn::MulAdd(x, x, hn::Mul(y, y));
    const V sv = hn::Sqrt(s2), n = hn::Sqrt(hn::MulAdd(z, z, s2));
    const V psi = Atan2(d, sv, z);
    ok = hn::And(hn::Not(hn::Gt(psi, hn::Set(d, s[6]))), hn::Not(hn::Gt(psi, hn::Set(d, s[7]))));
    const V npz = hn::Add(n, z);
    V k;
    switch (static_cast<int>(s[10])) {
      case 1: k = hn::Div(hn::Set(d, T(1)), hn::Sqrt(hn::Mul(hn::Mul(n, npz), hn::Set(d, T(0.5))))); break;
      case 2: k = hn::Div(hn::Set(d, T(1)), n); break;
      case 3:
        ok = hn::And(ok, hn::Lt(psi, hn::Set(d, T(kPiF))));
        k = hn::Div(hn::Set(d, T(2)), npz);
        break;
      default: {
        const M axis = hn::Eq(sv, zero);
        k = hn::Div(hn::IfThenElse(axis, hn::Set(d, T(1)), psi), hn::IfThenElse(axis, z, sv));
        break;
      }
    }
    // (s / n is small on the axis too, where k = psi / s -> 1 / z is well conditioned: only
    // behind, z < 0.)
    coarse = hn::Or(hn::Lt(npz, hn::Mul(hn::Set(d, s[11]), n)),
                    hn::And(hn::Lt(sv, hn::Mul(hn::Set(d, s[12]), n)), hn::Lt(z, zero)));
    sx = hn::MulAdd(hn::Mul(k, x), hn::Set(d, s[4]), hn::Set(d, s[1]));
    sy = hn::MulAdd(hn::Mul(k, y), hn::Set(d, s[5]), hn::Set(d, s[2]));
    ok = hn::And(ok, in_frame(sx, sy));
    return;
  }
  if (g.src == SimdGeometry::Src::Hammer || g.src == SimdGeometry::Src::Aitoff || g.src == SimdGeometry::Src::Bonne) {
    // The maps' forward equations on the normalized ray: lambda relative to lon0 (wrapped),
    // cos phi = |(x, z)| / n, sin phi = -y / n; then the frame (MapFrame: [4] xmin, [5] pixels
    // per unit in x, [6] ymax, [7] in y), closed. Near the poles an error in lambda is multiplied
    // by cos phi.
    coarse = hn::Lt(zero, zero);
    const V one = hn::Set(d, T(1));
    const V lam = s[2] != T(0) ? WrapPi(d, hn::Sub(Atan2(d, x, z), hn::Set(d, s[2]))) : Atan2(d, x, z);
    const V h2 = hn::MulAdd(x, x, hn::Mul(z, z));
    const V n = hn::Sqrt(hn::MulAdd(y, y, h2)), inv_n = hn::Div(one, n);
    const V cp = hn::Mul(hn::Sqrt(h2), inv_n), sp = hn::Neg(hn::Mul(y, inv_n));
    V X, Y;
    if (g.src == SimdGeometry::Src::Hammer) {
      // d = sqrt(2 / (1 + cos phi cos(lambda W))), X = d cos phi sin(lambda W) / W, Y = d sin phi.
      const V lw = hn::Mul(lam, hn::Set(d, s[1]));
      const V dd = hn::Sqrt(hn::Div(hn::Set(d, T(2)), hn::MulAdd(cp, hn::Cos(d, lw), one)));
      X = hn::Mul(hn::Mul(dd, cp), hn::Mul(hn::Sin(d, lw), hn::Set(d, s[8])));
      Y = hn::Mul(dd, sp);
    } else if (g.src == SimdGeometry::Src::Aitoff) {
      // aitoff.hpp: h = sin^2(phi/2) + cos phi sin^2(lambda/4) = sin^2(alpha/2), written without
      // cancellation: sin^2(phi/2) = y^2 / (2 n (n + |(x, z)|)), sin^2(lambda/4) = sin^2(lambda/2)
      // / (2 (1 + cos(lambda/2))). g = alpha / sin alpha = asin(r) / (r sqrt(1 - h)), r = sqrt(h);
      // X = 2 cos phi sin(lambda/2) g, Y = sin phi g. Float lanes: coarse where 1 - h < s[8]
      // (g grows as 1 / sqrt(1 - h) towards the outline's antipode, and with it the error).
      const V half = hn::Mul(lam, hn::Set(d, T(0.5)));
      const V sl = hn::Sin(d, half), cl = hn::Cos(d, half);
      const V s2 = hn::Div(hn::Mul(y, y), hn::Mul(hn::Set(d, T(2)), hn::Mul(n, hn::Add(n, hn::Sqrt(h2)))));
      const V s4 = hn::Div(hn::Mul(sl, sl), hn::Mul(hn::Set(d, T(2)), hn::Add(one, cl)));
      const V hh = hn::Min(one, hn::MulAdd(cp, s4, s2));
      const V r = hn::Sqrt(hh), rest = hn::Sub(one, hh);
      const hn::Mask<D> tiny = hn::Lt(r, hn::Set(d, T(1e-4)));
      // asin(r) / r: the series 1 + r^2 / 6 below 1e-4 (error < r^4 3/40).
      const V a_over_r = hn::IfThenElse(tiny, hn::MulAdd(hh, hn::Set(d, T(1.0 / 6)), one),
                                        hn::Div(hn::Asin(d, r), hn::IfThenElse(tiny, one, r)));
      const V gg = hn::Div(a_over_r, hn::Sqrt(hn::Max(rest, hn::Set(d, std::numeric_limits<T>::min()))));
      X = hn::Mul(hn::Mul(hn::Set(d, T(2)), cp), hn::Mul(sl, gg));
      Y = hn::Mul(sp, gg);
      coarse = hn::Lt(rest, hn::Set(d, s[8]));
    } else {
      // bonne.hpp, phi mirrored by s[9] (a southern phi1), [8] |phi1|, [10] tan, [11] cot, [12] 1
      // for the 1/rho form of small |phi1|. coarse: float lanes near Werner's apex (rho < s[13]).
      const V phi = hn::Mul(Atan2<true>(d, sp, cp), hn::Set(d, s[9]));
      const V p1 = hn::Set(d, s[8]);
      auto sinc = [&](V e) {
        const hn::Mask<D> at0 = hn::Lt(hn::Abs(e), hn::Set(d, T(1e-30)));
        return hn::IfThenElse(at0, one, hn::Div(hn::Sin(d, e), hn::IfThenElse(at0, one, e)));
      };
      if (s[12] != T(0)) {
        const V t = hn::Set(d, s[10]);
        const V q = hn::Div(t, hn::MulAdd(t, hn::Sub(p1, phi), one));
        const V lc = hn::Mul(lam, cp), e = hn::Mul(lc, q), eh = hn::Mul(e, hn::Set(d, T(0.5)));
        X = hn::Mul(lc, sinc(e));
        Y = hn::MulAdd(lc, hn::Mul(hn::Sin(d, eh), sinc(eh)), hn::Sub(phi, p1));
      } else {
        const V rho = hn::Sub(hn::Add(hn::Set(d, s[11]), p1), phi);
        const hn::Mask<D> apex = hn::Not(hn::Gt(rho, hn::Set(d, T(1e-300))));
        const V e = hn::IfThenElse(apex, lam, hn::Div(hn::Mul(lam, cp), hn::IfThenElse(apex, one, rho)));
        X = hn::Mul(rho, hn::Sin(d, e));
        Y = hn::NegMulAdd(rho, hn::Cos(d, e), hn::Set(d, s[11]));
        coarse = hn::Lt(rho, hn::Set(d, s[13]));
      }
      Y = hn::Mul(Y, hn::Set(d, s[9]));
    }
    sx = hn::Mul(hn::Sub(X, hn::Set(d, s[4])), hn::Set(d, s[5]));
    sy = hn::Mul(hn::Sub(hn::Set(d, s[6]), Y), hn::Set(d, s[7]));
    ok = in_frame(sx, sy);
    return;
  }
  // Cubemap: the face of the largest component (ties: x, then y, then z, as cube_face_of).
  coarse = hn::Lt(zero, zero);  // none
  const V ax = hn::Abs(x), ay = hn::Abs(y), az = hn::Abs(z);
  const M xf = hn::And(hn::Not(hn::Lt(ax, ay)), hn::Not(hn::Lt(ax, az)));
  const M yf = hn::AndNot(xf, hn::Not(hn::Lt(ay, az)));
  // Per face (0 front, 1 right, 2 back, 3 left, 4 up, 5 down): depth, numerators of a and b.
  const M xp = hn::Gt(x, zero), yp = hn::Gt(y, zero), zp = hn::Gt(z, zero);
  const V depth = hn::IfThenElse(xf, ax, hn::IfThenElse(yf, ay, az));
  const V an = hn::IfThenElse(xf, hn::IfThenElse(xp, hn::Neg(z), z), hn::IfThenElse(yf, x, hn::IfThenElse(zp, x, hn::Neg(x))));
  const V bn = hn::IfThenElse(xf, y, hn::IfThenElse(yf, hn::IfThenElse(yp, hn::Neg(z), z), y));
  // The face's origin (s[1 + f], s[7 + f]) chosen by the same masks.
  auto origin = [&](const T* o) {
    return hn::IfThenElse(xf, hn::IfThenElse(xp, hn::Set(d, o[1]), hn::Set(d, o[3])),
                          hn::IfThenElse(yf, hn::IfThenElse(yp, hn::Set(d, o[5]), hn::Set(d, o[4])),
                                         hn::IfThenElse(zp, hn::Set(d, o[0]), hn::Set(d, o[2]))));
  };
  const V inv = hn::Div(hn::Set(d, T(1)), depth);
  const V a = hn::Mul(an, inv), b = hn::Mul(bn, inv);
  const V ox = origin(s + 1), oy = origin(s + 7);
  // Within the face's cell [o, o + F): the far edge becomes the largest value below o + F in the
  // lane type (s[0] = F, s[14] = F / 2).
  const V half_f = hn::Set(d, s[14]), f = hn::Set(d, s[0]);
  const hn::RebindToSigned<D> di;
  auto below = [&](V v) { return hn::BitCast(d, hn::Sub(hn::BitCast(di, v), hn::Set(di, 1))); };
  sx = hn::Min(hn::Add(ox, hn::Max(hn::MulAdd(a, half_f, half_f), zero)), below(hn::Add(ox, f)));
  sy = hn::Min(hn::Add(oy, hn::Max(hn::MulAdd(b, half_f, half_f), zero)), below(hn::Add(oy, f)));
  ok = hn::Gt(depth, zero);
}

// Source positions (sx, sy) of target rays (x, y, z) (ok_dst, coarse_dst from TargetRay):
// rotation, source pixel; ok where both sides are valid; coarse where float lanes are not
// accurate enough.
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void SourceOfRays(D d, const SimdGeometry& g, V x, V y, V z, M ok_dst, M coarse_dst, V& sx, V& sy, M& ok,
                             M& coarse) {
  using T = hn::TFromD<D>;
  const T* r = g.params<T>().r;
  M ok_src, coarse_src;
  if (g.rotated_rays) {  // the target's rays come rotated (its basis holds the rotation)
    SourcePixel(d, g, x, y, z, sx, sy, ok_src, coarse_src);
  } else {
    const V rx = hn::MulAdd(hn::Set(d, r[0]), x, hn::MulAdd(hn::Set(d, r[1]), y, hn::Mul(hn::Set(d, r[2]), z)));
    const V ry = hn::MulAdd(hn::Set(d, r[3]), x, hn::MulAdd(hn::Set(d, r[4]), y, hn::Mul(hn::Set(d, r[5]), z)));
    const V rz = hn::MulAdd(hn::Set(d, r[6]), x, hn::MulAdd(hn::Set(d, r[7]), y, hn::Mul(hn::Set(d, r[8]), z)));
    SourcePixel(d, g, rx, ry, rz, sx, sy, ok_src, coarse_src);
  }
  ok = hn::And(ok_dst, ok_src);
  coarse = hn::And(ok, hn::Or(coarse_dst, coarse_src));
}

// The grid of TileRows (SimdGeometry::grid): cells of kGridCell pixels, and lagrange_cubic at
// t = i / kGridCell in float.
constexpr int64_t kGridCell = 16;
struct GridWeights {
  float w[kGridCell][4];
  HWY_ALIGN float by_node[4][kGridCell];  // the same, transposed
  constexpr GridWeights() : w{}, by_node{} {
    for (int i = 0; i < kGridCell; ++i) {
      double d[4] = {};
      lagrange_cubic(static_cast<double>(i) / kGridCell, d);
      for (int l = 0; l < 4; ++l) w[i][l] = by_node[l][i] = static_cast<float>(d[l]);
    }
  }
};
inline constexpr GridWeights kGridWeights{};

// The source positions of the rows of one tile, with per-tile tables where the geometry
// separates into a column part and a row part:
//   - equirect and cylindrical targets: rays (cos lat sin lon, -sin lat, cos lat cos lon) and
//     (sin lon, -t, cos lon); the sines and cosines of the tile's longitudes and latitudes
//     (vector, once per tile) replace the sines of every pixel;
//   - equirect and cylindrical sources seen from pinhole or cube-face targets turned only about
//     the vertical (g.separable): the ray's (x, z) depends on the column alone and y on the row
//     alone, so the source x and x^2 + z^2 come from a column table and each pixel computes the
//     latitude only (one arctangent instead of two);
//   - with the grid (SimdGeometry::grid, asked for by the caller): exact nodes every kGridCell px
//     and the checked cubic between them (BuildGrid), per-pixel geometry only in failed cells.
class TileRows {
 public:
  static constexpr int64_t kMaxTableWidth = 64;
  static constexpr int64_t kGridCells = kMaxTableWidth / kGridCell;  // per axis
  static constexpr int64_t kGridNodes = kGridCells + 3;               // a ring before, two after
  static constexpr size_t kLanesD = HWY_MAX_BYTES / sizeof(double);

  // grid: interpolate between exact nodes where the pair allows it (SimdGeometry::grid).
  TileRows(const SimdGeometry& g, const TileRect& rect, bool grid = false)
      : g_(g), x0_(rect.x0), y0_(rect.y0), n_(rect.w) {
    const bool fits = rect.w <= kMaxTableWidth && rect.h <= kMaxTableWidth;
    cylinder_ = g.dst == SimdGeometry::Dst::Cylindrical;
    table_ = (g.dst == SimdGeometry::Dst::Equirect || cylinder_) && fits;
    grid_ = grid && g.grid && fits && g.use_float;
    separable_ = g.separable && fits && !grid_;
    // Vector functions (a few ulp), every entry: rows read whole vectors past n.
    const DD dd;
    const hn::Rebind<float, DD> df;
    const auto ND = static_cast<int64_t>(hn::Lanes(dd));
    const double* p = g.pd.d;
    auto store = [&](VD v, double* to_d, float* to_f, int64_t i) {
      hn::Store(v, dd, to_d + i);
      hn::StoreU(hn::DemoteTo(df, v), df, to_f + i);
    };
    for (int64_t i = 0; table_ && i < kMaxTableWidth + kPad; i += ND) {
      const VD lon = hn::MulAdd(hn::Iota(dd, static_cast<double>(x0_ + i) + 0.5), hn::Set(dd, p[6]), hn::Set(dd, p[8]));
      store(hn::Sin(dd, lon), col_a_d_, col_a_f_, i);
      store(hn::Cos(dd, lon), col_b_d_, col_b_f_, i);
      // Rows: equirect (sin, cos) of the latitude; cylindrical (t, 1), t = tan(lat) linear in y.
      const VD v = hn::NegMulAdd(hn::Iota(dd, static_cast<double>(y0_ + i) + 0.5), hn::Set(dd, p[7]), hn::Set(dd, p[4]));
      hn::Store(cylinder_ ? v : hn::Sin(dd, v), dd, row_a_ + i);
      hn::Store(cylinder_ ? hn::Set(dd, 1.0) : hn::Cos(dd, v), dd, row_b_ + i);
    }
    for (int64_t i = 0; separable_ && i < kMaxTableWidth + kPad; i += ND) {
      // Columns: (x, z) of the rotated ray (cube face: fwd + a right; pinhole: u c0 + c2) ->
      // source x (a) and x^2 + z^2 (b), with the longitude's validity (ok_x). Rows: the ray's y.
      const VD px = hn::Iota(dd, static_cast<double>(x0_ + i) + 0.5), py = hn::Iota(dd, static_cast<double>(y0_ + i) + 0.5);
      VD x, z, y;
      if (g.dst == SimdGeometry::Dst::CubeFace) {
        const VD a = hn::MulSub(hn::Sub(px, hn::Set(dd, p[1])), hn::Set(dd, p[12]), hn::Set(dd, 1.0));
        const VD b = hn::MulSub(hn::Sub(py, hn::Set(dd, p[2])), hn::Set(dd, p[12]), hn::Set(dd, 1.0));
        x = hn::MulAdd(a, hn::Set(dd, p[6]), hn::Set(dd, p[3]));
        z = hn::MulAdd(a, hn::Set(dd, p[8]), hn::Set(dd, p[5]));
        y = hn::Mul(b, hn::Set(dd, p[10]));
      } else {
        const VD u = hn::Mul(hn::Sub(px, hn::Set(dd, p[2])), hn::Set(dd, p[0]));
        const VD v = hn::Mul(hn::Sub(py, hn::Set(dd, p[3])), hn::Set(dd, p[1]));
        x = hn::MulAdd(u, hn::Set(dd, p[4]), hn::Set(dd, p[10]));
        z = hn::MulAdd(u, hn::Set(dd, p[6]), hn::Set(dd, p[12]));
        y = hn::Mul(v, hn::Set(dd, p[8]));
      }
      VD sx;
      MD ok_x;
      LongitudeX(dd, g, x, z, sx, ok_x);
      store(sx, col_a_d_, col_a_f_, i);
      store(hn::MulAdd(x, x, hn::Mul(z, z)), col_b_d_, col_b_f_, i);
      store(hn::IfThenElseZero(ok_x, hn::Set(dd, 1.0)), col_ok_d_, col_ok_f_, i);
      hn::Store(y, dd, row_a_ + i);
    }
    if (grid_) BuildGrid(rect);
  }

  // Calls sink(sx, sy, ok, i, m) for output pixels (x0 + i .. x0 + i + m - 1, y), i from 0 to n
  // in steps of the vector: float vectors (twice the lanes) where g.use_float and every lane is
  // accurate enough, else double vectors. Lanes beyond n have ok false.
  template <class Sink>
  HWY_INLINE void Row(int64_t y, Sink&& sink) const {
    const DD dd;
    const auto ND = static_cast<int64_t>(hn::Lanes(dd));
    const bool rows = table_ || separable_;
    const double ra = rows ? row_a_[y - y0_] : 0.0, rb = table_ ? row_b_[y - y0_] : 0.0;
    auto doubles = [&](int64_t i, int64_t end) {
      const VD py = hn::Set(dd, static_cast<double>(y) + 0.5);
      for (; i < end; i += ND) {
        const int64_t m = std::min(ND, end - i);
        VD sx, sy;
        MD ok, coarse;
        Positions(dd, hn::Iota(dd, static_cast<double>(x0_ + i) + 0.5), py, i, ra, rb, sx, sy, ok, coarse);
        sink(sx, sy, hn::And(ok, hn::FirstN(dd, static_cast<size_t>(m))), i, m);
      }
    };
    if (!g_.use_float) return doubles(0, n_);
    using DF32 = hn::ScalableTag<float>;
    const DF32 df;
    const auto NF = static_cast<int64_t>(hn::Lanes(df));
    const auto py = hn::Set(df, static_cast<float>(y) + 0.5f);
    // The grid's row and cell row. (A vector lies in one cell.)
    static_assert(kGridCell % (HWY_MAX_BYTES / sizeof(float)) == 0);
    const int64_t j = y - y0_, b = j / kGridCell;
    for (int64_t i = 0; i < n_; i += NF) {
      const int64_t m = std::min(NF, n_ - i);
      hn::Vec<DF32> sx, sy;
      hn::Mask<DF32> ok, coarse;
      if (grid_ && cell_[b][i / kGridCell]) {
        GridOffsets(df, i, j, sx, sy);
        sx = hn::Add(sx, hn::Set(df, base_x_[b][i / kGridCell])), sy = hn::Add(sy, hn::Set(df, base_y_[b][i / kGridCell]));
        ok = hn::FirstN(df, static_cast<size_t>(m));
      } else {
        Positions(df, hn::Iota(df, static_cast<float>(x0_ + i) + 0.5f), py, i, static_cast<float>(ra),
                  static_cast<float>(rb), sx, sy, ok, coarse);
        ok = hn::And(ok, hn::FirstN(df, static_cast<size_t>(m)));
        if (HWY_UNLIKELY(!hn::AllFalse(df, hn::And(coarse, ok)))) {
          doubles(i, i + m);
          continue;
        }
      }
      sink(sx, sy, ok, i, m);
    }
  }

  // The grid's cells over the tile, and those interpolated (0 without the grid).
  int64_t cells() const { return cells_; }
  int64_t grid_cells() const {
    int64_t n = 0;
    for (int64_t b = 0; grid_ && b < kGridCells; ++b)
      for (int64_t a = 0; a < kGridCells; ++a) n += cell_[b][a];
    return n;
  }

 private:
  static constexpr int64_t kPad = HWY_MAX_BYTES / sizeof(float);  // a vector read past n

  // The tables in the lane type.
  template <class T>
  const T* col(const double* d, const float* f) const {
    if constexpr (std::is_same_v<T, float>) return f;
    else return d;
  }

  // Positions of the pixels from column i on, with the row's values ra, rb (see the tables).
  template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
  HWY_INLINE void Positions(D d, V px, V py, int64_t i, T ra, T rb, V& sx, V& sy, M& ok, M& coarse) const {
    const T* a = col<T>(col_a_d_, col_a_f_) + i;
    const T* b = col<T>(col_b_d_, col_b_f_) + i;
    if (separable_) {
      sx = hn::LoadU(d, a);
      LatitudeY(d, g_, hn::Set(d, ra), hn::LoadU(d, b), sy, ok, coarse);
      ok = hn::And(ok, hn::Ne(hn::LoadU(d, col<T>(col_ok_d_, col_ok_f_) + i), hn::Zero(d)));
      return;
    }
    V x, y, z;
    M ok_dst, coarse_dst;
    if (table_) {
      const V cl = hn::Set(d, rb);  // (sin, cos) of the longitude (a, b) and the latitude (ra, rb)
      x = hn::Mul(cl, hn::LoadU(d, a));
      y = hn::Set(d, -ra);
      z = hn::Mul(cl, hn::LoadU(d, b));
      ok_dst = hn::Eq(x, x);  // every equirect and cylindrical target pixel has a ray
      coarse_dst = hn::Not(ok_dst);
    } else {
      TargetRay(d, g_, px, py, x, y, z, ok_dst, coarse_dst);
      if (hn::AllFalse(d, ok_dst)) {  // outside a fisheye's circle or a map's outline: no source
        sx = sy = hn::Zero(d);
        ok = coarse = ok_dst;
        return;
      }
    }
    SourceOfRays(d, g_, x, y, z, ok_dst, coarse_dst, sx, sy, ok, coarse);
  }

  // The grid's positions of the float vector of pixels from column i on, in row j of the tile
  // (cell (j, i) / kGridCell), less the cell's base: the column node's cubic in y + the node
  // rows' offsets from it, interpolated along y. BuildGrid checks these very values.
  template <class DF32, class V = hn::Vec<DF32>>
  HWY_INLINE void GridOffsets(DF32 df, int64_t i, int64_t j, V& sx, V& sy) const {
    const int64_t a = i / kGridCell, b = j / kGridCell;
    const float* wy = kGridWeights.w[j % kGridCell];
    float cx = 0, cy = 0;
    for (int k = 0; k < 4; ++k) cx += wy[k] * col_x_[b][a][k], cy += wy[k] * col_y_[b][a][k];
    sx = hn::Set(df, cx), sy = hn::Set(df, cy);
    for (int k = 0; k < 4; ++k) {
      sx = hn::MulAdd(hn::Set(df, wy[k]), hn::LoadU(df, rel_x_[b + k] + i), sx);
      sy = hn::MulAdd(hn::Set(df, wy[k]), hn::LoadU(df, rel_y_[b + k] + i), sy);
    }
  }

  // Grid mode (SimdGeometry::grid): node (r, c) at pixel centre (x0 + (c - 1) kGridCell + 1/2,
  // y0 + (r - 1) kGridCell + 1/2); cell (b, a) spans pixels [a, a + 1) kGridCell x [b, b + 1)
  // kGridCell and interpolates nodes b..b+3 x a..a+3.
  void BuildGrid(const TileRect& rect) {
    const DD dd;
    const auto ND = static_cast<int64_t>(hn::Lanes(dd));
    const int64_t ncx = (rect.w + kGridCell - 1) / kGridCell, ncy = (rect.h + kGridCell - 1) / kGridCell;
    const int64_t nnx = ncx + 3, nny = ncy + 3;
    cells_ = ncx * ncy;
    double nx[kGridNodes][kGridNodes], ny[kGridNodes][kGridNodes];
    bool nok[kGridNodes][kGridNodes];
    HWY_ALIGN double bx[kLanesD], by[kLanesD], bo[kLanesD];
    // Exact positions (double lanes) of points (px[q], py[q]), q < n, into the three arrays.
    auto exact = [&](const double* px, const double* py, int64_t n, double* ox, double* oy, bool* ook) {
      for (int64_t q = 0; q < n; q += ND) {
        const int64_t m = std::min(ND, n - q);
        VD sx, sy;
        MD ok, coarse;
        HWY_ALIGN double qx[kLanesD] = {}, qy[kLanesD] = {};
        for (int64_t l = 0; l < m; ++l) qx[l] = px[q + l], qy[l] = py[q + l];
        Positions(dd, hn::Load(dd, qx), hn::Load(dd, qy), 0, 0.0, 0.0, sx, sy, ok, coarse);
        hn::Store(sx, dd, bx), hn::Store(sy, dd, by), hn::Store(hn::IfThenElseZero(ok, hn::Set(dd, 1.0)), dd, bo);
        for (int64_t l = 0; l < m; ++l) ox[q + l] = bx[l], oy[q + l] = by[l], ook[q + l] = bo[l] != 0.0;
      }
    };
    for (int64_t r = 0; r < nny; ++r) {
      double px[kGridNodes], py[kGridNodes];
      for (int64_t c = 0; c < nnx; ++c)
        px[c] = static_cast<double>(x0_ + (c - 1) * kGridCell) + 0.5, py[c] = static_cast<double>(y0_ + (r - 1) * kGridCell) + 0.5;
      exact(px, py, nnx, nx[r], ny[r], nok[r]);
    }
    // Cells whose 16 nodes are valid, then the centre check, then (where the centre errs by over
    // a sixteenth of the tolerance) eight more, as map_tile.
    constexpr int q4 = kGridCell / 4, h3 = 3 * kGridCell / 4, c2 = kGridCell / 2;
    constexpr int64_t kChecks[9][2] = {{c2, c2}, {q4, q4}, {h3, q4}, {q4, h3}, {h3, h3}, {c2, q4}, {q4, c2}, {h3, c2}, {c2, h3}};
    const double tol = g_.grid_tolerance;
    int64_t todo[kGridCells * kGridCells], n_todo = 0;
    for (int64_t b = 0; b < kGridCells; ++b)
      for (int64_t a = 0; a < kGridCells; ++a) {
        bool all = a < ncx && b < ncy;
        for (int k = 0; k < 16 && all; ++k) all = nok[b + k / 4][a + k % 4];
        cell_[b][a] = all;
        if (all) todo[n_todo++] = b * kGridCells + a;
      }
    // Per node row, the cubic along x less the cell's column node a + 1; per cell, an integer
    // base near its positions and that column's four nodes less it (all small: float).
    const hn::ScalableTag<float> df;
    const auto NF = static_cast<int64_t>(hn::Lanes(df));
    for (int64_t r = 0; r < nny; ++r)
      for (int64_t c = 0; c < ncx * kGridCell; c += NF) {
        const int64_t a = c / kGridCell, i = c % kGridCell;
        auto vx = hn::Zero(df), vy = hn::Zero(df);
        for (int l = 0; l < 4; ++l) {
          const auto w = hn::LoadU(df, kGridWeights.by_node[l] + i);
          vx = hn::MulAdd(w, hn::Set(df, static_cast<float>(nx[r][a + l] - nx[r][a + 1])), vx);
          vy = hn::MulAdd(w, hn::Set(df, static_cast<float>(ny[r][a + l] - ny[r][a + 1])), vy);
        }
        hn::Store(vx, df, rel_x_[r] + c), hn::Store(vy, df, rel_y_[r] + c);
      }
    for (int64_t b = 0; b < ncy; ++b)
      for (int64_t a = 0; a < ncx; ++a) {
        if (!cell_[b][a]) continue;  // (nodes not all valid)
        base_x_[b][a] = static_cast<float>(std::nearbyint(nx[b + 1][a + 1]));
        base_y_[b][a] = static_cast<float>(std::nearbyint(ny[b + 1][a + 1]));
        for (int k = 0; k < 4; ++k) {
          col_x_[b][a][k] = static_cast<float>(nx[b + k][a + 1] - static_cast<double>(base_x_[b][a]));
          col_y_[b][a][k] = static_cast<float>(ny[b + k][a + 1] - static_cast<double>(base_y_[b][a]));
        }
      }
    for (int pass = 0; pass < 2 && n_todo > 0; ++pass) {
      const int first = pass == 0 ? 0 : 1, count = pass == 0 ? 1 : 8;
      double px[kGridCells * kGridCells * 8], py[kGridCells * kGridCells * 8], ex[kGridCells * kGridCells * 8],
          ey[kGridCells * kGridCells * 8];
      bool eok[kGridCells * kGridCells * 8];
      int64_t n = 0;
      for (int64_t t = 0; t < n_todo; ++t)
        for (int k = first; k < first + count; ++k) {
          const int64_t a = todo[t] % kGridCells, b = todo[t] / kGridCells;
          px[n] = static_cast<double>(x0_ + a * kGridCell + kChecks[k][0]) + 0.5;
          py[n++] = static_cast<double>(y0_ + b * kGridCell + kChecks[k][1]) + 0.5;
        }
      exact(px, py, n, ex, ey, eok);
      int64_t next = 0;
      n = 0;
      for (int64_t t = 0; t < n_todo; ++t) {
        const int64_t a = todo[t] % kGridCells, b = todo[t] / kGridCells;
        double worst = 0;
        for (int k = first; k < first + count; ++k, ++n) {
          // The vector Row makes there (before its base), and the check point's lane of it.
          const int64_t i = a * kGridCell + kChecks[k][0], lane = i % NF;
          hn::Vec<decltype(df)> vx, vy;
          GridOffsets(df, i - lane, b * kGridCell + kChecks[k][1], vx, vy);
          HWY_ALIGN float gx[kMaxTableWidth], gy[kMaxTableWidth];
          hn::Store(vx, df, gx), hn::Store(vy, df, gy);
          // (The base added in double: Row's last rounding is in the budget, not in the check.)
          const double dx = base_x_[b][a] + static_cast<double>(gx[lane]) - ex[n];
          const double dy = base_y_[b][a] + static_cast<double>(gy[lane]) - ey[n];
          worst = std::max(worst, eok[n] ? dx * dx + dy * dy : HUGE_VAL);
        }
        cell_[b][a] = worst <= tol * tol;  // (squared distances)
        if (pass == 0 && cell_[b][a] && worst > tol * tol / 256) todo[next++] = todo[t];
      }
      n_todo = next;
    }
  }

  const SimdGeometry& g_;
  int64_t x0_, y0_, n_;
  bool table_, cylinder_, separable_, grid_;
  int64_t cells_ = 0;
  bool cell_[kGridCells][kGridCells];
  float base_x_[kGridCells][kGridCells], base_y_[kGridCells][kGridCells];
  float col_x_[kGridCells][kGridCells][4], col_y_[kGridCells][kGridCells][4];  // a cell's column nodes less its base
  HWY_ALIGN float rel_x_[kGridNodes][kMaxTableWidth], rel_y_[kGridNodes][kMaxTableWidth];
  // Per column, two values a, b (and the separable form's ok), in both lane types; per row two.
  HWY_ALIGN double col_a_d_[kMaxTableWidth + kPad], col_b_d_[kMaxTableWidth + kPad], col_ok_d_[kMaxTableWidth + kPad];
  HWY_ALIGN float col_a_f_[kMaxTableWidth + kPad], col_b_f_[kMaxTableWidth + kPad], col_ok_f_[kMaxTableWidth + kPad];
  HWY_ALIGN double row_a_[kMaxTableWidth + kPad], row_b_[kMaxTableWidth + kPad];
};

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
