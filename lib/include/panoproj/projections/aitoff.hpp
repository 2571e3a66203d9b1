#pragma once
// Aitoff: with cos(alpha) = cos phi cos(lambda/2),
//   X = 2 cos phi sin(lambda/2) / sinc(alpha),  Y = sin phi / sinc(alpha)
// (Snyder, "Flattening the Earth", 1993, p. 131). Its outline is the ellipse
// (X/pi)^2 + (Y/(pi/2))^2 = 1. No closed-form inverse: a safeguarded Newton iteration runs only
// for points inside the outline, seeded by the Hammer inverse of the same point (same outline,
// scaled), with an analytic Jacobian and step halving; it stops at |residual| < 1e-12.
#include <cmath>

#include "panoproj/projections/hammer.hpp"
#include "panoproj/projections/map_frame.hpp"

namespace panoproj {

class Aitoff : public MapProjection<Aitoff> {
 public:
  static constexpr bool kConvexOutline = true;  // an ellipse
  static constexpr int kMaxIterations = 40;
  static constexpr double kTolerance = 1e-12;

  Aitoff(Size size, double lon0)
      : MapProjection(lon0, {size, -kPi, kPi, -kHalfPi, kHalfPi}), seed_(size, 0.5, 0.0) {}

  // Also returns the Jacobian d(X, Y)/d(lambda, phi) when J is given (row-major 2x2).
  static void forward(double lam, double phi, double& X, double& Y, double* J = nullptr) {
    const double cp = std::cos(phi), sp = std::sin(phi);
    const double sl = std::sin(0.5 * lam), cl = std::cos(0.5 * lam);
    // h = (1 - cos alpha)/2 = sin^2(phi/2) + cos phi sin^2(lambda/4): exact near alpha = 0.
    const double s2 = std::sin(0.5 * phi), s4 = std::sin(0.25 * lam);
    const double h = std::fmin(1.0, s2 * s2 + cp * s4 * s4);
    const double alpha = 2.0 * std::asin(std::sqrt(h));
    const double g = 1.0 / sinc(alpha);  // alpha / sin(alpha)
    X = 2.0 * cp * sl * g;
    Y = sp * g;
    if (!J) return;
    // dg/dD with D = cos alpha: -(sin a - a cos a) / sin^3 a; series -(1/3 + 2 a^2/15) near 0.
    double gp;
    if (alpha < 1e-4) {
      gp = -(1.0 / 3.0 + 2.0 * alpha * alpha / 15.0);
    } else {
      const double sa = std::sin(alpha);
      gp = -(sa - alpha * std::cos(alpha)) / (sa * sa * sa);
    }
    const double dD_dlam = -0.5 * cp * sl, dD_dphi = -sp * cl;
    J[0] = cp * cl * g + 2.0 * cp * sl * gp * dD_dlam;         // dX/dlambda
    J[1] = -2.0 * sp * sl * g + 2.0 * cp * sl * gp * dD_dphi;  // dX/dphi
    J[2] = sp * gp * dD_dlam;                                  // dY/dlambda
    J[3] = cp * g + sp * gp * dD_dphi;                         // dY/dphi
  }

  bool inside(double X, double Y) const { return inside_outline(X, Y); }
  static bool inside_outline(double X, double Y) {
    const double u = X / kPi, v = Y / kHalfPi;
    return u * u + v * v <= 1.0 + kEdgeSlack;
  }

  bool inverse(double X, double Y, double& lam, double& phi) const {
    return newton_inverse(X, Y, lam, phi) >= 0;
  }
  // Newton inverse; returns the iteration count used (0 when the seed already fits), or -1
  // outside the outline.
  int newton_inverse(double X, double Y, double& lam, double& phi) const {
    if (!inside_outline(X, Y)) return -1;
    constexpr double kToHammer = 2.0 * 1.4142135623730951 / kPi;  // outline pi -> 2 sqrt 2
    if (!seed_.inverse(X * kToHammer, Y * kToHammer, lam, phi)) {
      lam = std::copysign(kPi, X);  // on the outline within rounding
      phi = std::asin(std::fmin(1.0, std::fabs(Y) / kHalfPi)) * (Y < 0 ? -1.0 : 1.0);
    }
    double fx, fy, J[4];
    forward(lam, phi, fx, fy, J);
    double err = std::hypot(fx - X, fy - Y);
    int it = 0;
    for (; it < kMaxIterations && err > kTolerance; ++it) {
      const double det = J[0] * J[3] - J[1] * J[2];
      if (!(std::fabs(det) > 1e-300)) break;  // singular (a pole): the seed's answer stands
      const double rx = X - fx, ry = Y - fy;
      double dl = (J[3] * rx - J[1] * ry) / det, dp = (-J[2] * rx + J[0] * ry) / det;
      bool improved = false;
      for (int halve = 0; halve < 30; ++halve, dl *= 0.5, dp *= 0.5) {
        const double nl = std::fmin(kPi, std::fmax(-kPi, lam + dl));
        const double np = std::fmin(kHalfPi, std::fmax(-kHalfPi, phi + dp));
        double nx, ny, nJ[4];
        forward(nl, np, nx, ny, nJ);
        const double nerr = std::hypot(nx - X, ny - Y);
        if (nerr < err) {
          lam = nl, phi = np, fx = nx, fy = ny, err = nerr;
          std::copy(nJ, nJ + 4, J);
          improved = true;
          break;
        }
      }
      if (!improved) break;
    }
    return it;
  }


 private:
  Hammer seed_;
};

}  // namespace panoproj
