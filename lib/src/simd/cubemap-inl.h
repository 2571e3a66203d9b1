// A cubemap's vector forms (lanes in cubemap.hpp), for float and double lanes.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_CUBEMAP_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_CUBEMAP_INL_H_
#undef PANOPROJ_SIMD_CUBEMAP_INL_H_
#else
#define PANOPROJ_SIMD_CUBEMAP_INL_H_
#endif

#include <hwy/highway.h>

#include "simd/cubemap.hpp"
#include "simd/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// A face's tangent at cell coordinate s: s, or eac's tan(pi/4 s).
template <class D, class V = hn::Vec<D>>
HWY_INLINE V CubeTangent(D d, bool angular, V s) {
  if (!angular) return s;
  const V t = hn::Mul(s, hn::Set(d, hn::TFromD<D>(0.25 * kPi)));
  return hn::Div(hn::Sin(d, t), hn::Cos(d, t));
}

// The tangents (a, b) of pixel centres (px, py) on the face.
template <class D, class T, class V = hn::Vec<D>>
HWY_INLINE void CubeFaceTangents(D d, const simd::CubeFaceRays<T>& p, V px, V py, V& a, V& b) {
  a = CubeTangent(d, p.angular, hn::MulSub(hn::Sub(px, hn::Set(d, p.ox)), hn::Set(d, p.kx), hn::Set(d, p.mx)));
  b = CubeTangent(d, p.angular, hn::MulSub(hn::Sub(py, hn::Set(d, p.oy)), hn::Set(d, p.ky), hn::Set(d, p.my)));
}

// The rotated ray fwd + a right + b down of pixel centres (px, py) on the face.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void TargetRay(D d, const simd::CubeFaceRays<T>& p, V px, V py, V& x, V& y, V& z, M&, M&) {
  V a, b;
  CubeFaceTangents(d, p, px, py, a, b);
  x = hn::MulAdd(b, hn::Set(d, p.down[0]), hn::MulAdd(a, hn::Set(d, p.right[0]), hn::Set(d, p.fwd[0])));
  y = hn::MulAdd(b, hn::Set(d, p.down[1]), hn::MulAdd(a, hn::Set(d, p.right[1]), hn::Set(d, p.fwd[1])));
  z = hn::MulAdd(b, hn::Set(d, p.down[2]), hn::MulAdd(a, hn::Set(d, p.right[2]), hn::Set(d, p.fwd[2])));
}

// The face of the largest component (ties: x, then y, then z, as cube_face_of).
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void SourcePixel(D d, const simd::CubemapSource<T>& s, V x, V y, V z, V& sx, V& sy, M& ok, M& coarse) {
  const V zero = hn::Zero(d);
  coarse = hn::Lt(zero, zero);  // none
  const V ax = hn::Abs(x), ay = hn::Abs(y), az = hn::Abs(z);
  const M xf = hn::And(hn::Not(hn::Lt(ax, ay)), hn::Not(hn::Lt(ax, az)));
  const M yf = hn::AndNot(xf, hn::Not(hn::Lt(ay, az)));
  // Per face (0 front, 1 right, 2 back, 3 left, 4 up, 5 down): depth, numerators of a and b.
  const M xp = hn::Gt(x, zero), yp = hn::Gt(y, zero), zp = hn::Gt(z, zero);
  const V depth = hn::IfThenElse(xf, ax, hn::IfThenElse(yf, ay, az));
  const V an = hn::IfThenElse(xf, hn::IfThenElse(xp, hn::Neg(z), z), hn::IfThenElse(yf, x, hn::IfThenElse(zp, x, hn::Neg(x))));
  const V bn = hn::IfThenElse(xf, y, hn::IfThenElse(yf, hn::IfThenElse(yp, hn::Neg(z), z), y));
  // The face's origin chosen by the same masks.
  auto origin = [&](const T* o) {
    return hn::IfThenElse(xf, hn::IfThenElse(xp, hn::Set(d, o[1]), hn::Set(d, o[3])),
                          hn::IfThenElse(yf, hn::IfThenElse(yp, hn::Set(d, o[5]), hn::Set(d, o[4])),
                                         hn::IfThenElse(zp, hn::Set(d, o[0]), hn::Set(d, o[2]))));
  };
  V a, b;
  if (s.angular) {  // 4/pi atan(an / depth)
    const V k = hn::Set(d, T(4 / kPi));
    a = hn::Mul(Atan2<true>(d, an, depth), k), b = hn::Mul(Atan2<true>(d, bn, depth), k);
  } else {
    const V inv = hn::Div(hn::Set(d, T(1)), depth);
    a = hn::Mul(an, inv), b = hn::Mul(bn, inv);
  }
  const V ox = origin(s.ox), oy = origin(s.oy);
  // Within the face's cell [o, o + F): the far edge becomes the largest value below o + F in the
  // lane type.
  const hn::RebindToSigned<D> di;
  auto below = [&](V v) { return hn::BitCast(d, hn::Sub(hn::BitCast(di, v), hn::Set(di, 1))); };
  ok = hn::Gt(depth, zero);
  if (s.plain) {
    const V half_f = hn::Set(d, s.half_face), f = hn::Set(d, s.face);
    sx = hn::Min(hn::Add(ox, hn::Max(hn::MulAdd(a, half_f, half_f), zero)), below(hn::Add(ox, f)));
    sy = hn::Min(hn::Add(oy, hn::Max(hn::MulAdd(b, half_f, half_f), zero)), below(hn::Add(oy, f)));
    return;
  }
  // Turned or padded cells: the cell's position from (a, b) by its face's coefficients.
  const V cx = hn::MulAdd(b, origin(s.kx[2]), hn::MulAdd(a, origin(s.kx[1]), origin(s.kx[0])));
  const V cy = hn::MulAdd(b, origin(s.ky[2]), hn::MulAdd(a, origin(s.ky[1]), origin(s.ky[0])));
  sx = hn::Min(hn::Max(cx, ox), below(origin(s.x1)));
  sy = hn::Min(hn::Max(cy, oy), below(origin(s.y1)));
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
