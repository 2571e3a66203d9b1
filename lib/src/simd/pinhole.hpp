#pragma once
// A pinhole's SIMD lanes (vector forms in pinhole-inl.h).
#include <Eigen/Core>
#include <algorithm>

#include "panoproj/projections/pinhole.hpp"
#include "simd/lanes.hpp"

namespace panoproj::simd {

// As a target: u = (x - cx) / fx, v = (y - cy) / fy and the rotation's columns, so the rays
// u col0 + v col1 + col2 come rotated.
template <class T>
struct PinholeRays {
  T inv_fx, inv_fy, cx, cy;
  T col0[3], col1[3], col2[3];
};

template <class T>
void describe(const Pinhole& p, const Eigen::Matrix3d& rotation, PinholeRays<T>& l) {
  l.inv_fx = lane<T>(1.0 / static_cast<double>(p.fx()));
  l.inv_fy = lane<T>(1.0 / static_cast<double>(p.fy()));
  l.cx = lane<T>(p.cx());
  l.cy = lane<T>(p.cy());
  for (int i = 0; i < 3; ++i) {
    l.col0[i] = lane<T>(rotation(i, 0));
    l.col1[i] = lane<T>(rotation(i, 1));
    l.col2[i] = lane<T>(rotation(i, 2));
  }
}

// As a source: x = cx + fx x / z, y = cy + fy y / z; float lanes err by f eps (1 + t^2) with
// t^2 = (x^2 + y^2) / z^2, coarse beyond max_t2.
template <class T>
struct PinholeSource {
  T width, height, fx, fy, cx, cy, max_t2;
};

// Returns whether float lanes serve (at least out to 45 degrees).
template <class T>
bool describe(const Pinhole& p, PinholeSource<T>& l) {
  const double w = static_cast<double>(p.size().width), h = static_cast<double>(p.size().height);
  const double f = std::max(p.fx(), p.fy());
  const double t2 = (kFloatTolerance - std::max(w, h) * kHalfUlp) / (f * kFloatRayError) - 1.0;
  l = {lane<T>(w), lane<T>(h), lane<T>(p.fx()), lane<T>(p.fy()),
       lane<T>(p.cx()), lane<T>(p.cy()), lane<T>(std::max(t2, 0.0))};
  return t2 > 1.0;
}

}  // namespace panoproj::simd
