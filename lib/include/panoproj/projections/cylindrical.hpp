#pragma once
// Cylindrical panoramic: lambda = lon0 + (x/W - 1/2) hfov around the vertical axis; the height on
// the unit cylinder is t = tan(phi), linear in y from tan(lat0 + vfov/2) (row 0) to
// tan(lat0 - vfov/2) (row H). Ray = normalize(sin lambda, -t, cos lambda). vfov < 180 degrees.
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

class Cylindrical {
 public:
  Cylindrical(Size size, double hfov, double vfov, double lon0, double lat0)
      : size_(size), hfov_(hfov), lon0_(lon0), t_top_(std::tan(lat0 + 0.5 * vfov)),
        t_bottom_(std::tan(lat0 - 0.5 * vfov)), full_lon_(hfov >= kTwoPi * (1.0 - 1e-12)) {}

  bool to_ray(double x, double y, Ray& d) const {
    const double lon = lon0_ + (x / static_cast<double>(size_.width) - 0.5) * hfov_;
    const double t = t_top_ + (y / static_cast<double>(size_.height)) * (t_bottom_ - t_top_);
    d = Ray(std::sin(lon), -t, std::cos(lon)).normalized();
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    const double rho = std::hypot(d.x(), d.z());
    if (!(rho > 0.0)) return false;  // the poles are at infinity
    const double lon = wrap_pi(longitude(d) - lon0_);
    if (!full_lon_ && std::fabs(lon) > 0.5 * hfov_ * (1.0 + kEdgeSlack)) return false;
    x = (lon / hfov_ + 0.5) * static_cast<double>(size_.width);
    y = (-d.y() / rho - t_top_) / (t_bottom_ - t_top_) * static_cast<double>(size_.height);
    return in_frame(x, y, size_);
  }

  // Whether pixel position (x, y) has a ray (cheap form of to_ray's test).
  bool contains(double x, double y) const { return in_frame(x, y, size_); }

  // True only if every position in [x0, x1] x [y0, y1] has a ray (used to skip per-pixel tests).
  bool covers(double x0, double y0, double x1, double y1) const {
    return in_frame(x0, y0, size_) && in_frame(x1, y1, size_);
  }
  Size size() const { return size_; }
  double center_density() const { return static_cast<double>(size_.width) / hfov_; }
  bool full_longitude() const { return full_lon_; }

 private:
  Size size_;
  double hfov_, lon0_, t_top_, t_bottom_;
  bool full_lon_;
};

}  // namespace panoproj
