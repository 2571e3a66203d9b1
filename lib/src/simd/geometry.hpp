#pragma once
// Source positions of pixel rows in SIMD (Google Highway): targets pinhole, equirect,
// cylindrical, fisheye (any law, clipped or not), Hammer / Eckert-Greifendorff, Bonne, cube
// tiles inside one face and dual-fisheye tiles inside one lens; sources equirect, cylindrical
// (full or partial), cubemap, Hammer, Aitoff, Bonne, pinhole, fisheye and one lens of a dual
// fisheye. Each projection's lanes (its parameters, named) are in simd/<projection>.hpp and its
// vector forms in simd/<projection>-inl.h; this pairs them. Float lanes where they stay within
// kFloatTolerance, double lanes elsewhere: near an equirect pole the longitude atan2(x, z)
// divides float's ~1e-7 absolute ray error by cos(latitude) (float everywhere erred by 0.1 px at
// 32768 px, measured), and float positions themselves are coarse beyond a few thousand pixels.
// Tested against the exact map in tests/simd_geometry_test.cpp; other pairs use the tile mapper.
// For uint8 sources, pairs with SimdGeometry::grid interpolate between exact nodes instead
// (TileRows). Internal.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <type_traits>

#include "panoproj/projection.hpp"
#include "geometry/tile_map.hpp"
#include "simd/aitoff.hpp"
#include "simd/bonne.hpp"
#include "simd/cubemap.hpp"
#include "simd/fisheye.hpp"
#include "simd/hammer.hpp"
#include "simd/lanes.hpp"
#include "simd/longitude_axis.hpp"
#include "simd/pinhole.hpp"

namespace panoproj {

struct SimdGeometry {
  // Error bound of float lanes, in source pixels: lanes that could exceed it are computed in
  // double (see use_float and each source's coarse lanes).
  static constexpr double kFloatTolerance = simd::kFloatTolerance;
  enum class Dst { Pinhole, Equirect, Cylindrical, CubeFace, Fisheye, Hammer, Bonne } dst;
  enum class Src { Equirect, Cylindrical, Cubemap, Hammer, Aitoff, Bonne, Pinhole, Fisheye } src;
  // Float lanes (twice as many per vector, shorter polynomials) where the source is small enough
  // for float positions to stay within kFloatTolerance; double lanes otherwise.
  bool use_float;
  // The target's rays need no rotation (9 operations a vector fewer): the identity, or folded
  // into the target (pinhole and cube-face bases; equirect and cylindrical longitudes for a turn
  // about the vertical).
  bool rotated_rays;
  // A longitude-axis source and a pinhole or cube-face target turned only about the vertical:
  // the ray's (x, z) follows the column and y the row (TileRows' column tables).
  bool separable;
  // Exact positions at nodes every kGridCell pixels and cubic interpolation between them, in
  // cells where exact check points agree within grid_tolerance (TileRows): a source whose every
  // ray has a pixel (a full equirect, a cubemap) and a target whose valid pixels form a convex
  // set (pinhole, cube face, fisheye), so a cell whose nodes are all valid is valid throughout.
  bool grid;
  double grid_tolerance;
  // Nearest: float vectors with a position within kEdgeGuard of a pixel edge (a whole number)
  // are computed in double, so the pixel picked is the exact position's.
  bool edge_exact = false;
  static constexpr double kEdgeGuard = 2 * kFloatTolerance;
  // Where the target's samples sit and the source's are read (a plane's Siting): pixel (i, j)'s
  // ray at (i + centre_x, j + centre_y), its position less (shift_x, shift_y).
  double centre_x = 0.5, centre_y = 0.5, shift_x = 0, shift_y = 0;
  // The lanes of the pair in one lane type: the target's of kind dst and the source's of kind
  // src (the others stay zero), and the rotation.
  template <class T>
  struct Lanes {
    struct {
      simd::PinholeRays<T> pinhole;
      simd::AxisRays<T> axis;  // equirect, cylindrical
      simd::CubeFaceRays<T> cube_face;
      simd::FisheyeRays<T> fisheye;
      simd::HammerRays<T> hammer;
      simd::BonneRays<T> bonne;
    } target;
    struct {
      simd::AxisSource<T> axis;  // equirect, cylindrical
      simd::CubemapSource<T> cubemap;
      simd::PinholeSource<T> pinhole;
      simd::FisheyeSource<T> fisheye;
      simd::MapPixels<T> map;  // Hammer, Aitoff, Bonne: the frame
      simd::HammerSource<T> hammer;
      simd::AitoffSource<T> aitoff;
      simd::BonneSource<T> bonne;
    } source;
    T rotation[9];  // row-major
  };
  Lanes<double> ld;
  Lanes<float> lf;  // the same, rounded to float
  template <class T>
  const Lanes<T>& lanes() const {
    if constexpr (std::is_same_v<T, float>) return lf;
    else return ld;
  }
};

// Describes the pair for one tile, its samples sited as siting says; false when the pair (or
// this tile: a cube tile spanning two face cells) is not supported.
bool simd_geometry_for(const Projection& src, const Projection& dst,
                       const Eigen::Matrix3d& rotation, const PixelRect& rect, SimdGeometry& g,
                       const Siting& siting = {});

// Fills out (a TileMap of rect's size) with the source positions of the tile's pixel centres;
// grid: interpolated between exact nodes where g.grid allows, as the fused uint8 converter.
void simd_map_tile(const SimdGeometry& g, const PixelRect& rect, TileMap& out, bool grid = false);

// Widens box {x0, y0, x1, y1} to the tile's valid source positions (the same positions, nothing
// stored: the footprint of a fused tile).
void simd_tile_bounds(const SimdGeometry& g, const PixelRect& rect, std::array<double, 4>& box);

}  // namespace panoproj
