#pragma once
// Bonne, equal-area, standard parallel phi1 (Snyder, PP 1395, eq. 19-1..19-5):
//   rho = cot phi1 + phi1 - phi,  E = lambda cos phi / rho,
//   X = rho sin E,  Y = cot phi1 - rho cos E        (origin at lambda = 0, phi = phi1).
// cot phi1 overflows as phi1 -> 0, where Bonne tends to the sinusoidal projection
// (X = lambda cos phi, Y = phi). For |phi1| < kSmallPhi1 the same equations are written with
// q = 1/rho = t / (1 + t (phi1 - phi)), t = tan phi1, which stays finite at phi1 = 0:
//   X = lambda cos phi sinc(E),  Y = (phi - phi1) + lambda cos phi sin(E/2) sinc(E/2).
// A southern phi1 is the mirror image (phi -> -phi, Y -> -Y). phi1 = 90 degrees is Werner's.
#include <cmath>

#include "panoproj/projections/map_frame.hpp"

namespace panoproj {

class Bonne : public MapProjection<Bonne> {
 public:
  static constexpr bool kConvexOutline = false;  // the heart's notch
  static constexpr double kSmallPhi1 = 0.1;  // radians; both forms are exact on either side

  Bonne(Size size, double phi1, double lon0);

  void forward(double lam, double phi, double& X, double& Y) const {
    phi *= sign_;
    const double cp = std::cos(phi);
    if (small_) {
      const double q = t_ / (1.0 + t_ * (p1_ - phi));
      const double lc = lam * cp, E = lc * q;
      X = lc * sinc(E);
      Y = (phi - p1_) + lc * std::sin(0.5 * E) * sinc(0.5 * E);
    } else {
      const double rho = cot_ + p1_ - phi;
      const double E = rho > 1e-300 ? lam * cp / rho : lam;  // Werner's apex: cos phi / rho -> 1
      X = rho * std::sin(E);
      Y = cot_ - rho * std::cos(E);
    }
    Y *= sign_;
  }
  bool inside(double X, double Y) const {
    double lam, phi;
    return inverse(X, Y, lam, phi);
  }
  // False outside the outline.
  bool inverse(double X, double Y, double& lam, double& phi) const {
    Y *= sign_;
    double rho_e_over_cos;  // rho * E, to be divided by cos phi
    if (small_) {
      const double a = 1.0 - t_ * Y;
      const double root = std::sqrt(t_ * t_ * X * X + a * a);
      phi = p1_ + (2.0 * Y - t_ * (X * X + Y * Y)) / (1.0 + root);
      const double e_over_t = t_ > 1e-150 ? std::atan2(t_ * X, a) / t_ : X;
      rho_e_over_cos = root * e_over_t;
    } else {
      const double cy = cot_ - Y;
      const double rho = std::hypot(X, cy);
      phi = cot_ + p1_ - rho;
      rho_e_over_cos = rho * std::atan2(X, cy);
    }
    if (std::fabs(phi) > kHalfPi * (1.0 + kEdgeSlack)) return false;
    phi = std::fmin(kHalfPi, std::fmax(-kHalfPi, phi));
    const double cp = std::cos(phi);
    lam = cp > 1e-15 ? rho_e_over_cos / cp : 0.0;  // at a pole every longitude is one point
    phi *= sign_;
    return std::fabs(lam) <= kPi * (1.0 + kEdgeSlack);
  }

  // The parameters of the forms above (for the vector geometry): |phi1|, the mirror sign,
  // tan |phi1|, cot |phi1| (0 in the small form), and whether the 1/rho form is used.
  double abs_phi1() const { return p1_; }
  double mirror() const { return sign_; }
  double tan_phi1() const { return t_; }
  double cot_phi1() const { return cot_; }
  bool small_form() const { return small_; }

 private:
  double p1_, sign_, t_, cot_;
  bool small_;
};

}  // namespace panoproj
