#pragma once
// Mollweide (Snyder, PP 1395, eq. 31-1..31-3, 31-8..31-10): with the auxiliary angle theta,
//   2 theta + sin 2 theta = pi sin phi,  X = (2 sqrt 2 / pi) lambda cos theta,  Y = sqrt 2 sin theta.
// The forward equation has no closed form. Written in delta = pi/2 - |theta| it is
//   h(2 delta) = pi (1 - sin|phi|) = pi cos^2 phi / (1 + sin|phi|),  h(u) = u - sin u,
// free of cancellation near the poles (h by its series below u = 0.5), solved by a Newton
// iteration kept inside its bracket [0, pi/2] (h' = 2 sin^2(u/2) > 0: one root), seeded by
// h(u) ~ u^3 / 6 (at most 4 iterations in panoproj stability; 6 asserted over every latitude). The inverse is closed: delta = acos(|Y| / sqrt 2), phi from the same h.
// The outline is the ellipse (X / 2 sqrt 2)^2 + (Y / sqrt 2)^2 = 1.
#include <cmath>

#include "panoproj/projections/map_frame.hpp"

namespace panoproj {

class Mollweide : public MapProjection<Mollweide> {
 public:
  static constexpr bool kConvexOutline = true;  // an ellipse
  static constexpr int kMaxIterations = 60;
  static constexpr double kSqrt2 = 1.4142135623730951;

  Mollweide(Size size, double lon0) : MapProjection(lon0, {size, -2 * kSqrt2, 2 * kSqrt2, -kSqrt2, kSqrt2}) {}

  // Pixels per radian along the equator at the centre (X = (2 sqrt 2 / pi) lambda there).
  double center_density() const { return frame_.density() * 2.0 * kSqrt2 / kPi; }

  // h(u) = u - sin u, exact near 0.
  static double h(double u) {
    if (u > 0.5) return u - std::sin(u);
    // u^3/6 (1 - u^2/20 (1 - u^2/42 (...))): the term after the last is under 1e-16 of the sum
    const double u2 = u * u;
    return u * u2 / 6.0 *
           (1.0 - u2 / 20.0 * (1.0 - u2 / 42.0 * (1.0 - u2 / 72.0 * (1.0 - u2 / 110.0 * (1.0 - u2 / 156.0 * (1.0 - u2 / 210.0))))));
  }
  // delta = pi/2 - |theta| for a latitude with cos phi = c, sin |phi| = s; also the iterations.
  static double delta_of(double c, double s, int* iterations = nullptr) {
    const double rhs = kPi * c * c / (1.0 + s);  // pi (1 - sin|phi|), in [0, pi]
    double lo = 0.0, hi = kHalfPi;
    double u = std::fmin(kPi, std::cbrt(6.0 * rhs));  // u = 2 delta
    int it = 0;
    for (; it < kMaxIterations; ++it) {
      const double f = h(u) - rhs;
      if (f == 0.0) break;
      if (f > 0) hi = 0.5 * u; else lo = 0.5 * u;
      const double sh = std::sin(0.5 * u), dfdu = 2.0 * sh * sh;
      double next = dfdu > 0 ? u - f / dfdu : -1.0;
      // Within a few ulp (f's rounding, 1e-17 near u = 0.4, moves the root by ~1e-15 u), or the
      // bracket closed on it: further steps would only oscillate.
      if (std::fabs(next - u) <= 4e-15 * u || hi - lo <= 2e-16 * u) {
        u = next;
        break;
      }
      // h is convex: from the seed below the root the first step overshoots (to at most the
      // bracket's top), then the steps fall monotonically onto the root. Bisect if one goes below.
      if (!(next < 2 * hi)) next = 2 * hi;
      if (!(next > 2 * lo)) next = lo + hi;
      u = next;
    }
    if (iterations) *iterations = it;
    return 0.5 * u;
  }

  void forward(double lam, double phi, double& X, double& Y) const {
    const double d = delta_of(std::cos(phi), std::fabs(std::sin(phi)));
    X = 2.0 * kSqrt2 / kPi * lam * std::sin(d);
    Y = std::copysign(kSqrt2 * std::cos(d), phi);
  }
  bool inside(double X, double Y) const {
    const double u = X / (2 * kSqrt2), v = Y / kSqrt2;
    return u * u + v * v <= 1.0 + kEdgeSlack;
  }
  bool inverse(double X, double Y, double& lam, double& phi) const {
    if (!inside(X, Y)) return false;
    const double ay = std::fmin(1.0, std::fabs(Y) / kSqrt2);
    const double d = std::atan2(std::sqrt((1.0 - ay) * (1.0 + ay)), ay);  // acos(ay), exact near the poles
    // 1 - sin|phi| = h(2 delta) / pi = 2 sin^2(e/2), e = pi/2 - |phi|.
    const double e = 2.0 * std::asin(std::fmin(1.0, std::sqrt(0.5 * h(2.0 * d) / kPi)));
    phi = std::copysign(kHalfPi - e, Y);
    const double sd = std::sin(d);
    lam = sd > 1e-300 ? kPi * X / (2.0 * kSqrt2 * sd) : 0.0;  // at a pole every longitude is one point
    return std::fabs(lam) <= kPi * (1.0 + kEdgeSlack);
  }
};

}  // namespace panoproj
