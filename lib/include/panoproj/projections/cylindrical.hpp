#pragma once
// Cylindrical panoramic: lambda = lon0 + (x/W - 1/2) hfov around the vertical axis; the height on
// the unit cylinder is t = tan(phi), linear in y from tan(lat0 + vfov/2) (row 0) to
// tan(lat0 - vfov/2) (row H). Ray = normalize(sin lambda, -t, cos lambda). vfov < 180 degrees.
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"
#include "panoproj/projections/longitude_axis.hpp"

namespace panoproj {

class Cylindrical : public FramedBounds {
 public:
  Cylindrical(Size size, double hfov, double vfov, double lon0, double lat0)
      : FramedBounds(size), axis_(size.width, hfov, lon0), t_top_(std::tan(lat0 + 0.5 * vfov)),
        t_bottom_(std::tan(lat0 - 0.5 * vfov)) {}

  bool to_ray(double x, double y, Ray& d) const {
    const double lon = axis_.longitude_at(x);
    const double t = t_top_ + (y / static_cast<double>(size_.height)) * (t_bottom_ - t_top_);
    d = Ray(std::sin(lon), -t, std::cos(lon)).normalized();
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    const double rho = std::hypot(d.x(), d.z());
    if (!(rho > 0.0)) return false;  // the poles are at infinity
    if (!axis_.to_x(d, x)) return false;
    y = (-d.y() / rho - t_top_) / (t_bottom_ - t_top_) * static_cast<double>(size_.height);
    return in_frame(x, y, size_);
  }

  double center_density() const { return axis_.density(); }
  bool full_longitude() const { return axis_.full; }
  const LongitudeAxis& axis() const { return axis_; }
  double t_top() const { return t_top_; }  // heights of rows 0 and H on the unit cylinder
  double t_bottom() const { return t_bottom_; }

 private:
  LongitudeAxis axis_;
  double t_top_, t_bottom_;
};

}  // namespace panoproj
