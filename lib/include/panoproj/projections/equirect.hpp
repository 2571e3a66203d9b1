#pragma once
// Equirectangular (spherical panoramic), full or partial:
//   lambda = lon0 + (x/W - 1/2) hfov,  phi = lat0 + (1/2 - y/H) vfov.
// Full (hfov = 360): x = 0 and x = W are one meridian, the seam; to_pixel returns x in [0, W).
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

class Equirect {
 public:
  Equirect(Size size, double hfov, double vfov, double lon0, double lat0)
      : size_(size), hfov_(hfov), vfov_(vfov), lon0_(lon0), lat0_(lat0),
        lat_top_(lat0 + 0.5 * vfov), full_lon_(hfov >= kTwoPi * (1.0 - 1e-12)) {}

  bool to_ray(double x, double y, Ray& d) const {
    const double lon = lon0_ + (x / static_cast<double>(size_.width) - 0.5) * hfov_;
    const double lat = lat_top_ - (y / static_cast<double>(size_.height)) * vfov_;
    d = ray_from_lonlat(lon, lat);
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    const double lon = wrap_pi(longitude(d) - lon0_);
    if (!full_lon_ && std::fabs(lon) > 0.5 * hfov_ * (1.0 + kEdgeSlack)) return false;
    x = (lon / hfov_ + 0.5) * static_cast<double>(size_.width);
    y = (lat_top_ - latitude(d)) / vfov_ * static_cast<double>(size_.height);
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
  // With a full circle of longitude, a frame edge at a pole can be crossed by interpolation taps.
  bool reaches_north_pole() const { return full_lon_ && lat_top_ >= kHalfPi * (1.0 - 1e-12); }
  bool reaches_south_pole() const {
    return full_lon_ && lat_top_ - vfov_ <= -kHalfPi * (1.0 - 1e-12);
  }

 private:
  Size size_;
  double hfov_, vfov_, lon0_, lat0_, lat_top_;
  bool full_lon_;
};

}  // namespace panoproj
