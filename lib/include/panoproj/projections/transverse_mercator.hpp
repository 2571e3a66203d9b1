#pragma once
// Transverse Mercator on a sphere (Snyder, PP 1395, eq. 8-1..8-3 and 8-6..8-7), the central
// meridian lambda = 0 the line X = 0:
//   B = cos phi sin lambda,  X = atanh(B),  Y = atan2(sin phi, cos phi cos lambda);
// X is computed as asinh(B / hypot(sin phi, cos phi cos lambda)): the same, without atanh's
// cancellation near |B| = 1 (hypot is sqrt(1 - B^2) from the ray's other two components).
//   phi = asin(sin Y / cosh X),  lambda = atan2(sinh X, cos Y).
// Y covers the whole great circle through the poles (-pi, pi]; X grows without bound towards the
// two points 90 degrees off the central meridian on the equator, so the map ends at
// |X| <= atanh(sin x_max) = asinh(tan x_max) (the latter finite up to x_max's last double below
// 90 degrees, where sin rounds to 1): x_max is the angle from the central meridian (Mercator's
// phi_max, turned a quarter).
#include <cmath>

#include "panoproj/projections/map_frame.hpp"

namespace panoproj {

class TransverseMercator : public MapProjection<TransverseMercator> {
 public:
  static constexpr bool kConvexOutline = true;  // a rectangle

  TransverseMercator(Size size, double x_max, double lon0)
      : MapProjection(lon0), x_max_(x_max), X_max_(std::asinh(std::tan(x_max))) {
    frame_ = {size, -X_max_, X_max_, -kPi, kPi};
  }

  void forward(double lam, double phi, double& X, double& Y) const {
    const double cp = std::cos(phi), sp = std::sin(phi), cc = cp * std::cos(lam);
    const double rest = std::hypot(sp, cc);
    X = rest > 0 ? std::asinh(cp * std::sin(lam) / rest) : std::copysign(HUGE_VAL, lam);
    if (std::fabs(X) > X_max_ * (1.0 + kEdgeSlack)) X = std::copysign(HUGE_VAL, X);  // past x_max: off the map
    Y = std::atan2(sp, cc);
  }
  bool inside(double X, double Y) const {
    return std::fabs(X) <= X_max_ * (1.0 + kEdgeSlack) && std::fabs(Y) <= kPi * (1.0 + kEdgeSlack);
  }
  bool inverse(double X, double Y, double& lam, double& phi) const {
    if (!inside(X, Y)) return false;
    // The unit vector (sinh X, sin Y, cos Y) / cosh X in (east, north, the central meridian's
    // equator point): atan2 keeps phi exact near the poles.
    const double sy = std::sin(Y), cy = std::cos(Y), sh = std::sinh(X);
    phi = std::atan2(sy, std::hypot(sh, cy));
    lam = std::atan2(sh, cy);
    return true;
  }
  double x_max() const { return x_max_; }

 private:
  double x_max_, X_max_;
};

}  // namespace panoproj
