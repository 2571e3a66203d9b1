// The source positions of a tile's pixel rows (TileRows) from the SIMD pair of simd/geometry.hpp,
// shared by the map builder (simd/geometry.cpp) and the fused converter (simd_sampler.cpp):
// the pair's projections' vector forms chosen by kind, the rotation, per-tile tables and the
// interpolating grid. Rays are not normalized: both sides are scale-invariant (atan2; ratios).
// Per-target include guard (Highway's pattern for -inl headers re-included per target).
#if defined(PANOPROJ_SIMD_TILE_ROWS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PANOPROJ_SIMD_TILE_ROWS_INL_H_
#undef PANOPROJ_SIMD_TILE_ROWS_INL_H_
#else
#define PANOPROJ_SIMD_TILE_ROWS_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "simd/aitoff-inl.h"
#include "simd/bonne-inl.h"
#include "simd/cubemap-inl.h"
#include "simd/fisheye-inl.h"
#include "simd/geometry.hpp"
#include "simd/hammer-inl.h"
#include "simd/longitude_axis-inl.h"
#include "simd/map_frame-inl.h"
#include "simd/math-inl.h"
#include "simd/pinhole-inl.h"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The rays of pixel centres (px, py) for the target (simd/<projection>-inl.h). ok: the pixel
// has a ray; coarse: lanes where float lanes would be ill-conditioned.
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void TargetRay(D d, const SimdGeometry& g, V px, V py, V& x, V& y, V& z, M& ok, M& coarse) {
  const auto& l = g.lanes<hn::TFromD<D>>().target;
  ok = hn::Eq(px, px);  // all true
  coarse = hn::Not(ok);
  x = y = z = hn::Zero(d);
  switch (g.dst) {
    case SimdGeometry::Dst::Pinhole: return TargetRay(d, l.pinhole, px, py, x, y, z, ok, coarse);
    case SimdGeometry::Dst::Equirect:
    case SimdGeometry::Dst::Cylindrical: return TargetRay(d, l.axis, px, py, x, y, z, ok, coarse);
    case SimdGeometry::Dst::Hammer: return TargetRay(d, l.hammer, px, py, x, y, z, ok, coarse);
    case SimdGeometry::Dst::Bonne: return TargetRay(d, l.bonne, px, py, x, y, z, ok, coarse);
    case SimdGeometry::Dst::CubeFace: return TargetRay(d, l.cube_face, px, py, x, y, z, ok, coarse);
    case SimdGeometry::Dst::Fisheye: return TargetRay(d, l.fisheye, px, py, x, y, z, ok, coarse);
  }
}

// The source pixel of ray (x, y, z) (simd/<projection>-inl.h). coarse: lanes where float lanes
// would err by more than SimdGeometry::kFloatTolerance.
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void SourcePixel(D d, const SimdGeometry& g, V x, V y, V z, V& sx, V& sy, M& ok, M& coarse) {
  const auto& l = g.lanes<hn::TFromD<D>>().source;
  switch (g.src) {
    case SimdGeometry::Src::Equirect:
    case SimdGeometry::Src::Cylindrical: return SourcePixel(d, l.axis, x, y, z, sx, sy, ok, coarse);
    case SimdGeometry::Src::Pinhole: return SourcePixel(d, l.pinhole, x, y, z, sx, sy, ok, coarse);
    case SimdGeometry::Src::Fisheye: return SourcePixel(d, l.fisheye, x, y, z, sx, sy, ok, coarse);
    case SimdGeometry::Src::Hammer:
    case SimdGeometry::Src::Aitoff:
    case SimdGeometry::Src::Bonne: {
      // The map forms: their angles, the form's plane point, the frame. (One join before the
      // frame, as before the lanes were named: GCC contracts multiplies into FMAs by the code's
      // shape, and a change of shape changed float positions by an ulp.)
      V lam, h2, n, cp, sp, X, Y;
      coarse = hn::Lt(hn::Zero(d), hn::Zero(d));  // none
      MapAngles(d, l.map, x, y, z, lam, h2, n, cp, sp);
      if (g.src == SimdGeometry::Src::Hammer) Forward(d, l.hammer, lam, h2, n, cp, sp, y, X, Y, coarse);
      else if (g.src == SimdGeometry::Src::Aitoff) Forward(d, l.aitoff, lam, h2, n, cp, sp, y, X, Y, coarse);
      else Forward(d, l.bonne, lam, h2, n, cp, sp, y, X, Y, coarse);
      return FramePixel(d, l.map, X, Y, sx, sy, ok);
    }
    case SimdGeometry::Src::Cubemap:
    default: return SourcePixel(d, l.cubemap, x, y, z, sx, sy, ok, coarse);
  }
}

// Source positions (sx, sy) of target rays (x, y, z) (ok_dst, coarse_dst from TargetRay):
// rotation, source pixel; ok where both sides are valid; coarse where float lanes are not
// accurate enough.
template <class D, class V = hn::Vec<D>, class M = hn::Mask<D>>
HWY_INLINE void SourceOfRays(D d, const SimdGeometry& g, V x, V y, V z, M ok_dst, M coarse_dst, V& sx, V& sy, M& ok,
                             M& coarse) {
  const auto* r = g.lanes<hn::TFromD<D>>().rotation;
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
  TileRows(const SimdGeometry& g, const PixelRect& rect, bool grid = false)
      : g_(g), x0_(rect.x0), y0_(rect.y0), n_(rect.width()) {
    const bool fits = rect.width() <= kMaxTableWidth && rect.height() <= kMaxTableWidth;
    cylinder_ = g.dst == SimdGeometry::Dst::Cylindrical;
    table_ = (g.dst == SimdGeometry::Dst::Equirect || cylinder_) && fits;
    grid_ = grid && g.grid && fits && g.use_float;
    separable_ = g.separable && fits && !grid_;
    // Vector functions (a few ulp), every entry: rows read whole vectors past n.
    const DD dd;
    const hn::Rebind<float, DD> df;
    const auto ND = static_cast<int64_t>(hn::Lanes(dd));
    const simd::AxisRays<double>& ax = g.ld.target.axis;
    auto store = [&](VD v, double* to_d, float* to_f, int64_t i) {
      hn::Store(v, dd, to_d + i);
      hn::StoreU(hn::DemoteTo(df, v), df, to_f + i);
    };
    for (int64_t i = 0; table_ && i < kMaxTableWidth + kPad; i += ND) {
      const VD lon = hn::MulAdd(hn::Iota(dd, static_cast<double>(x0_ + i) + g.centre_x),
                                hn::Set(dd, ax.lon_per_px), hn::Set(dd, ax.lon_first));
      store(hn::Sin(dd, lon), col_a_d_, col_a_f_, i);
      store(hn::Cos(dd, lon), col_b_d_, col_b_f_, i);
      // Rows: equirect (sin, cos) of the latitude; cylindrical (t, 1), t = tan(lat) linear in y.
      const VD v = hn::NegMulAdd(hn::Iota(dd, static_cast<double>(y0_ + i) + g.centre_y),
                                 hn::Set(dd, ax.fall), hn::Set(dd, ax.top));
      hn::Store(cylinder_ ? v : hn::Sin(dd, v), dd, row_a_ + i);
      hn::Store(cylinder_ ? hn::Set(dd, 1.0) : hn::Cos(dd, v), dd, row_b_ + i);
    }
    for (int64_t i = 0; separable_ && i < kMaxTableWidth + kPad; i += ND) {
      // Columns: (x, z) of the rotated ray (cube face: fwd + a right; pinhole: u c0 + c2) ->
      // source x (a) and x^2 + z^2 (b), with the longitude's validity (ok_x). Rows: the ray's y.
      const VD px = hn::Iota(dd, static_cast<double>(x0_ + i) + g.centre_x),
               py = hn::Iota(dd, static_cast<double>(y0_ + i) + g.centre_y);
      VD x, z, y;
      if (g.dst == SimdGeometry::Dst::CubeFace) {
        const auto& c = g.ld.target.cube_face;
        VD a, b;
        CubeFaceTangents(dd, c, px, py, a, b);
        x = hn::MulAdd(a, hn::Set(dd, c.right[0]), hn::Set(dd, c.fwd[0]));
        z = hn::MulAdd(a, hn::Set(dd, c.right[2]), hn::Set(dd, c.fwd[2]));
        y = hn::Mul(b, hn::Set(dd, c.down[1]));
      } else {
        const auto& p = g.ld.target.pinhole;
        const VD u = hn::Mul(hn::Sub(px, hn::Set(dd, p.cx)), hn::Set(dd, p.inv_fx));
        const VD v = hn::Mul(hn::Sub(py, hn::Set(dd, p.cy)), hn::Set(dd, p.inv_fy));
        x = hn::MulAdd(u, hn::Set(dd, p.col0[0]), hn::Set(dd, p.col2[0]));
        z = hn::MulAdd(u, hn::Set(dd, p.col0[2]), hn::Set(dd, p.col2[2]));
        y = hn::Mul(v, hn::Set(dd, p.col1[1]));
      }
      VD sx;
      MD ok_x;
      LongitudeX(dd, g.ld.source.axis, x, z, sx, ok_x);
      store(sx, col_a_d_, col_a_f_, i);
      store(hn::MulAdd(x, x, hn::Mul(z, z)), col_b_d_, col_b_f_, i);
      store(hn::IfThenElseZero(ok_x, hn::Set(dd, 1.0)), col_ok_d_, col_ok_f_, i);
      hn::Store(y, dd, row_a_ + i);
    }
    if (grid_) BuildGrid(rect);
  }

  // Calls sink(sx, sy, ok, i, m) for output pixels (x0 + i .. x0 + i + m - 1, y), i from 0 to n
  // in steps of the vector: float vectors (twice the lanes) where g.use_float and every lane is
  // accurate enough (and, with g.edge_exact, none near a pixel edge), else double vectors. Lanes
  // beyond n have ok false.
  template <class Sink>
  HWY_INLINE void Row(int64_t y, Sink&& sink) const {
    const DD dd;
    const auto ND = static_cast<int64_t>(hn::Lanes(dd));
    const bool rows = table_ || separable_;
    const double ra = rows ? row_a_[y - y0_] : 0.0, rb = table_ ? row_b_[y - y0_] : 0.0;
    auto doubles = [&](int64_t i, int64_t end) {
      const VD py = hn::Set(dd, static_cast<double>(y) + g_.centre_y);
      for (; i < end; i += ND) {
        const int64_t m = std::min(ND, end - i);
        VD sx, sy;
        MD ok, coarse;
        Positions(dd, hn::Iota(dd, static_cast<double>(x0_ + i) + g_.centre_x), py, i, ra, rb, sx,
                  sy, ok, coarse);
        sink(sx, sy, hn::And(ok, hn::FirstN(dd, static_cast<size_t>(m))), i, m);
      }
    };
    if (!g_.use_float) return doubles(0, n_);
    using DF32 = hn::ScalableTag<float>;
    const DF32 df;
    const auto NF = static_cast<int64_t>(hn::Lanes(df));
    const auto py = hn::Set(df, static_cast<float>(static_cast<double>(y) + g_.centre_y));
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
        Positions(df, hn::Iota(df, static_cast<float>(static_cast<double>(x0_ + i) + g_.centre_x)),
                  py, i, static_cast<float>(ra), static_cast<float>(rb), sx, sy, ok, coarse);
        ok = hn::And(ok, hn::FirstN(df, static_cast<size_t>(m)));
        if (g_.edge_exact) {
          const auto guard = hn::Set(df, static_cast<float>(SimdGeometry::kEdgeGuard));
          auto near = [&](hn::Vec<DF32> v) { return hn::Lt(hn::Abs(hn::Sub(v, hn::Round(v))), guard); };
          coarse = hn::Or(coarse, hn::Or(near(sx), near(sy)));
        }
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

  // Positions of the pixels from column i on, with the row's values ra, rb (see the tables), less
  // the source's shift (exact: a shift of eighths in a plane under 2^20 px).
  template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
  HWY_INLINE void Positions(D d, V px, V py, int64_t i, T ra, T rb, V& sx, V& sy, M& ok, M& coarse) const {
    RayPositions(d, px, py, i, ra, rb, sx, sy, ok, coarse);
    if (g_.shift_x != 0 || g_.shift_y != 0)
      sx = hn::Sub(sx, hn::Set(d, static_cast<T>(g_.shift_x))),
      sy = hn::Sub(sy, hn::Set(d, static_cast<T>(g_.shift_y)));
  }

  // The same before the shift.
  template <class D, class T, class V = hn::Vec<D>, class M = hn::Mask<D>>
  HWY_INLINE void RayPositions(D d, V px, V py, int64_t i, T ra, T rb, V& sx, V& sy, M& ok,
                               M& coarse) const {
    const T* a = col<T>(col_a_d_, col_a_f_) + i;
    const T* b = col<T>(col_b_d_, col_b_f_) + i;
    if (separable_) {
      sx = hn::LoadU(d, a);
      LatitudeY(d, g_.lanes<T>().source.axis, hn::Set(d, ra), hn::LoadU(d, b), sy, ok, coarse);
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

  // Grid mode (SimdGeometry::grid): node (r, c) at pixel centre (x0 + (c - 1) kGridCell + centre_x,
  // y0 + (r - 1) kGridCell + centre_y); cell (b, a) spans pixels [a, a + 1) kGridCell x [b, b + 1)
  // kGridCell and interpolates nodes b..b+3 x a..a+3.
  void BuildGrid(const PixelRect& rect) {
    const DD dd;
    const auto ND = static_cast<int64_t>(hn::Lanes(dd));
    const int64_t ncx = (rect.width() + kGridCell - 1) / kGridCell,
                  ncy = (rect.height() + kGridCell - 1) / kGridCell;
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
        px[c] = static_cast<double>(x0_ + (c - 1) * kGridCell) + g_.centre_x,
        py[c] = static_cast<double>(y0_ + (r - 1) * kGridCell) + g_.centre_y;
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
          px[n] = static_cast<double>(x0_ + a * kGridCell + kChecks[k][0]) + g_.centre_x;
          py[n++] = static_cast<double>(y0_ + b * kGridCell + kChecks[k][1]) + g_.centre_y;
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
