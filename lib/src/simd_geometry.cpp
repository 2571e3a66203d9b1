// Highway kernels for simd_geometry.hpp. Rays are not normalized: both sources' to_pixel are
// scale-invariant (atan2; ratios to the depth).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "simd_geometry.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// Order matters: foreach_target re-includes this file once per target.
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cmath>

#include "simd_geometry.hpp"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<double>;
using VF = hn::Vec<DF>;
using MF = hn::Mask<DF>;

constexpr double kPiF = 3.14159265358979323846;

// atan2(y, x) from Atan and a quadrant fix-up (Highway 1.0.3 has no Atan2); 0 where x = y = 0.
HWY_INLINE VF Atan2(DF df, VF y, VF x) {
  const VF zero = hn::Zero(df);
  const VF ax = hn::Abs(x), ay = hn::Abs(y);
  // atan of the smaller over the larger ratio stays in [-1, 1] (accurate), then reflect.
  const MF swap = hn::Lt(ax, ay);
  const VF num = hn::IfThenElse(swap, ax, ay), den = hn::IfThenElse(swap, ay, ax);
  const MF both_zero = hn::Eq(den, zero);
  VF a = hn::Atan(df, hn::Div(num, hn::IfThenElse(both_zero, hn::Set(df, 1.0), den)));  // [0, pi/4]
  a = hn::IfThenElse(swap, hn::Sub(hn::Set(df, 0.5 * kPiF), a), a);                     // [0, pi/2]
  a = hn::IfThenElse(hn::Lt(x, zero), hn::Sub(hn::Set(df, kPiF), a), a);                 // [0, pi]
  a = hn::IfThenElse(hn::Lt(y, zero), hn::Neg(a), a);
  return hn::IfThenElse(both_zero, zero, a);
}

// The rays of pixel centres (px, py) for the target.
HWY_INLINE void TargetRay(DF df, const SimdGeometry& g, VF px, VF py, VF& x, VF& y, VF& z, MF& ok) {
  const double* d = g.d;
  ok = hn::Eq(px, px);  // all true
  x = y = z = hn::Zero(df);
  switch (g.dst) {
    case SimdGeometry::Dst::Pinhole:
      x = hn::Div(hn::Sub(px, hn::Set(df, d[2])), hn::Set(df, d[0]));
      y = hn::Div(hn::Sub(py, hn::Set(df, d[3])), hn::Set(df, d[1]));
      z = hn::Set(df, 1.0);
      return;
    case SimdGeometry::Dst::Equirect: {
      const VF lon = hn::MulAdd(hn::Sub(hn::Div(px, hn::Set(df, d[0])), hn::Set(df, 0.5)), hn::Set(df, d[1]), hn::Set(df, d[2]));
      const VF lat = hn::Sub(hn::Set(df, d[4]), hn::Mul(hn::Div(py, hn::Set(df, d[3])), hn::Set(df, d[5])));
      const VF cl = hn::Cos(df, lat);
      x = hn::Mul(cl, hn::Sin(df, lon));
      y = hn::Neg(hn::Sin(df, lat));
      z = hn::Mul(cl, hn::Cos(df, lon));
      return;
    }
    case SimdGeometry::Dst::CubeFace: {
      const VF a = hn::Sub(hn::Div(hn::Mul(hn::Set(df, 2.0), hn::Sub(px, hn::Set(df, d[1]))), hn::Set(df, d[0])), hn::Set(df, 1.0));
      const VF b = hn::Sub(hn::Div(hn::Mul(hn::Set(df, 2.0), hn::Sub(py, hn::Set(df, d[2]))), hn::Set(df, d[0])), hn::Set(df, 1.0));
      x = hn::MulAdd(b, hn::Set(df, d[9]), hn::MulAdd(a, hn::Set(df, d[6]), hn::Set(df, d[3])));
      y = hn::MulAdd(b, hn::Set(df, d[10]), hn::MulAdd(a, hn::Set(df, d[7]), hn::Set(df, d[4])));
      z = hn::MulAdd(b, hn::Set(df, d[11]), hn::MulAdd(a, hn::Set(df, d[8]), hn::Set(df, d[5])));
      return;
    }
    case SimdGeometry::Dst::Fisheye: {
      const VF u = hn::Div(hn::Sub(px, hn::Set(df, d[0])), hn::Set(df, d[2]));
      const VF v = hn::Div(hn::Sub(py, hn::Set(df, d[1])), hn::Set(df, d[3]));
      const VF r = hn::Sqrt(hn::MulAdd(u, u, hn::Mul(v, v)));
      ok = hn::Not(hn::Gt(r, hn::Set(df, 1.0 + 1e-9)));
      const VF gv = hn::Mul(hn::Min(r, hn::Set(df, 1.0)), hn::Set(df, d[4]));
      VF psi;
      switch (g.law) {
        case 1: psi = hn::Mul(hn::Set(df, 2.0), hn::Asin(df, hn::Min(hn::Mul(gv, hn::Set(df, 0.5)), hn::Set(df, 1.0)))); break;
        case 2: psi = hn::Asin(df, hn::Min(gv, hn::Set(df, 1.0))); break;
        case 3: psi = hn::Mul(hn::Set(df, 2.0), hn::Atan(df, hn::Mul(gv, hn::Set(df, 0.5)))); break;
        default: psi = gv; break;
      }
      // (sin psi u / r, sin psi v / r, cos psi); at r = 0 the direction is the axis.
      const VF k = hn::Div(hn::Sin(df, psi), hn::Max(r, hn::Set(df, 1e-300)));
      x = hn::Mul(k, u);
      y = hn::Mul(k, v);
      z = hn::Cos(df, psi);
      return;
    }
  }
}

// Source pixel of ray (x, y, z).
HWY_INLINE void SourcePixel(DF df, const SimdGeometry& g, VF x, VF y, VF z, VF& sx, VF& sy, MF& ok) {
  const double* s = g.s;
  if (g.src == SimdGeometry::Src::Equirect) {
    VF lon = hn::Sub(Atan2(df, x, z), hn::Set(df, s[2]));
    lon = hn::IfThenElse(hn::Not(hn::Lt(lon, hn::Set(df, kPiF))), hn::Sub(lon, hn::Set(df, 2 * kPiF)), lon);
    lon = hn::IfThenElse(hn::Lt(lon, hn::Set(df, -kPiF)), hn::Add(lon, hn::Set(df, 2 * kPiF)), lon);
    sx = hn::Mul(hn::Add(hn::Div(lon, hn::Set(df, s[1])), hn::Set(df, 0.5)), hn::Set(df, s[0]));
    const VF lat = Atan2(df, hn::Neg(y), hn::Sqrt(hn::MulAdd(x, x, hn::Mul(z, z))));
    sy = hn::Mul(hn::Div(hn::Sub(hn::Set(df, s[4]), lat), hn::Set(df, s[5])), hn::Set(df, s[3]));
    const VF slack = hn::Set(df, 1e-9 * s[3]);
    ok = hn::And(hn::Not(hn::Lt(sy, hn::Neg(slack))), hn::Not(hn::Gt(sy, hn::Add(hn::Set(df, s[3]), slack))));
    // Keep x in [0, W) (the seam's far side is 0).
    sx = hn::IfThenElse(hn::Not(hn::Lt(sx, hn::Set(df, s[0]))), hn::Sub(sx, hn::Set(df, s[0])), sx);
    sx = hn::Max(sx, hn::Zero(df));
    return;
  }
  // Cubemap: the face of the largest component (ties: x, then y, then z, as cube_face_of).
  const VF ax = hn::Abs(x), ay = hn::Abs(y), az = hn::Abs(z);
  const MF xf = hn::And(hn::Not(hn::Lt(ax, ay)), hn::Not(hn::Lt(ax, az)));
  const MF yf = hn::AndNot(xf, hn::Not(hn::Lt(ay, az)));
  const VF zero = hn::Zero(df);
  // Per face: depth, numerators of a and b, face index (0 front, 1 right, 2 back, 3 left, 4 up, 5 down).
  const MF xp = hn::Gt(x, zero), yp = hn::Gt(y, zero), zp = hn::Gt(z, zero);
  VF depth = hn::IfThenElse(xf, ax, hn::IfThenElse(yf, ay, az));
  VF an = hn::IfThenElse(xf, hn::IfThenElse(xp, hn::Neg(z), z), hn::IfThenElse(yf, x, hn::IfThenElse(zp, x, hn::Neg(x))));
  VF bn = hn::IfThenElse(xf, y, hn::IfThenElse(yf, hn::IfThenElse(yp, hn::Neg(z), z), y));
  VF face = hn::IfThenElse(xf, hn::IfThenElse(xp, hn::Set(df, 1.0), hn::Set(df, 3.0)),
                           hn::IfThenElse(yf, hn::IfThenElse(yp, hn::Set(df, 5.0), hn::Set(df, 4.0)),
                                          hn::IfThenElse(zp, hn::Set(df, 0.0), hn::Set(df, 2.0))));
  const VF a = hn::Div(an, depth), b = hn::Div(bn, depth);
  VF ox = hn::Set(df, s[1]), oy = hn::Set(df, s[7]);
  for (int f = 1; f < 6; ++f) {
    const MF is = hn::Eq(face, hn::Set(df, static_cast<double>(f)));
    ox = hn::IfThenElse(is, hn::Set(df, s[1 + f]), ox);
    oy = hn::IfThenElse(is, hn::Set(df, s[7 + f]), oy);
  }
  const VF half_f = hn::Set(df, 0.5 * s[0]), hi = hn::Set(df, s[0] * (1.0 - 1e-12));
  sx = hn::Add(ox, hn::Min(hn::Max(hn::Mul(hn::Add(a, hn::Set(df, 1.0)), half_f), zero), hi));
  sy = hn::Add(oy, hn::Min(hn::Max(hn::Mul(hn::Add(b, hn::Set(df, 1.0)), half_f), zero), hi));
  ok = hn::Gt(depth, zero);
}

void MapTile(const SimdGeometry& g, const TileRect& rect, TileMap& out) {
  const DF df;
  const size_t N = hn::Lanes(df);
  HWY_ALIGN double bx[64], by[64], bo[64];
  const double* r = g.r;
  for (int64_t j = 0; j < rect.h; ++j) {
    const VF py = hn::Set(df, static_cast<double>(rect.y0 + j) + 0.5);
    for (int64_t i = 0; i < rect.w; i += static_cast<int64_t>(N)) {
      const VF px = hn::Add(hn::Iota(df, static_cast<double>(rect.x0 + i) + 0.5), hn::Zero(df));
      VF x, y, z, sx, sy;
      MF ok_dst, ok_src;
      TargetRay(df, g, px, py, x, y, z, ok_dst);
      const VF rx = hn::MulAdd(hn::Set(df, r[0]), x, hn::MulAdd(hn::Set(df, r[1]), y, hn::Mul(hn::Set(df, r[2]), z)));
      const VF ry = hn::MulAdd(hn::Set(df, r[3]), x, hn::MulAdd(hn::Set(df, r[4]), y, hn::Mul(hn::Set(df, r[5]), z)));
      const VF rz = hn::MulAdd(hn::Set(df, r[6]), x, hn::MulAdd(hn::Set(df, r[7]), y, hn::Mul(hn::Set(df, r[8]), z)));
      SourcePixel(df, g, rx, ry, rz, sx, sy, ok_src);
      hn::Store(sx, df, bx);
      hn::Store(sy, df, by);
      hn::Store(hn::IfThenElseZero(hn::And(ok_dst, ok_src), hn::Set(df, 1.0)), df, bo);
      const int64_t m = std::min<int64_t>(static_cast<int64_t>(N), rect.w - i);
      for (int64_t l = 0; l < m; ++l) {
        const size_t k = static_cast<size_t>(j * rect.w + i + l);
        out.xs[k] = bx[l];
        out.ys[k] = by[l];
        out.ok[k] = bo[l] != 0.0;
      }
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace panoproj {
HWY_EXPORT(MapTile);

bool simd_geometry_for(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation,
                       const TileRect& rect, SimdGeometry& g) {
  for (int i = 0; i < 9; ++i) g.r[i] = static_cast<double>(rotation(i / 3, i % 3));
  // W, hfov, lon0, H, lat_top, vfov: the same layout on both sides.
  auto equirect = [](const Equirect& e, double* out) {
    const double v[6] = {static_cast<double>(e.size().width), e.axis().hfov, e.axis().lon0,
                         static_cast<double>(e.size().height), e.lat_top(), e.vfov()};
    std::copy(v, v + 6, out);
  };
  if (const auto* e = std::get_if<Equirect>(&src)) {
    if (!e->full_longitude()) return false;
    g.src = SimdGeometry::Src::Equirect;
    equirect(*e, g.s);
  } else if (const auto* c = std::get_if<Cubemap>(&src)) {
    g.src = SimdGeometry::Src::Cubemap;
    g.s[0] = static_cast<double>(c->face_size());
    for (int f = 0; f < 6; ++f) {
      g.s[1 + f] = static_cast<double>(c->face_origin(f)[0]);
      g.s[7 + f] = static_cast<double>(c->face_origin(f)[1]);
    }
  } else {
    return false;
  }
  if (const auto* p = std::get_if<Pinhole>(&dst)) {
    g.dst = SimdGeometry::Dst::Pinhole;
    const double v[4] = {static_cast<double>(p->fx()), static_cast<double>(p->fy()), static_cast<double>(p->cx()),
                        static_cast<double>(p->cy())};
    std::copy(v, v + 4, g.d);
  } else if (const auto* e = std::get_if<Equirect>(&dst)) {
    g.dst = SimdGeometry::Dst::Equirect;
    equirect(*e, g.d);
  } else if (const auto* c = std::get_if<Cubemap>(&dst)) {
    // The whole tile inside one face's cell.
    const int f = c->face_at(static_cast<double>(rect.x0) + 0.5, static_cast<double>(rect.y0) + 0.5);
    if (f < 0) return false;
    const auto o = c->face_origin(f);
    if (rect.x0 + rect.w > o[0] + c->face_size() || rect.y0 + rect.h > o[1] + c->face_size()) return false;
    g.dst = SimdGeometry::Dst::CubeFace;
    const CubeFace& cf = cube_faces()[f];
    const double v[12] = {static_cast<double>(c->face_size()), static_cast<double>(o[0]), static_cast<double>(o[1]),
                         static_cast<double>(cf.fwd.x()), static_cast<double>(cf.fwd.y()), static_cast<double>(cf.fwd.z()),
                         static_cast<double>(cf.right.x()), static_cast<double>(cf.right.y()), static_cast<double>(cf.right.z()),
                         static_cast<double>(cf.down.x()), static_cast<double>(cf.down.y()), static_cast<double>(cf.down.z())};
    std::copy(v, v + 12, g.d);
  } else if (const auto* fe = std::get_if<Fisheye>(&dst)) {
    if (!fe->clip()) return false;
    g.dst = SimdGeometry::Dst::Fisheye;
    const double v[5] = {static_cast<double>(fe->cx()), static_cast<double>(fe->cy()), static_cast<double>(fe->rx()),
                        static_cast<double>(fe->ry()), static_cast<double>(fe->g_max())};
    std::copy(v, v + 5, g.d);
    g.law = static_cast<int>(fe->model());
  } else {
    return false;
  }
  return true;
}

void simd_map_tile(const SimdGeometry& g, const TileRect& rect, TileMap& out) {
  const auto n = static_cast<size_t>(rect.w * rect.h);
  out.rect = rect;
  out.xs.resize(n);
  out.ys.resize(n);
  out.ok.resize(n);
  out.exact_cells = out.interpolated_cells = 0;
  HWY_DYNAMIC_DISPATCH(MapTile)(g, rect, out);
}

}  // namespace panoproj
#endif
