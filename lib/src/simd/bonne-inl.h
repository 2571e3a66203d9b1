// Bonne's vector forms (lanes in bonne.hpp), for float and double lanes.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_BONNE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_BONNE_INL_H_
#undef PANOPROJ_SIMD_BONNE_INL_H_
#else
#define PANOPROJ_SIMD_BONNE_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include "simd/bonne.hpp"
#include "simd/map_frame-inl.h"
#include "simd/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// bonne.hpp's inverse, with Y mirrored for a southern phi1.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void TargetRay(D d, const simd::BonneRays<T>& p, V px, V py, V& x, V& y, V& z, M& ok, M&) {
  const simd::BonneShape<T>& b = p.shape;
  const V one = hn::Set(d, T(1));
  V X, Y;
  PlanePoint(d, p.plane, px, py, X, Y);
  Y = hn::Mul(Y, hn::Set(d, b.mirror));
  const V p1 = hn::Set(d, b.abs_phi1);
  V phi, rec;  // latitude, and rho E (lambda cos phi)
  if (b.small_form) {
    const V t = hn::Set(d, b.tan_phi1);
    const V a = hn::NegMulAdd(t, Y, one);
    const V tx = hn::Mul(t, X);
    const V root = hn::Sqrt(hn::MulAdd(tx, tx, hn::Mul(a, a)));
    const V num = hn::NegMulAdd(t, hn::MulAdd(X, X, hn::Mul(Y, Y)), hn::Add(Y, Y));
    phi = hn::Add(p1, hn::Div(num, hn::Add(one, root)));
    rec = hn::Mul(root, b.tan_phi1 > T(1e-150) ? hn::Div(Atan2(d, tx, a), t) : X);
  } else {
    const V cy = hn::Sub(hn::Set(d, b.cot_phi1), Y);
    const V rho = hn::Sqrt(hn::MulAdd(X, X, hn::Mul(cy, cy)));
    phi = hn::Sub(hn::Add(hn::Set(d, b.cot_phi1), p1), rho);
    rec = hn::Mul(rho, Atan2(d, X, cy));
  }
  const V half_pi = hn::Set(d, T(0.5 * kPiF));
  ok = hn::Not(hn::Gt(hn::Abs(phi), hn::Set(d, T(0.5 * kPiF * (1.0 + kEdgeSlack)))));
  phi = hn::Min(half_pi, hn::Max(hn::Neg(half_pi), phi));
  const V cp = hn::Cos(d, phi);
  const M pole = hn::Not(hn::Gt(cp, hn::Set(d, T(1e-15))));
  const V lam = hn::IfThenElseZero(hn::Not(pole), hn::Div(rec, hn::IfThenElse(pole, one, cp)));
  ok = hn::And(ok, hn::Not(hn::Gt(hn::Abs(lam), hn::Set(d, T(kPiF * (1.0 + kEdgeSlack))))));
  const V lon = hn::Add(lam, hn::Set(d, p.plane.lon0));
  x = hn::Mul(cp, hn::Sin(d, lon));
  y = hn::Neg(hn::Mul(hn::Sin(d, phi), hn::Set(d, b.mirror)));
  z = hn::Mul(cp, hn::Cos(d, lon));
}

// bonne.hpp's forward equations on the ray's angles (MapAngles), phi mirrored for a southern
// phi1; coarse near Werner's apex.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void Forward(D d, const simd::BonneSource<T>& s, V lam, V, V, V cp, V sp, V, V& X, V& Y, M& coarse) {
  const simd::BonneShape<T>& b = s.shape;
  const V one = hn::Set(d, T(1));
  const V phi = hn::Mul(Atan2<true>(d, sp, cp), hn::Set(d, b.mirror));
  const V p1 = hn::Set(d, b.abs_phi1);
  auto sinc = [&](V e) {
    const M at0 = hn::Lt(hn::Abs(e), hn::Set(d, T(1e-30)));
    return hn::IfThenElse(at0, one, hn::Div(hn::Sin(d, e), hn::IfThenElse(at0, one, e)));
  };
  if (b.small_form) {
    const V t = hn::Set(d, b.tan_phi1);
    const V q = hn::Div(t, hn::MulAdd(t, hn::Sub(p1, phi), one));
    const V lc = hn::Mul(lam, cp), e = hn::Mul(lc, q), eh = hn::Mul(e, hn::Set(d, T(0.5)));
    X = hn::Mul(lc, sinc(e));
    Y = hn::MulAdd(lc, hn::Mul(hn::Sin(d, eh), sinc(eh)), hn::Sub(phi, p1));
  } else {
    const V rho = hn::Sub(hn::Add(hn::Set(d, b.cot_phi1), p1), phi);
    const M apex = hn::Not(hn::Gt(rho, hn::Set(d, T(1e-300))));
    const V e = hn::IfThenElse(apex, lam, hn::Div(hn::Mul(lam, cp), hn::IfThenElse(apex, one, rho)));
    X = hn::Mul(rho, hn::Sin(d, e));
    Y = hn::NegMulAdd(rho, hn::Cos(d, e), hn::Set(d, b.cot_phi1));
    coarse = hn::Lt(rho, hn::Set(d, s.coarse_rho));
  }
  Y = hn::Mul(Y, hn::Set(d, b.mirror));
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
