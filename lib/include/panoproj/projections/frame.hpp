#pragma once
// Image frame helpers shared by the projections: size, bounds test with a tolerance.
#include <cstdint>

namespace panoproj {

struct Size {
  int64_t width = 0;
  int64_t height = 0;
  bool operator==(const Size&) const = default;
};

// Relative slack for "on the rim/outline" tests, so that a pixel produced by to_pixel at the
// closed frame's edge (x == W) or a ray produced by to_ray at the rim is accepted back.
inline constexpr double kEdgeSlack = 1e-9;

// Inside the closed frame [0, W] x [0, H] (false for NaN).
inline bool in_frame(double x, double y, const Size& s) {
  const double tx = kEdgeSlack * static_cast<double>(s.width);
  const double ty = kEdgeSlack * static_cast<double>(s.height);
  return x >= -tx && x <= static_cast<double>(s.width) + tx && y >= -ty &&
         y <= static_cast<double>(s.height) + ty;
}

}  // namespace panoproj
