// The map forms' shared vector steps (lanes in map_frame.hpp), for float and double lanes.
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_MAP_FRAME_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_MAP_FRAME_INL_H_
#undef PANOPROJ_SIMD_MAP_FRAME_INL_H_
#else
#define PANOPROJ_SIMD_MAP_FRAME_INL_H_
#endif

#include <hwy/highway.h>

#include "simd/map_frame.hpp"
#include "simd/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The plane point (X, Y) of pixel centres (px, py).
template <class D, class T, class V = hn::Vec<D>>
HWY_INLINE void PlanePoint(D d, const simd::MapPlane<T>& p, V px, V py, V& X, V& Y) {
  X = hn::MulAdd(px, hn::Set(d, p.x_per_px), hn::Set(d, p.xmin));
  Y = hn::NegMulAdd(py, hn::Set(d, p.y_per_px), hn::Set(d, p.ymax));
}

// What the maps' forward equations start from: lambda relative to lon0 (wrapped), h2 = x^2 + z^2,
// n = |ray|, cos phi = |(x, z)| / n, sin phi = -y / n. Near the poles an error in lambda is
// multiplied by cos phi.
template <class D, class T, class V = hn::Vec<D>>
HWY_INLINE void MapAngles(D d, const simd::MapPixels<T>& f, V x, V y, V z, V& lam, V& h2, V& n, V& cp, V& sp) {
  lam = f.lon0 != T(0) ? WrapPi(d, hn::Sub(Atan2(d, x, z), hn::Set(d, f.lon0))) : Atan2(d, x, z);
  h2 = hn::MulAdd(x, x, hn::Mul(z, z));
  n = hn::Sqrt(hn::MulAdd(y, y, h2));
  const V inv_n = hn::Div(hn::Set(d, T(1)), n);
  cp = hn::Mul(hn::Sqrt(h2), inv_n);
  sp = hn::Neg(hn::Mul(y, inv_n));
}

// The pixel of plane point (X, Y), ok inside the closed frame.
template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void FramePixel(D d, const simd::MapPixels<T>& f, V X, V Y, V& sx, V& sy, M& ok) {
  sx = hn::Mul(hn::Sub(X, hn::Set(d, f.xmin)), hn::Set(d, f.px_per_x));
  sy = hn::Mul(hn::Sub(hn::Set(d, f.ymax), Y), hn::Set(d, f.px_per_y));
  ok = InFrame(d, sx, sy, f.width, f.height);
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
