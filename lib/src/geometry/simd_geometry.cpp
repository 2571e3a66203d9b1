// Tile maps from the vector geometry of simd_geometry-inl.h (Highway, runtime dispatch), and the
// choice of pairs and parameters.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "geometry/simd_geometry.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// Order matters: foreach_target re-includes this file once per target.
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "geometry/simd_geometry-inl.h"
#include "geometry/simd_geometry.hpp"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The positions the fused converter computes (TileRows), stored in double.
void MapTile(const SimdGeometry& g, const TileRect& rect, bool grid, TileMap& out) {
  const TileRows rows(g, rect, grid);
  out.interpolated_cells = rows.grid_cells();
  out.exact_cells = grid && g.grid ? rows.cells() - out.interpolated_cells : 0;
  for (int64_t j = 0; j < rect.h; ++j) {
    const size_t row = static_cast<size_t>(j * rect.w);
    rows.Row(rect.y0 + j, [&](auto sx, auto sy, auto ok, int64_t i, int64_t m) {
      using D = hn::DFromV<decltype(sx)>;
      using T = hn::TFromD<D>;
      const D d;
      HWY_ALIGN T bx[hn::MaxLanes(D())], by[hn::MaxLanes(D())], bo[hn::MaxLanes(D())];
      hn::Store(sx, d, bx);
      hn::Store(sy, d, by);
      hn::Store(hn::IfThenElseZero(ok, hn::Set(d, T(1))), d, bo);
      for (int64_t l = 0; l < m; ++l) {
        const size_t k = row + static_cast<size_t>(i + l);
        out.xs[k] = bx[l];
        out.ys[k] = by[l];
        out.ok[k] = bo[l] != T(0);
      }
    });
  }
}

// Lane-wise running minima and maxima of valid positions, reduced across lanes once.
template <class D>
struct Extent {
  using V = hn::Vec<D>;
  using T = hn::TFromD<D>;
  V lo_x, lo_y, hi_x, hi_y;
  Extent() {
    lo_x = lo_y = hn::Set(D(), std::numeric_limits<T>::max());
    hi_x = hi_y = hn::Neg(lo_x);
  }
  void add(V sx, V sy, hn::Mask<D> ok) {
    lo_x = hn::Min(lo_x, hn::IfThenElse(ok, sx, lo_x)), lo_y = hn::Min(lo_y, hn::IfThenElse(ok, sy, lo_y));
    hi_x = hn::Max(hi_x, hn::IfThenElse(ok, sx, hi_x)), hi_y = hn::Max(hi_y, hn::IfThenElse(ok, sy, hi_y));
  }
  void widen(double* box) const {  // (no valid lane: the limits, which do not widen it)
    const D d;
    box[0] = std::min(box[0], static_cast<double>(hn::GetLane(hn::MinOfLanes(d, lo_x))));
    box[1] = std::min(box[1], static_cast<double>(hn::GetLane(hn::MinOfLanes(d, lo_y))));
    box[2] = std::max(box[2], static_cast<double>(hn::GetLane(hn::MaxOfLanes(d, hi_x))));
    box[3] = std::max(box[3], static_cast<double>(hn::GetLane(hn::MaxOfLanes(d, hi_y))));
  }
};

// Widens box (x0, y0, x1, y1) to the valid source positions of rect's pixels: the same
// positions as MapTile, reduced in registers instead of stored.
void TileBounds(const SimdGeometry& g, const TileRect& rect, double* box) {
  const TileRows rows(g, rect);
  Extent<hn::ScalableTag<float>> ef;
  Extent<DD> ed;
  for (int64_t j = 0; j < rect.h; ++j)
    rows.Row(rect.y0 + j, [&](auto sx, auto sy, auto ok, int64_t, int64_t) {
      if constexpr (std::is_same_v<hn::TFromV<decltype(sx)>, float>) ef.add(sx, sy, ok);
      else ed.add(sx, sy, ok);
    });
  ef.widen(box);
  ed.widen(box);
}

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace panoproj {
HWY_EXPORT(MapTile);
HWY_EXPORT(TileBounds);

namespace {
// Largest absolute error of a float unit ray after the target's projection and the rotation
// (measured at <= 2.4e-7 over the pairs of tests/simd_geometry_test.cpp; with margin).
constexpr double kFloatRayError = 2.5e-7;
constexpr double kHalfUlp = 0x1p-24;  // relative rounding of a float
}  // namespace

bool simd_geometry_for(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation,
                       const TileRect& rect, SimdGeometry& g) {
  // A dual fisheye's lens alone is a fisheye turned by R_k (lens ray = R_k^T camera ray); a tile
  // inside one half of a dual-fisheye target, that half's lens (camera ray = R_k lens ray).
  if (const auto* d = std::get_if<DualFisheye>(&src)) {
    const int k = d->only();
    return k >= 0 && simd_geometry_for(Projection(d->lens(k)), dst, d->rotation(k).transpose() * rotation, rect, g);
  }
  if (const auto* d = std::get_if<DualFisheye>(&dst)) {
    const int k = d->lens_at(static_cast<double>(rect.x0) + 0.5, static_cast<double>(rect.y0) + 0.5);
    if (d->lens_at(static_cast<double>(rect.x0 + rect.w) - 0.5, static_cast<double>(rect.y0 + rect.h) - 0.5) != k) return false;
    return simd_geometry_for(src, Projection(d->lens(k)), rotation * d->rotation(k), rect, g);
  }
  double* gd = g.pd.d;
  double* gs = g.pd.s;
  std::fill(gd, gd + 16, 0.0);  // unused parameters are 0
  std::fill(gs, gs + 16, 0.0);
  for (int i = 0; i < 9; ++i) g.pd.r[i] = static_cast<double>(rotation(i / 3, i % 3));
  g.rotated_rays = rotation == Eigen::Matrix3d::Identity();  // nothing to turn
  // Float lanes: the tolerance holds per axis for the rounding of the position itself plus the
  // ray's error carried through the source projection.
  const double tol = SimdGeometry::kFloatTolerance;
  // Longitude-axis sources, equirect and cylindrical: [0] W, [1] hfov, [2] lon0, [3] H, [4] the
  // top row's latitude (equirect) or height t = tan(lat) (cylindrical), [6] W / hfov, [7] H per
  // unit of latitude or height (cylindrical: negative, t falls downwards), [8] W / 2, [9] cos^2 of
  // the latitude beyond which float lanes are too coarse, [10] 1 for a full circle, [11] the half
  // span with Fisheye's edge slack (multiplications in the kernels, not divisions).
  auto longitude_source = [&](const LongitudeAxis& axis, Size size, double top, double per_unit, double y_gain) {
    const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
    const double v[12] = {w, axis.hfov, axis.lon0, h, top, 0.0, w / axis.hfov, per_unit, 0.5 * w, 0.0,
                          axis.full ? 1.0 : 0.0, 0.5 * axis.hfov * (1.0 + kEdgeSlack)};
    std::copy(v, v + 12, gs);
    // x: longitude error (W / hfov) eps / cos(lat); y: (H per unit) eps / cos^y_gain(lat).
    const double room = tol - w * kHalfUlp, room_y = tol - h * kHalfUlp;
    const double y_error = std::fabs(per_unit) * kFloatRayError;
    g.use_float = room > 0 && room_y > 0 && (y_gain > 0 || y_error <= room_y);
    const double cos_x = gs[6] * kFloatRayError / std::max(room, 1e-300);
    const double cos_y = y_gain > 0 ? std::pow(y_error / std::max(room_y, 1e-300), 1.0 / y_gain) : 0.0;
    const double cos_min = g.use_float ? std::min(1.0, std::max(cos_x, cos_y)) : 1.0;
    gs[9] = cos_min * cos_min;
  };
  if (const auto* e = std::get_if<Equirect>(&src)) {
    g.src = SimdGeometry::Src::Equirect;
    longitude_source(e->axis(), e->size(), e->lat_top(), static_cast<double>(e->size().height) / e->vfov(), 0.0);
    gs[12] = e->vfov() == kPi && e->lat_top() == kHalfPi ? 1.0 : 0.0;  // a full sphere
    // A latitude band whose lanes all need double is no use for float (the check above is per lane).
    g.use_float = g.use_float && gs[9] < 1.0;
  } else if (const auto* cy = std::get_if<Cylindrical>(&src)) {
    g.src = SimdGeometry::Src::Cylindrical;
    // dt / dlat = 1 / cos^2(lat).
    longitude_source(cy->axis(), cy->size(), cy->t_top(),
                     static_cast<double>(cy->size().height) / (cy->t_bottom() - cy->t_top()), 2.0);
    g.use_float = g.use_float && gs[9] < 1.0;
  } else if (const auto* hm = std::get_if<Hammer>(&src)) {
    // [0] W, [1] w, [2] lon0, [3] H, [4] xmin, [5] W / (xmax - xmin), [6] ymax,
    // [7] H / (ymax - ymin), [8] 1 / w.
    g.src = SimdGeometry::Src::Hammer;
    const MapFrame& f = hm->frame();
    const double w = static_cast<double>(f.size.width), h = static_cast<double>(f.size.height);
    const double v[9] = {w, hm->w(), hm->lon0(), h, f.xmin, w / (f.xmax - f.xmin), f.ymax, h / (f.ymax - f.ymin),
                         1.0 / hm->w()};
    std::copy(v, v + 9, gs);
    // The plane position's error is the ray's (unit scale at the centre, less elsewhere) times the
    // pixels per plane unit; plus rounding.
    g.use_float = std::max(w, h) * kHalfUlp + std::max(gs[5], gs[7]) * 2 * kFloatRayError <= tol;
  } else if (std::holds_alternative<Aitoff>(src) || std::holds_alternative<Bonne>(src)) {
    // [0] W, [2] lon0, [3] H, [4] xmin, [5] W / (xmax - xmin), [6] ymax, [7] H / (ymax - ymin);
    // Aitoff: [8] the 1 - h below which float lanes are coarse; Bonne: [8] |phi1|, [9] the
    // mirror sign, [10] tan, [11] cot, [12] 1 for the small form, [13] the rho below which
    // float lanes are coarse.
    const auto* ai = std::get_if<Aitoff>(&src);
    const auto* bo = std::get_if<Bonne>(&src);
    g.src = ai ? SimdGeometry::Src::Aitoff : SimdGeometry::Src::Bonne;
    const MapFrame& f = ai ? ai->frame() : bo->frame();
    const double w = static_cast<double>(f.size.width), h = static_cast<double>(f.size.height);
    const double v[8] = {w, 0.0, ai ? ai->lon0() : bo->lon0(), h, f.xmin, w / (f.xmax - f.xmin), f.ymax,
                         h / (f.ymax - f.ymin)};
    std::copy(v, v + 8, gs);
    // The plane position's error: the ray's through plane scales of a few units (measured in
    // tests/simd_geometry_test.cpp), plus rounding.
    const double density = std::max(gs[5], gs[7]);
    const double room = tol - std::max(w, h) * kHalfUlp - density * 4 * kFloatRayError;
    g.use_float = room > 0;
    if (ai) {
      // X and Y scale with g ~ 1 / sqrt(1 - h): their error with eps / (1 - h).
      gs[8] = density * 4 * kFloatRayError / std::max(room, 1e-300);
    } else {
      const double v2[6] = {bo->abs_phi1(), bo->mirror(), bo->tan_phi1(), bo->cot_phi1(), bo->small_form() ? 1.0 : 0.0,
                            0.1};  // rho < 0.1: E = lambda cos phi / rho loses digits near the apex
      std::copy(v2, v2 + 6, gs + 8);
    }
  } else if (const auto* ph = std::get_if<Pinhole>(&src)) {
    // [0] W, [1] fx, [2] fy, [3] H, [4] cx, [5] cy, [9] the largest (x^2 + y^2) / z^2 for float
    // lanes: the error f eps (1 + t^2) plus rounding within the tolerance.
    g.src = SimdGeometry::Src::Pinhole;
    const double w = static_cast<double>(ph->size().width), h = static_cast<double>(ph->size().height);
    const double f = std::max(ph->fx(), ph->fy());
    const double t2 = (tol - std::max(w, h) * kHalfUlp) / (f * kFloatRayError) - 1.0;
    const double v[10] = {w, ph->fx(), ph->fy(), h, ph->cx(), ph->cy(), 0.0, 0.0, 0.0, std::max(t2, 0.0)};
    std::copy(v, v + 10, gs);
    g.use_float = t2 > 1.0;  // at least out to 45 degrees
  } else if (const auto* fs = std::get_if<Fisheye>(&src)) {
    // [0] W, [1] cx, [2] cy, [3] H, [4] rx / g, [5] ry / g, [6] psi_max with slack if clipped
    // (else unbounded), [7] the law's limit with slack, [10] the law, [11] (n + z) / n and [12]
    // s / n below which float lanes are coarse.
    g.src = SimdGeometry::Src::Fisheye;
    const double w = static_cast<double>(fs->size().width), h = static_cast<double>(fs->size().height);
    const double v[12] = {w, static_cast<double>(fs->cx()), static_cast<double>(fs->cy()), h, fs->rx() / fs->g_max(),
                          fs->ry() / fs->g_max(), fs->clip() ? fs->psi_max() * (1.0 + kEdgeSlack) : 1e300,
                          fs->psi_limit() * (1.0 + kEdgeSlack), 0.0, 0.0, static_cast<double>(static_cast<int>(fs->model())),
                          0.0};
    std::copy(v, v + 12, gs);
    // Float lanes: pixels per radian (r / g) law'(psi) is rx / g at the centre; towards psi = pi
    // the error grows where a small quantity carries the result, so those lanes are coarse:
    //   equidistant: the azimuth (x, y) / s, error (rx/g) pi eps / sin(psi) -> [12] on s / n;
    //   equisolid: n + z, relative error eps / q with q = (n + z) / n: (rx/g) eps / q -> [11];
    //   stereographic: (rx/g) 2 sqrt(2) eps / q^1.5 -> [11]; orthographic stays below 90 deg.
    const double scale = std::max(fs->rx(), fs->ry()) / fs->g_max();
    const double room = tol - std::max(w, h) * kHalfUlp - scale * kFloatRayError;
    g.use_float = room > 0;
    const double e = scale * kFloatRayError / std::max(room, 1e-300);
    switch (fs->model()) {
      case FisheyeModel::Equidistant: gs[12] = kPi * e; break;
      case FisheyeModel::Equisolid: gs[11] = e; break;
      case FisheyeModel::Stereographic: gs[11] = std::pow(2.0 * std::sqrt(2.0) * e, 2.0 / 3.0); break;
      case FisheyeModel::Orthographic: break;
    }
  } else if (const auto* c = std::get_if<Cubemap>(&src)) {
    g.src = SimdGeometry::Src::Cubemap;
    const double f = static_cast<double>(c->face_size());
    gs[0] = f;
    for (int i = 0; i < 6; ++i) {
      gs[1 + i] = static_cast<double>(c->face_origin(i)[0]);
      gs[7 + i] = static_cast<double>(c->face_origin(i)[1]);
    }
    gs[14] = 0.5 * f;
    // a = an / depth, both with the ray's error (depth >= |ray| / sqrt(3)).
    const Size frame = c->size();
    g.use_float = static_cast<double>(std::max(frame.width, frame.height)) * kHalfUlp +
                      0.5 * f * 2 * std::sqrt(3.0) * kFloatRayError <= tol;
  } else {
    return false;
  }
  if (const auto* p = std::get_if<Pinhole>(&dst)) {
    // [0] 1 / fx, [1] 1 / fy, [2] cx, [3] cy, [4..12] the rotation's columns (rays come rotated).
    g.dst = SimdGeometry::Dst::Pinhole;
    const double v[4] = {1.0 / static_cast<double>(p->fx()), 1.0 / static_cast<double>(p->fy()), static_cast<double>(p->cx()),
                        static_cast<double>(p->cy())};
    std::copy(v, v + 4, gd);
    for (int i = 0; i < 9; ++i) gd[4 + i] = static_cast<double>(rotation(i % 3, i / 3));
    g.rotated_rays = true;
  } else if (std::holds_alternative<Equirect>(dst) || std::holds_alternative<Cylindrical>(dst)) {
    // [0] W, [1] hfov, [2] lon0, [3] H, [4] the top row's latitude (equirect) or height t
    // (cylindrical), [6] hfov / W, [7] the fall of latitude or t per row, [8] lon0 - hfov / 2.
    const auto* e = std::get_if<Equirect>(&dst);
    const auto* cy = std::get_if<Cylindrical>(&dst);
    g.dst = e ? SimdGeometry::Dst::Equirect : SimdGeometry::Dst::Cylindrical;
    const LongitudeAxis& axis = e ? e->axis() : cy->axis();
    const Size size = e ? e->size() : cy->size();
    const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
    const double top = e ? e->lat_top() : cy->t_top();
    const double fall = e ? e->vfov() / h : (cy->t_top() - cy->t_bottom()) / h;
    const double v[9] = {w, axis.hfov, axis.lon0, h, top, 0.0, axis.hfov / w, fall, axis.lon0 - 0.5 * axis.hfov};
    std::copy(v, v + 9, gd);
    // A turn about the vertical only shifts the longitudes: fold it into [8] (rays come rotated).
    if (rotation(1, 1) > 0 && rotation(0, 1) == 0 && rotation(1, 0) == 0 && rotation(1, 2) == 0 &&
        rotation(2, 1) == 0) {
      gd[8] += std::atan2(rotation(0, 2), rotation(0, 0));
      g.rotated_rays = true;
    }
  } else if (const auto* c = std::get_if<Cubemap>(&dst)) {
    // The whole tile inside one face's cell.
    const int f = c->face_at(static_cast<double>(rect.x0) + 0.5, static_cast<double>(rect.y0) + 0.5);
    if (f < 0) return false;
    const auto o = c->face_origin(f);
    if (rect.x0 + rect.w > o[0] + c->face_size() || rect.y0 + rect.h > o[1] + c->face_size()) return false;
    g.dst = SimdGeometry::Dst::CubeFace;
    const CubeFace& cf = cube_faces()[f];
    // [0] F, [1..2] face origin, [3..5] forward, [6..8] right, [9..11] down, all rotated (the
    // rays come rotated), [12] 2 / F.
    const Eigen::Vector3d fwd = rotation * cf.fwd, right = rotation * cf.right,
                          down = rotation * cf.down;
    const double v[13] = {static_cast<double>(c->face_size()), static_cast<double>(o[0]), static_cast<double>(o[1]),
                          fwd.x(), fwd.y(), fwd.z(), right.x(), right.y(), right.z(), down.x(), down.y(), down.z(),
                          2.0 / static_cast<double>(c->face_size())};
    std::copy(v, v + 13, gd);
    g.rotated_rays = true;
  } else if (const auto* hm = std::get_if<Hammer>(&dst)) {
    // [0] xmin, [1] plane units per pixel in x, [2] ymax, [3] in y, [4] w, [5] 1 / w, [6] lon0,
    // [7] the outline |lambda| <= pi with the edge slack.
    g.dst = SimdGeometry::Dst::Hammer;
    const MapFrame& f = hm->frame();
    const double v[8] = {f.xmin, (f.xmax - f.xmin) / static_cast<double>(f.size.width), f.ymax,
                         (f.ymax - f.ymin) / static_cast<double>(f.size.height), hm->w(), 1.0 / hm->w(), hm->lon0(),
                         kPi * (1.0 + kEdgeSlack)};
    std::copy(v, v + 8, gd);
  } else if (const auto* bo = std::get_if<Bonne>(&dst)) {
    // [0] xmin, [1] plane units per pixel in x, [2] ymax, [3] in y, [6] lon0, [8] |phi1|, [9] the
    // mirror sign, [10] tan, [11] cot, [12] 1 for the small form. Double lanes only: phi =
    // cot + phi1 - rho cancels digits of rho (up to ~3 + cot), beyond float rays' error budget.
    g.dst = SimdGeometry::Dst::Bonne;
    const MapFrame& f = bo->frame();
    const double v[13] = {f.xmin, (f.xmax - f.xmin) / static_cast<double>(f.size.width), f.ymax,
                          (f.ymax - f.ymin) / static_cast<double>(f.size.height), 0.0, 0.0, bo->lon0(), 0.0,
                          bo->abs_phi1(), bo->mirror(), bo->tan_phi1(), bo->cot_phi1(), bo->small_form() ? 1.0 : 0.0};
    std::copy(v, v + 13, gd);
    g.use_float = false;
  } else if (const auto* fe = std::get_if<Fisheye>(&dst)) {
    g.dst = SimdGeometry::Dst::Fisheye;
    // [0..1] centre, [2..3] 1 / radii, [4] the law's value at the rim, [5] 1 if clipped to the
    // circle, [6] the law's largest value (its inverse's domain; stereographic: unbounded).
    const double limit[4] = {kPi, 2.0, 1.0, 1e300};
    const double v[7] = {static_cast<double>(fe->cx()), static_cast<double>(fe->cy()), 1.0 / static_cast<double>(fe->rx()),
                        1.0 / static_cast<double>(fe->ry()), static_cast<double>(fe->g_max()), fe->clip() ? 1.0 : 0.0,
                        limit[static_cast<int>(fe->model())]};
    std::copy(v, v + 7, gd);
    g.law = static_cast<int>(fe->model());
  } else {
    return false;
  }
  // Separable: (x, z) of the rotated ray independent of the row, y of the column. Pinhole rays
  // u c0 + v c1 + c2 ([4..12] by column): c1 = (0, c1y, 0), c0y = c2y = 0; cube rays fwd + a right
  // + b down ([3..11]): fwd y = right y = 0, down = (0, down y, 0). Exact zeros: a rotation about
  // the vertical has them.
  const bool axis_src = g.src == SimdGeometry::Src::Equirect || g.src == SimdGeometry::Src::Cylindrical;
  g.separable = axis_src && ((g.dst == SimdGeometry::Dst::Pinhole && gd[7] == 0 && gd[9] == 0 && gd[5] == 0 &&
                              gd[11] == 0) ||
                             (g.dst == SimdGeometry::Dst::CubeFace && gd[4] == 0 && gd[7] == 0 && gd[9] == 0 &&
                              gd[11] == 0));
  // Target pixel coordinates are exact in float up to 2^23.
  const Size ts = size_of(dst);
  g.use_float = g.use_float && std::max(ts.width, ts.height) < (int64_t{1} << 23);
  // The grid's float positions: the interpolation's error, one rounding of the position, and
  // float sums of offsets below ~1e3 px (under 1e-5 px) within kFloatTolerance.
  const Size ss = size_of(src);
  g.grid_tolerance = tol - static_cast<double>(std::max(ss.width, ss.height)) * kHalfUlp - 1e-5;
  const bool every_ray = (g.src == SimdGeometry::Src::Equirect && gs[10] != 0 && gs[12] != 0) ||
                         g.src == SimdGeometry::Src::Cubemap;
  const bool convex = g.dst == SimdGeometry::Dst::Pinhole || g.dst == SimdGeometry::Dst::CubeFace ||
                      g.dst == SimdGeometry::Dst::Fisheye;
  g.grid = g.use_float && every_ray && convex && g.grid_tolerance > 0.25 * tol;
  auto round = [](const double* a, float* b, int n) {
    for (int i = 0; i < n; ++i) b[i] = static_cast<float>(a[i]);
  };
  round(g.pd.d, g.pf.d, 16);
  round(g.pd.s, g.pf.s, 16);
  round(g.pd.r, g.pf.r, 9);
  return true;
}

void simd_tile_bounds(const SimdGeometry& g, const TileRect& rect, std::array<double, 4>& box) {
  HWY_DYNAMIC_DISPATCH(TileBounds)(g, rect, box.data());
}

void simd_map_tile(const SimdGeometry& g, const TileRect& rect, TileMap& out, bool grid) {
  const auto n = static_cast<size_t>(rect.w * rect.h);
  out.rect = rect;
  out.xs.resize(n);
  out.ys.resize(n);
  out.ok.resize(n);
  HWY_DYNAMIC_DISPATCH(MapTile)(g, rect, grid, out);
}

}  // namespace panoproj
#endif
