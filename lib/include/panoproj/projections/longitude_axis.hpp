#pragma once
// The horizontal axis of equirect and cylindrical panoramas: longitude linear in x,
//   lambda = lon0 + (x/W - 1/2) hfov,
// a full circle (hfov = 360) wrapping at the seam (x = 0 and x = W are one meridian; to_x returns
// x in [0, W)), a partial one refusing longitudes outside its span.
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

struct LongitudeAxis {
  double width, hfov, lon0;
  bool full;

  LongitudeAxis(int64_t w, double hfov_rad, double lon0_rad)
      : width(static_cast<double>(w)), hfov(hfov_rad), lon0(lon0_rad),
        full(hfov_rad >= kTwoPi * (1.0 - 1e-12)) {}

  double longitude_at(double x) const { return lon0 + (x / width - 0.5) * hfov; }
  // False where the ray's longitude is outside a partial span.
  bool to_x(const Ray& d, double& x) const {
    const double lon = wrap_pi(longitude(d) - lon0);
    if (!full && std::fabs(lon) > 0.5 * hfov * (1.0 + kEdgeSlack)) return false;
    x = (lon / hfov + 0.5) * width;
    return true;
  }
  double density() const { return width / hfov; }  // pixels per radian
};

}  // namespace panoproj
