#pragma once
// Source positions of pixel rows in double-precision SIMD (Google Highway), for the common pairs:
// targets pinhole, equirect, fisheye (clip=circle, any law) and cube tiles inside one face;
// sources equirect with a full circle of longitude and cubemap. Double, not float: near a pole
// the longitude atan2(x, z) divides float's 6e-8 absolute error by cos(latitude), which reached
// 0.1 px at 32768 px (measured). Tested against the exact map in tests/simd_geometry_test.cpp;
// other pairs use the tile mapper. Internal.
#include <Eigen/Core>
#include <cstdint>

#include "panoproj/projection.hpp"
#include "panoproj/tile_map.hpp"

namespace panoproj {

struct SimdGeometry {
  enum class Dst { Pinhole, Equirect, CubeFace, Fisheye } dst;
  enum class Src { Equirect, Cubemap } src;
  double d[12];   // target parameters (see simd_geometry.cpp)
  double s[20];   // source parameters
  double r[9];    // rotation, row-major
  int law;        // fisheye law (FisheyeModel as int)
};

// Describes the pair for one tile; false when the pair (or this tile: a cube tile spanning two
// face cells) is not supported.
bool simd_geometry_for(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation,
                       const TileRect& rect, SimdGeometry& g);

// Fills out (a TileMap of rect's size) with the source positions of the tile's pixel centres.
void simd_map_tile(const SimdGeometry& g, const TileRect& rect, TileMap& out);

}  // namespace panoproj
