#pragma once
// Radial laws of calibrated lens models: a ray at angle theta from the optical axis (+z) meets
// the normalized image plane at radius R(theta) (pixels: x = cx + fx R cos phi, y = cy + fy R sin
// phi, phi the ray's azimuth; lens.hpp). Each law gives R, its inverse, R'(0), limit(): the
// largest theta its model projects (the papers' domain Omega), beyond which R is undefined or
// folds back, and bounded(): whether R stays finite up to limit() (else it grows without bound
// toward it, and a field must stop short of it).
//   Kannala-Brandt  R = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)
//                   (Kannala and Brandt, IEEE TPAMI 28(8), 2006; OpenCV's cv::fisheye). No closed
//                   inverse: Newton from theta = R inside a bisection bracket.
//   Double Sphere   R = sin t / (alpha d2 + (1 - alpha)(xi + cos t)), d2 = |(sin t, xi + cos t)|
//                   (Usenko, Demmel and Cremers, "The Double Sphere Camera Model", 3DV 2018,
//                   eqs. 40-47: projection, its domain z > -w2 d, and the closed-form unprojection).
//   Unified         R = sin t / (cos t + xi)  (Geyer and Daniilidis, ECCV 2000; Mei and Rives,
//                   ICRA 2007: the xi form; domain z > -w, w = xi <= 1 ? xi : 1 / xi).
//   Extended unified R = sin t / (alpha d + (1 - alpha) cos t), d = sqrt(beta sin^2 t + cos^2 t)
//                   (Khomutenko, Garcia and Martinet, IEEE RA-L 1(1), 2016; domain and inverse as
//                   summarized in Usenko et al. 2018, eqs. 30-39).
// The closed forms return theta = atan2(radial, z) of the papers' unprojected ray.
#include <array>
#include <cmath>
#include <variant>

#include "panoproj/conventions.hpp"

namespace panoproj {

struct KannalaBrandtLaw {
  std::array<double, 4> k{};
  double radius(double t) const {
    const double t2 = t * t;
    return t * (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
  }
  double slope(double t) const {
    const double t2 = t * t;
    return 1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
  }
  // theta in [0, t_max] with radius(theta) = r, for r in [0, radius(t_max)] (radius increasing
  // there): Newton from theta = r, a step leaving the bracket replaced by bisection; stops when a
  // step is under 1e-15 rad or after 60 steps.
  double angle(double r, double t_max) const {
    double lo = 0.0, hi = t_max, t = std::fmin(r, t_max);
    for (int i = 0; i < 60; ++i) {
      const double f = radius(t) - r;
      if (f == 0.0) return t;
      (f > 0.0 ? hi : lo) = t;
      double next = t - f / slope(t);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // outside the bracket (or NaN)
      const double step = std::fabs(next - t);
      t = next;
      if (step < 1e-15) break;
    }
    return t;
  }
  double limit() const { return kPi; }
  bool bounded() const { return true; }
  double slope0() const { return 1.0; }
  // The first angle in (0, t] where the slope reaches 0, or -1 if R increases all the way: the
  // slope sampled every t/4096, then bisected (a polynomial of degree 4 in theta^2 has at most 4
  // sign changes, far apart for any lens a calibration returns).
  double fold_back(double t) const {
    constexpr int kSteps = 4096;
    double prev = 0.0;
    for (int i = 1; i <= kSteps; ++i) {
      const double ti = t * i / kSteps;
      if (slope(ti) <= 0.0) {
        double lo = prev, hi = ti;
        for (int j = 0; j < 60; ++j) {
          const double mid = 0.5 * (lo + hi);
          (slope(mid) > 0.0 ? lo : hi) = mid;
        }
        return hi;
      }
      prev = ti;
    }
    return -1.0;
  }
};

// w of the unified models' domains z > -w d (alpha form).
inline double unified_w(double alpha) { return alpha <= 0.5 ? alpha / (1.0 - alpha) : (1.0 - alpha) / alpha; }

struct DoubleSphereLaw {
  double xi = 0.0, alpha = 0.5;
  double radius(double t) const {
    const double s = std::sin(t), c = std::cos(t);
    const double d2 = std::hypot(s, xi + c);
    return s / (alpha * d2 + (1.0 - alpha) * (xi + c));
  }
  double angle(double r, double) const {
    const double r2 = r * r;
    const double mz = (1.0 - alpha * alpha * r2) /
                      (alpha * std::sqrt(std::fmax(0.0, 1.0 - (2.0 * alpha - 1.0) * r2)) + 1.0 - alpha);
    const double k = (mz * xi + std::sqrt(std::fmax(0.0, mz * mz + (1.0 - xi * xi) * r2))) / (mz * mz + r2);
    return std::atan2(k * r, k * mz - xi);
  }
  // z > -w2 d: w2 = (w1 + xi) / sqrt(2 w1 xi + xi^2 + 1), w1 = unified_w(alpha).
  double limit() const {
    const double w1 = unified_w(alpha);
    const double w2 = (w1 + xi) / std::sqrt(2.0 * w1 * xi + xi * xi + 1.0);
    return std::acos(std::fmax(-1.0, std::fmin(1.0, -w2)));
  }
  bool bounded() const { return alpha > 0.5; }  // R^2 <= 1 / (2 alpha - 1)
  double slope0() const { return 1.0 / (1.0 + xi); }
};

struct UnifiedLaw {
  double xi = 1.0;
  double radius(double t) const { return std::sin(t) / (std::cos(t) + xi); }
  double angle(double r, double) const {
    const double r2 = r * r;
    const double k = (xi + std::sqrt(std::fmax(0.0, 1.0 + (1.0 - xi * xi) * r2))) / (1.0 + r2);
    return std::atan2(k * r, k - xi);
  }
  double limit() const { return std::acos(-(xi <= 1.0 ? xi : 1.0 / xi)); }
  bool bounded() const { return xi > 1.0; }  // R^2 <= 1 / (xi^2 - 1)
  double slope0() const { return 1.0 / (1.0 + xi); }
};

struct ExtendedUnifiedLaw {
  double alpha = 0.5, beta = 1.0;
  double radius(double t) const {
    const double s = std::sin(t), c = std::cos(t);
    const double d = std::sqrt(beta * s * s + c * c);
    return s / (alpha * d + (1.0 - alpha) * c);
  }
  double angle(double r, double) const {
    const double r2 = r * r;
    const double mz = (1.0 - beta * alpha * alpha * r2) /
                      (alpha * std::sqrt(std::fmax(0.0, 1.0 - (2.0 * alpha - 1.0) * beta * r2)) + 1.0 - alpha);
    return std::atan2(r, mz);
  }
  // z > -w d with d = sqrt(beta sin^2 + cos^2): for cos t < 0, cos^2 t < w^2 beta / (1 - w^2 + w^2 beta).
  double limit() const {
    const double w = unified_w(alpha);
    if (w >= 1.0) return kPi;
    return std::acos(-std::sqrt(w * w * beta / (1.0 - w * w + w * w * beta)));
  }
  bool bounded() const { return alpha > 0.5; }  // R^2 <= 1 / (beta (2 alpha - 1))
  double slope0() const { return 1.0; }
};

using LensLaw = std::variant<KannalaBrandtLaw, DoubleSphereLaw, UnifiedLaw, ExtendedUnifiedLaw>;

}  // namespace panoproj
