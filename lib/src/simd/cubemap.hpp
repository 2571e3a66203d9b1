#pragma once
// A cubemap's SIMD lanes (vector forms in cubemap-inl.h).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "panoproj/projections/cubemap.hpp"
#include "geometry/tile_map.hpp"
#include "simd/lanes.hpp"

namespace panoproj::simd {

// As a target, one face: a = (x - ox) 2 / F - 1, b = (y - oy) 2 / F - 1 and the ray fwd + a right
// + b down, the basis rotated (the rays come rotated).
template <class T>
struct CubeFaceRays {
  T ox, oy, two_over_f;
  T fwd[3], right[3], down[3];
};

// Returns false unless the whole tile lies inside one face's cell.
template <class T>
bool describe(const Cubemap& c, const TileRect& rect, const Eigen::Matrix3d& rotation, CubeFaceRays<T>& l) {
  const int f = c.face_at(static_cast<double>(rect.x0) + 0.5, static_cast<double>(rect.y0) + 0.5);
  if (f < 0) return false;
  const auto o = c.face_origin(f);
  if (rect.x0 + rect.w > o[0] + c.face_size() || rect.y0 + rect.h > o[1] + c.face_size()) return false;
  const CubeFace& cf = cube_faces()[f];
  const Eigen::Vector3d fwd = rotation * cf.fwd, right = rotation * cf.right, down = rotation * cf.down;
  l.ox = lane<T>(o[0]);
  l.oy = lane<T>(o[1]);
  l.two_over_f = lane<T>(2.0 / static_cast<double>(c.face_size()));
  for (int i = 0; i < 3; ++i) {
    l.fwd[i] = lane<T>(fwd[i]);
    l.right[i] = lane<T>(right[i]);
    l.down[i] = lane<T>(down[i]);
  }
  return true;
}

// As a source: the face of the ray's largest component, its cell's origin (ox, oy)[face] and
// position half_face (a + 1) within it, F = face.
template <class T>
struct CubemapSource {
  T face, half_face;
  T ox[6], oy[6];
};

// Returns whether float lanes serve: a = an / depth, both with the ray's error (depth >= |ray| /
// sqrt(3)), plus rounding.
template <class T>
bool describe(const Cubemap& c, CubemapSource<T>& l) {
  const double f = static_cast<double>(c.face_size());
  l.face = lane<T>(f);
  l.half_face = lane<T>(0.5 * f);
  for (int i = 0; i < 6; ++i) {
    l.ox[i] = lane<T>(c.face_origin(i)[0]);
    l.oy[i] = lane<T>(c.face_origin(i)[1]);
  }
  const Size frame = c.size();
  return static_cast<double>(std::max(frame.width, frame.height)) * kHalfUlp +
             0.5 * f * 2 * std::sqrt(3.0) * kFloatRayError <=
         kFloatTolerance;
}

}  // namespace panoproj::simd
