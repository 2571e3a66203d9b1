// Tile maps from the vector geometry of tile_rows-inl.h (Highway, runtime dispatch), and the
// choice of pairs and their lanes.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "simd/geometry.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// Order matters: foreach_target re-includes this file once per target.
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "simd/geometry.hpp"
#include "simd/tile_rows-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The positions the fused converter computes (TileRows), stored in double.
void MapTile(const SimdGeometry& g, const PixelRect& rect, bool grid, TileMap& out) {
  const TileRows rows(g, rect, grid);
  out.interpolated_cells = rows.grid_cells();
  out.exact_cells = grid && g.grid ? rows.cells() - out.interpolated_cells : 0;
  for (int64_t j = 0; j < rect.height(); ++j) {
    const size_t row = static_cast<size_t>(j * rect.width());
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
void TileBounds(const SimdGeometry& g, const PixelRect& rect, double* box) {
  const TileRows rows(g, rect);
  Extent<hn::ScalableTag<float>> ef;
  Extent<DD> ed;
  for (int64_t j = 0; j < rect.height(); ++j)
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

// Sets g's lanes in double and in float by describe(lanes) (each projection's describe rounds
// its double values once); returns what it returns.
template <class Describe>
auto set_lanes(SimdGeometry& g, Describe&& describe) {
  describe(g.ld);
  return describe(g.lf);
}

// The source's lanes; false if the source has no vector form.
bool describe_source(const Projection& src, SimdGeometry& g) {
  using Src = SimdGeometry::Src;
  if (const auto* e = std::get_if<Equirect>(&src)) {
    g.src = Src::Equirect;
    g.use_float = set_lanes(g, [&](auto& l) { return simd::describe(*e, l.source.axis); });
  } else if (const auto* cy = std::get_if<Cylindrical>(&src)) {
    g.src = Src::Cylindrical;
    g.use_float = set_lanes(g, [&](auto& l) { return simd::describe(*cy, l.source.axis); });
  } else if (const auto* hm = std::get_if<Hammer>(&src)) {
    g.src = Src::Hammer;
    g.use_float = set_lanes(g, [&](auto& l) {
      simd::describe(hm->frame(), hm->lon0(), l.source.map);
      return simd::describe(*hm, l.source.hammer);
    });
  } else if (const auto* ai = std::get_if<Aitoff>(&src)) {
    g.src = Src::Aitoff;
    g.use_float = set_lanes(g, [&](auto& l) {
      simd::describe(ai->frame(), ai->lon0(), l.source.map);
      return simd::describe(*ai, l.source.aitoff);
    });
  } else if (const auto* bo = std::get_if<Bonne>(&src)) {
    g.src = Src::Bonne;
    g.use_float = set_lanes(g, [&](auto& l) {
      simd::describe(bo->frame(), bo->lon0(), l.source.map);
      return simd::describe(*bo, l.source.bonne);
    });
  } else if (const auto* ph = std::get_if<Pinhole>(&src)) {
    g.src = Src::Pinhole;
    g.use_float = set_lanes(g, [&](auto& l) { return simd::describe(*ph, l.source.pinhole); });
  } else if (const auto* fs = std::get_if<Fisheye>(&src); fs && fs->model() != FisheyeModel::Thoby) {  // Thoby: tile maps
    g.src = Src::Fisheye;
    g.use_float = set_lanes(g, [&](auto& l) { return simd::describe(*fs, l.source.fisheye); });
  } else if (const auto* c = std::get_if<Cubemap>(&src); c && c->uniform()) {  // FFmpeg's EAC frame: tile maps
    g.src = Src::Cubemap;
    g.use_float = set_lanes(g, [&](auto& l) { return simd::describe(*c, l.source.cubemap); });
  } else {
    return false;
  }
  return true;
}

// The target's lanes for the tile; false if the target (or this tile) has no vector form.
bool describe_target(const Projection& dst, const Eigen::Matrix3d& rotation, const PixelRect& rect,
                     SimdGeometry& g) {
  using Dst = SimdGeometry::Dst;
  if (const auto* p = std::get_if<Pinhole>(&dst)) {
    g.dst = Dst::Pinhole;
    set_lanes(g, [&](auto& l) { simd::describe(*p, rotation, l.target.pinhole); });
    g.rotated_rays = true;
  } else if (const auto* e = std::get_if<Equirect>(&dst)) {
    g.dst = Dst::Equirect;
    g.rotated_rays = set_lanes(g, [&](auto& l) { return simd::describe(*e, rotation, l.target.axis); }) || g.rotated_rays;
  } else if (const auto* cy = std::get_if<Cylindrical>(&dst)) {
    g.dst = Dst::Cylindrical;
    g.rotated_rays = set_lanes(g, [&](auto& l) { return simd::describe(*cy, rotation, l.target.axis); }) || g.rotated_rays;
  } else if (const auto* c = std::get_if<Cubemap>(&dst)) {
    g.dst = Dst::CubeFace;
    if (!set_lanes(g, [&](auto& l) { return simd::describe(*c, rect, rotation, l.target.cube_face); })) return false;
    g.rotated_rays = true;
    // eac: a = tan(pi/4 A) in float is within the ray's error budget for slopes up to pi/2
    // (pad 0); a padded cell's edges are steeper.
    if (c->format().angular && c->format().pad > 0) g.use_float = false;
  } else if (const auto* hm = std::get_if<Hammer>(&dst)) {
    g.dst = Dst::Hammer;
    set_lanes(g, [&](auto& l) { simd::describe(*hm, l.target.hammer); });
  } else if (const auto* bo = std::get_if<Bonne>(&dst)) {
    g.dst = Dst::Bonne;
    set_lanes(g, [&](auto& l) { simd::describe(*bo, l.target.bonne); });
    g.use_float = false;  // (simd/bonne.hpp)
  } else if (const auto* fe = std::get_if<Fisheye>(&dst); fe && fe->model() != FisheyeModel::Thoby) {
    g.dst = Dst::Fisheye;
    set_lanes(g, [&](auto& l) { simd::describe(*fe, l.target.fisheye); });
  } else {
    return false;
  }
  return true;
}

// Separable: (x, z) of the rotated ray independent of the row, y of the column. Pinhole rays
// u col0 + v col1 + col2: col1 = (0, col1 y, 0), col0 y = col2 y = 0; cube rays fwd + a right +
// b down: fwd y = right y = 0, down = (0, down y, 0). Exact zeros: a rotation about the vertical
// has them.
bool separable(const SimdGeometry& g) {
  const bool axis_src = g.src == SimdGeometry::Src::Equirect || g.src == SimdGeometry::Src::Cylindrical;
  const auto& p = g.ld.target.pinhole;
  const auto& c = g.ld.target.cube_face;
  return axis_src &&
         ((g.dst == SimdGeometry::Dst::Pinhole && p.col1[0] == 0 && p.col1[2] == 0 && p.col0[1] == 0 && p.col2[1] == 0) ||
          (g.dst == SimdGeometry::Dst::CubeFace && c.fwd[1] == 0 && c.right[1] == 0 && c.down[0] == 0 && c.down[2] == 0));
}

}  // namespace

bool simd_geometry_for(const Projection& src, const Projection& dst,
                       const Eigen::Matrix3d& rotation, const PixelRect& rect, SimdGeometry& g,
                       const Siting& siting) {
  g.centre_x = 0.5 + siting.target_x, g.centre_y = 0.5 + siting.target_y;
  g.shift_x = siting.source_x, g.shift_y = siting.source_y;
  // A tile inside one half of a dual-fisheye target: that half's lens (camera ray = R_k lens
  // ray). (A dual-fisheye source is sampled one lens at a time, each a fisheye: LensSource.)
  if (const auto* d = std::get_if<DualFisheye>(&dst)) {
    const int k = d->lens_at(static_cast<double>(rect.x0) + g.centre_x,
                             static_cast<double>(rect.y0) + g.centre_y);
    if (d->lens_at(static_cast<double>(rect.x0 + rect.width() - 1) + g.centre_x,
                   static_cast<double>(rect.y0 + rect.height() - 1) + g.centre_y) != k)
      return false;
    return simd_geometry_for(src, Projection(d->lens(k)), rotation * d->rotation(k), rect, g,
                             siting);
  }
  g.ld = {};  // unused lanes are 0
  g.lf = {};
  for (int i = 0; i < 9; ++i) {
    g.ld.rotation[i] = rotation(i / 3, i % 3);
    g.lf.rotation[i] = static_cast<float>(rotation(i / 3, i % 3));
  }
  g.rotated_rays = rotation == Eigen::Matrix3d::Identity();  // nothing to turn
  if (!describe_source(src, g) || !describe_target(dst, rotation, rect, g)) return false;
  g.separable = separable(g);
  // Target pixel coordinates are exact in float up to 2^23 (centres at halves), 2^20 when sited
  // (a 4:1:0 plane's eighths).
  const Size ts = size_of(dst);
  g.use_float =
      g.use_float && std::max(ts.width, ts.height) < (int64_t{1} << (siting.any() ? 20 : 23));
  // The grid's float positions: the interpolation's error, one rounding of the position, and
  // float sums of offsets below ~1e3 px (under 1e-5 px) within kFloatTolerance.
  const Size ss = size_of(src);
  const double tol = SimdGeometry::kFloatTolerance;
  g.grid_tolerance = tol - static_cast<double>(std::max(ss.width, ss.height)) * simd::kHalfUlp - 1e-5;
  const bool every_ray = (g.src == SimdGeometry::Src::Equirect && g.ld.source.axis.full && g.ld.source.axis.full_sphere) ||
                         g.src == SimdGeometry::Src::Cubemap;
  const bool convex = g.dst == SimdGeometry::Dst::Pinhole || g.dst == SimdGeometry::Dst::CubeFace ||
                      g.dst == SimdGeometry::Dst::Fisheye;
  g.grid = g.use_float && every_ray && convex && g.grid_tolerance > 0.25 * tol;
  return true;
}

void simd_tile_bounds(const SimdGeometry& g, const PixelRect& rect, std::array<double, 4>& box) {
  HWY_DYNAMIC_DISPATCH(TileBounds)(g, rect, box.data());
}

void simd_map_tile(const SimdGeometry& g, const PixelRect& rect, TileMap& out, bool grid) {
  const auto n = static_cast<size_t>(rect.width() * rect.height());
  out.rect = rect;
  out.xs.resize(n);
  out.ys.resize(n);
  out.ok.resize(n);
  HWY_DYNAMIC_DISPATCH(MapTile)(g, rect, grid, out);
}

}  // namespace panoproj
#endif
