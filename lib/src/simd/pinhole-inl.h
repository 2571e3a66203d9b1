// A pinhole's vector forms (lanes in pinhole.hpp), for float and double lanes.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_PINHOLE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_PINHOLE_INL_H_
#undef PANOPROJ_SIMD_PINHOLE_INL_H_
#else
#define PANOPROJ_SIMD_PINHOLE_INL_H_
#endif

#include <hwy/highway.h>

#include "simd/math-inl.h"
#include "simd/pinhole.hpp"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The rotated ray u col0 + v col1 + col2 of pixel centres (px, py); every pixel has one.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void TargetRay(D d, const simd::PinholeRays<T>& p, V px, V py, V& x, V& y, V& z, M&, M&) {
  const V u = hn::Mul(hn::Sub(px, hn::Set(d, p.cx)), hn::Set(d, p.inv_fx));
  const V v = hn::Mul(hn::Sub(py, hn::Set(d, p.cy)), hn::Set(d, p.inv_fy));
  x = hn::MulAdd(v, hn::Set(d, p.col1[0]), hn::MulAdd(u, hn::Set(d, p.col0[0]), hn::Set(d, p.col2[0])));
  y = hn::MulAdd(v, hn::Set(d, p.col1[1]), hn::MulAdd(u, hn::Set(d, p.col0[1]), hn::Set(d, p.col2[1])));
  z = hn::MulAdd(v, hn::Set(d, p.col1[2]), hn::MulAdd(u, hn::Set(d, p.col0[2]), hn::Set(d, p.col2[2])));
}

// x = cx + fx x / z, y = cy + fy y / z for z > 0, in the frame; coarse beyond max_t2.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void SourcePixel(D d, const simd::PinholeSource<T>& s, V x, V y, V z, V& sx, V& sy, M& ok, M& coarse) {
  const M pos = hn::Gt(z, hn::Zero(d));
  const V inv = hn::Div(hn::Set(d, T(1)), hn::IfThenElse(pos, z, hn::Set(d, T(1))));
  sx = hn::MulAdd(hn::Mul(x, inv), hn::Set(d, s.fx), hn::Set(d, s.cx));
  sy = hn::MulAdd(hn::Mul(y, inv), hn::Set(d, s.fy), hn::Set(d, s.cy));
  ok = hn::And(pos, InFrame(d, sx, sy, s.width, s.height));
  coarse = hn::Gt(hn::MulAdd(x, x, hn::Mul(y, y)), hn::Mul(hn::Set(d, s.max_t2), hn::Mul(z, z)));
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
