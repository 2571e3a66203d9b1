#pragma once
// Equirectangular (spherical panoramic), full or partial:
//   lambda = lon0 + (x/W - 1/2) hfov,  phi = lat0 + (1/2 - y/H) vfov.
// Full (hfov = 360): x = 0 and x = W are one meridian, the seam; to_pixel returns x in [0, W).
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"
#include "panoproj/projections/longitude_axis.hpp"

namespace panoproj {

class Equirect : public FramedBounds {
 public:
  Equirect(Size size, double hfov, double vfov, double lon0, double lat0)
      : FramedBounds(size), axis_(size.width, hfov, lon0), vfov_(vfov), lat_top_(lat0 + 0.5 * vfov) {}

  bool to_ray(double x, double y, Ray& d) const {
    const double lat = lat_top_ - (y / static_cast<double>(size_.height)) * vfov_;
    d = ray_from_lonlat(axis_.longitude_at(x), lat);
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    if (!axis_.to_x(d, x)) return false;
    y = (lat_top_ - latitude(d)) / vfov_ * static_cast<double>(size_.height);
    return in_frame(x, y, size_);
  }

  double center_density() const { return axis_.density(); }
  const LongitudeAxis& axis() const { return axis_; }
  double lat_top() const { return lat_top_; }
  double vfov() const { return vfov_; }
  bool full_longitude() const { return axis_.full; }
  // With a full circle of longitude, a frame edge at a pole can be crossed by interpolation taps.
  bool reaches_north_pole() const { return axis_.full && lat_top_ >= kHalfPi * (1.0 - 1e-12); }
  bool reaches_south_pole() const {
    return axis_.full && lat_top_ - vfov_ <= -kHalfPi * (1.0 - 1e-12);
  }

 private:
  LongitudeAxis axis_;
  double vfov_, lat_top_;
};

}  // namespace panoproj
