#pragma once
// Antialias's footprint kernel, auto's filter where the output shrinks: each output pixel
// averages the source pixels under its footprint, each weighted by its overlap with a box of
// width e along each source axis centred on the sample (box(e) convolved with the pixel's own
// box: OpenCV's INTER_AREA resize, but per pixel, along the map's local footprint):
//   w(d) = min(1, max(0, (e + 1) / 2 - |d|)) / e  (d: the sample's distance from a tap)
// on the 6 taps of first_tap(Interp::Lanczos3, s), which hold the box for any e <= 5 (the
// weights sum to 1; computed as divided by their sum). e = 1 is the bilinear tent.
// e is the width of the box with the footprint's second moment: the footprint, the
// parallelogram spanned by the map's steps to the next pixel along the output's x, (ux, uy), and
// y, (vx, vy), has variance (ux^2 + vx^2) / 12 along source x, as a box of width
//   e_x = sqrt(ux^2 + vx^2)  (likewise e_y = sqrt(uy^2 + vy^2)),
// clamped to [1, kFootprintReach]; wider footprints are split into sub-pixels (the engine).
// The widths come from the exact steps at 3 x 3 points of each output tile (corners, edge
// middles, centre), bilinear in between: the footprint changes slowly, and the fused SIMD
// geometry then needs no map (docs/decisions.md: the kernels measured before this one).
#include <cstdint>

#include "sampling/interpolator.hpp"
#include "panoproj/projection.hpp"
#include "geometry/tile_map.hpp"

namespace panoproj {

// The kernel whose taps the footprint kernel reads (with its own weights), and their count.
inline constexpr Interp kFootprintGrid = Interp::Lanczos3;
inline constexpr int kFootprintTaps = 6;  // support(kFootprintGrid)
inline constexpr double kFootprintReach = 5.0;  // source pixels: the widest box the taps hold

// The kFootprintTaps tap weights (from first_tap(kFootprintGrid, s)) for a sample at s with
// box width e in [1, kFootprintReach].
void footprint_weights(double s, double e, double* w);

// The box widths over a rect being sampled: at the 3 x 3 points of its output tile, and a rect
// pixel (i, j)'s place among them, u = u0 + i du, v = v0 + j dv (0, 1, 2: the points' columns
// and rows), clamped to [0, 2]; the widths there are scale times the bilinear blend of the
// nearest points' (the pieces of a 3 x 3 hat-function sum), clamped to [1, kFootprintReach].
struct FootprintField {
  float ex[9], ey[9];  // row-major
  float u0 = 0, du = 0, v0 = 0, dv = 0, scale = 1;
  // The widths at rect pixel (i, j), in float as the SIMD sampler computes them.
  void at(int64_t i, int64_t j, float& wx, float& wy) const;
  // The field of tile for rect pixels of the target n times finer (its sub-pixels; n = 1: the
  // tile's own pixels, rect = tile).
  FootprintField for_rect(const PixelRect& tile, const PixelRect& rect, int n) const;
};

// The field of output tile rect, and its footprint's side: the median over the points of the
// geometric mean of their step lengths (the square root of the footprint's area), in source
// pixels; and the same with x steps counted at the source's x sampling density relative to the
// equator's (cos(latitude) on an equirect, else 1), which sets the sub-pixel count: near an
// equirect's poles a row holds far more samples per angle than the panorama holds detail, and
// splitting for those would cost n^2 for nothing (the kernel's widths stay in pixels, clamped).
// A point without a source, or without steps, takes the mean of the others' widths. Both 0 (and
// no field) where no point has steps. wrap_width: the source frame's width where x wraps (a full
// circle of longitude), else 0.
struct FootprintSides {
  double side, split;
};
FootprintSides footprint_field(const Projection& source, const Projection& target,
                               const Eigen::Matrix3d& rotation, const PixelRect& rect,
                               double wrap_width, FootprintField& field);

}  // namespace panoproj
