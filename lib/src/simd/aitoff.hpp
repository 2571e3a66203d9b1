#pragma once
// Aitoff's SIMD lanes, as a source only (vector form in aitoff-inl.h): as a target it has no
// closed-form inverse, and a Newton iteration per pixel costs more than the tile mapper's
// interpolation between exact nodes.
#include <algorithm>

#include "panoproj/projections/aitoff.hpp"
#include "simd/map_frame.hpp"

namespace panoproj::simd {

// Float lanes are coarse where 1 - h < coarse_rest (h = sin^2(alpha / 2), aitoff.hpp). (The
// frame in MapPixels.)
template <class T>
struct AitoffSource {
  T coarse_rest;
};

// Returns whether float lanes serve: the plane position's error is the ray's through plane
// scales of a few units (measured in tests/simd_geometry_test.cpp), plus rounding; X and Y scale
// with 1 / sqrt(1 - h), their error with eps / (1 - h).
template <class T>
bool describe(const Aitoff& m, AitoffSource<T>& l) {
  const double spread = pixels_per_unit(m.frame()) * 4 * kFloatRayError;
  const double room = kFloatTolerance - rounding(m.frame()) - spread;
  l.coarse_rest = lane<T>(spread / std::max(room, 1e-300));
  return room > 0;
}

}  // namespace panoproj::simd
