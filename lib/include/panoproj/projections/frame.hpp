#pragma once
// Image frame helpers shared by the projections: the bounds test with a tolerance.
#include <cstdint>

#include "panoproj/image.hpp"  // Size

namespace panoproj {

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

// Validity for projections whose every in-frame position has a ray (pinhole, equirect,
// cylindrical): their contains() and covers() are the frame test.
class FramedBounds {
 public:
  explicit FramedBounds(Size size) : size_(size) {}
  // Whether pixel position (x, y) has a ray (cheap form of to_ray's test).
  bool contains(double x, double y) const { return in_frame(x, y, size_); }
  // True only if every position in [x0, x1] x [y0, y1] has a ray (used to skip per-pixel tests).
  bool covers(double x0, double y0, double x1, double y1) const {
    return in_frame(x0, y0, size_) && in_frame(x1, y1, size_);
  }
  Size size() const { return size_; }

 protected:
  Size size_;
};

}  // namespace panoproj
