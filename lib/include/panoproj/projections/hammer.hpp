#pragma once
// Hammer-Wagner family with parameter W (Hammer: W = 1/2; Eckert-Greifendorff: W = 1/4):
//   (X W, Y) is the Lambert azimuthal equal-area image of (lambda W, phi):
//   d = sqrt(2 / (1 + cos phi cos(lambda W))),  X = d cos phi sin(lambda W) / W,  Y = d sin phi.
// Inverse through LAEA's (Snyder, "Map Projections: A Working Manual", USGS PP 1395, eq. 24-2..):
//   rho^2 = (XW)^2 + Y^2 (< 4),  sin c / rho = sqrt(1 - rho^2/4),  cos c = 1 - rho^2/2,
//   phi = asin(Y sin c / rho),  lambda W = atan2(XW sin c / rho, cos c),
// written without dividing by rho, and phi by atan2 of the same unit vector. The outline is |lambda| = pi.
#include <cmath>

#include "panoproj/projections/map_frame.hpp"

namespace panoproj {

class Hammer : public MapProjection<Hammer> {
 public:
  static constexpr bool kConvexOutline = false;  // not shown for every W
  // The box: |X| to the outline's equator point (X grows with lambda there); |Y| to the pole's
  // sqrt 2 for W <= 1/2, else to the outline's highest point, where (with c = cos(pi W) < 0)
  // Y^2 = 2 sin^2 phi / (1 + c cos phi) peaks at cos phi = (sqrt(1 - c^2) - 1) / c.
  Hammer(Size size, double w, double lon0) : MapProjection(lon0), w_(w) {
    const double x_max = forward_x(kPi, 0.0), c = std::cos(kPi * w);
    double y_max = std::sqrt(2.0);
    if (c < 0) {
      const double u = (std::sqrt(1.0 - c * c) - 1.0) / c;
      y_max = std::sqrt(2.0 * (1.0 - u * u) / (1.0 + c * u));
    }
    frame_ = {size, -x_max, x_max, -y_max, y_max};
  }

  double w() const { return w_; }

  // Plane coordinates of (lambda, phi) relative to the central meridian.
  void forward(double lam, double phi, double& X, double& Y) const {
    const double cp = std::cos(phi), lw = lam * w_;
    const double d = std::sqrt(2.0 / (1.0 + cp * std::cos(lw)));
    X = d * cp * std::sin(lw) / w_;
    Y = d * std::sin(phi);
  }
  // Inside the outline (|lambda| <= pi): the closed-form inverse succeeds.
  bool inside(double X, double Y) const {
    double lam, phi;
    return inverse(X, Y, lam, phi);
  }
  // False outside the outline.
  bool inverse(double X, double Y, double& lam, double& phi) const {
    const double xw = X * w_;
    const double rho2 = xw * xw + Y * Y;
    if (rho2 > 4.0) return false;
    // The unit vector (XW k, Y k, cos c) with k = sin c / rho; atan2 keeps full precision
    // near the poles, where asin(Y k) loses half the digits.
    const double k = std::sqrt(1.0 - 0.25 * rho2), cos_c = 1.0 - 0.5 * rho2;
    phi = std::atan2(Y * k, std::hypot(xw * k, cos_c));
    lam = std::atan2(xw * k, cos_c) / w_;
    return std::fabs(lam) <= kPi * (1.0 + kEdgeSlack);
  }


 private:
  double forward_x(double lam, double phi) const {
    double X, Y;
    forward(lam, phi, X, Y);
    return X;
  }
  double w_;
};

}  // namespace panoproj
