#pragma once
// Source coordinates for one output tile, cheaply and within a stated error:
//   - exact (double) pixel -> ray -> R ray -> source pixel at the corners of kCell x kCell cells
//     (a node grid every kCell pixels, with one ring of nodes before and two after the tile);
//   - inside each cell, cubic Lagrange interpolation of the 4x4 surrounding nodes (error of
//     order h^4 times the map's 4th derivative), accepted when all 16 nodes have a source pixel
//     and exact check points in the cell agree within kMapTolerance source pixels: the centre,
//     and where it errs by over kMapTolerance/16, eight more (quarter points and the inner
//     square's edge midpoints);
//   - otherwise (seams, face changes, field boundaries, singular points) exact per pixel.
// Interpolated pixels are then checked with contains() on both sides, so validity is exact.
// Tested for every projection in tests/tile_map_test.cpp.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "panoproj/projection.hpp"

namespace panoproj {

inline constexpr int64_t kTile = 64;  // output tile side: the unit of work and of threading
inline constexpr int kCell = 8;
inline constexpr double kMapTolerance = 1.0 / 1024;  // source pixels, at the checked points

// Cubic Lagrange weights through nodes at t = -1, 0, 1, 2 (cells), at t.
constexpr void lagrange_cubic(double t, double w[4]) {
  w[0] = -t * (t - 1) * (t - 2) / 6;
  w[1] = (t + 1) * (t - 1) * (t - 2) / 2;
  w[2] = -(t + 1) * t * (t - 2) / 2;
  w[3] = (t + 1) * t * (t - 1) / 6;
}

struct TileMap {
  PixelRect rect{};
  std::vector<double> xs, ys;  // rect.w * rect.h source positions, row-major
  std::vector<uint8_t> ok;     // 1 where the output pixel has a source position
  int64_t exact_cells = 0, interpolated_cells = 0;
};

// exact: positions within kMapEdgeGuard of a pixel edge (a whole number) computed exactly, so
// nearest picks the reference's pixels bit for bit (a 16x margin over kMapTolerance).
inline constexpr double kMapEdgeGuard = 1.0 / 64;

// siting: where the planes' samples sit (projection.hpp); positions are the source's sample
// coordinates (a sample's centre at k + 0.5).
void map_tile(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation,
              PixelRect rect, TileMap& out, bool exact = false, const Siting& siting = {});

}  // namespace panoproj
