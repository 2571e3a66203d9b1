#pragma once
// Pinhole (rectilinear) camera: x = cx + fx * X/Z, y = cy + fy * Y/Z, defined for Z > 0.
#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

class Pinhole : public FramedBounds {
 public:
  // fx, fy: focal lengths in pixels; cx, cy: principal point in panoproj's pixel convention.
  Pinhole(Size size, double fx, double fy, double cx, double cy)
      : FramedBounds(size), fx_(fx), fy_(fy), cx_(cx), cy_(cy) {}

  bool to_ray(double x, double y, Ray& d) const {
    d = Ray((x - cx_) / fx_, (y - cy_) / fy_, 1.0).normalized();
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    if (!(d.z() > 0.0)) return false;
    x = cx_ + fx_ * (d.x() / d.z());
    y = cy_ + fy_ * (d.y() / d.z());
    return in_frame(x, y, size_);
  }

  double center_density() const { return fx_; }  // pixels per radian on the optical axis
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }

 private:
  double fx_, fy_, cx_, cy_;
};

}  // namespace panoproj
