#pragma once
// The steps of a conversion's source positions from an output pixel to its neighbours: the
// map's local Jacobian, which antialiasing reads (auto's footprint, mip's levels). Internal.
#include <cmath>
#include <cstdint>

#include "geometry/tile_map.hpp"

namespace panoproj {

// Along one output axis, of the steps from a pixel to its neighbours before (bx, by) and after
// (ax, ay) it, in source pixels, the shorter: a seam, a pole or a face edge lies on one side
// only. A neighbour without a position has bx (ax) NaN. x goes the short way around where wrap > 0
// (the width of a full circle of longitude). False where neither neighbour has a position. In
// float: a step is small, its rounding far below what antialiasing resolves.
inline bool shorter_step(float bx, float by, float ax, float ay, float wrap, float& dx, float& dy) {
  auto wrapped = [&](float x) { return x + (x < -0.5f * wrap ? wrap : 0.0f) - (x > 0.5f * wrap ? wrap : 0.0f); };
  bx = wrapped(bx), ax = wrapped(ax);
  const bool b = !std::isnan(bx), a = !std::isnan(ax);
  const bool before = b && (!a || bx * bx + by * by < ax * ax + ay * ay);
  dx = before ? bx : a ? ax : 0.0f, dy = before ? by : a ? ay : 0.0f;
  return a || b;
}

// Pixel (i, j)'s steps in tile map tm along the output's x (ux, uy) and y (vx, vy); false where
// it has no position or either step is missing.
inline bool pixel_steps(const TileMap& tm, int64_t i, int64_t j, float wrap, float& ux, float& uy, float& vx, float& vy) {
  const int64_t w = tm.rect.width(), k = j * w + i;
  ux = uy = vx = vy = 0.0f;
  if (!tm.ok[k]) return false;
  auto step = [&](int64_t q, float& dx, float& dy) {  // k -> q (NaN: none)
    const bool has = q >= 0 && tm.ok[q];
    dx = has ? static_cast<float>(tm.xs[q] - tm.xs[k]) : NAN, dy = has ? static_cast<float>(tm.ys[q] - tm.ys[k]) : 0.0f;
  };
  float bx, by, ax, ay;
  step(i > 0 ? k - 1 : -1, bx, by), step(i + 1 < w ? k + 1 : -1, ax, ay);
  if (!shorter_step(bx, by, ax, ay, wrap, ux, uy)) return false;
  step(j > 0 ? k - w : -1, bx, by), step(j + 1 < tm.rect.height() ? k + w : -1, ax, ay);
  return shorter_step(bx, by, ax, ay, wrap, vx, vy);
}

}  // namespace panoproj
