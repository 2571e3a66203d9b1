#pragma once
// The normal cylindrical world maps, X = lambda and Y = f(phi) up to |phi| <= phi_max
// (Snyder, "Map Projections: A Working Manual", USGS PP 1395, on a unit sphere):
//   mercator                Y = asinh(tan phi)                 phi = atan(sinh Y)           (eq. 7-2)
//   miller                  Y = 1.25 asinh(tan(0.8 phi))       phi = atan(sinh(0.8 Y)) / 0.8 (eq. 11-1)
// (asinh(tan phi) = atanh(sin phi), without atanh's cancellation near the poles)
//   cylindrical-equal-area  Y = sin phi / cos^2 phi_s          phi = asin(Y cos^2 phi_s)    (eq. 10-1)
// The equal-area form is Snyder's (lambda cos phi_s, sin phi / cos phi_s) over cos phi_s, so that the
// equator keeps unit scale like the others (the shape, and so the pixels, are the same).
#include <cmath>

#include "panoproj/projections/map_frame.hpp"

namespace panoproj {

enum class CylindricalLaw { Mercator, Miller, EqualArea };

class CylindricalMap : public MapProjection<CylindricalMap> {
 public:
  static constexpr bool kConvexOutline = true;  // a rectangle

  // phi_max: the latitude the map ends at (radians; < pi/2 for Mercator); phi_s: the equal-area
  // form's standard parallel.
  CylindricalMap(Size size, CylindricalLaw law, double phi_max, double phi_s, double lon0)
      : MapProjection(lon0), law_(law), phi_max_(phi_max), phi_s_(phi_s), k_(1.0 / std::pow(std::cos(phi_s), 2)) {
    const double y_max = y_of(phi_max);
    frame_ = {size, -kPi, kPi, -y_max, y_max};
  }

  void forward(double lam, double phi, double& X, double& Y) const {
    X = lam;
    Y = std::fabs(phi) <= phi_max_ * (1.0 + kEdgeSlack) ? y_of(phi) : std::copysign(HUGE_VAL, phi);
  }
  bool inside(double X, double Y) const { return std::fabs(X) <= kPi * (1.0 + kEdgeSlack) && std::fabs(Y) <= frame_y_max(); }
  bool inverse(double X, double Y, double& lam, double& phi) const {
    if (!inside(X, Y)) return false;
    lam = X;
    phi = 0.0;
    switch (law_) {
      case CylindricalLaw::Mercator: phi = std::atan(std::sinh(Y)); break;
      case CylindricalLaw::Miller: phi = std::atan(std::sinh(0.8 * Y)) / 0.8; break;
      case CylindricalLaw::EqualArea: phi = std::asin(std::fmax(-1.0, std::fmin(1.0, Y / k_))); break;
    }
    return true;
  }

  CylindricalLaw law() const { return law_; }
  double phi_max() const { return phi_max_; }
  double phi_s() const { return phi_s_; }
  double y_max() const { return y_of(phi_max_); }  // the outline's top, Y at phi_max

 private:
  double y_of(double phi) const {
    switch (law_) {
      case CylindricalLaw::Mercator: return std::asinh(std::tan(phi));
      case CylindricalLaw::Miller: return 1.25 * std::asinh(std::tan(0.8 * phi));
      case CylindricalLaw::EqualArea: return std::sin(phi) * k_;
    }
    return 0.0;
  }
  double frame_y_max() const { return y_of(phi_max_) * (1.0 + kEdgeSlack); }

  CylindricalLaw law_;
  double phi_max_, phi_s_, k_;
};

}  // namespace panoproj
