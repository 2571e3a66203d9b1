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
//   PTLens          R = g(s tan t) / s, g(u) = u (a u^3 + b u^2 + c u + d), d = 1 - a - b - c: a
//                   rectilinear lens whose distorted radius is g of the ideal one, both in units
//                   of half the image's shorter side (s = focal length over it); Dersch's Panorama
//                   Tools and lensfun's "ptlens" model. No closed inverse: Newton on g, bracketed.
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
  double angle(double r, double t_max) const;  // below bracketed_newton
  double limit() const { return kPi; }
  bool bounded() const { return true; }
  double slope0() const { return 1.0; }
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

// The bracketed Newton both polynomial laws invert with: x in [0, x_max] with f(x) = y, for f
// increasing there (df its derivative); from x = min(y, x_max), a step leaving the bracket
// replaced by bisection; stops when a step is under 1e-15 (1 + x) or after 60 steps.
template <class F, class DF>
double bracketed_newton(const F& f, const DF& df, double y, double x_max) {
  double lo = 0.0, hi = x_max, x = std::fmin(y, x_max);
  for (int i = 0; i < 60; ++i) {
    const double e = f(x) - y;
    if (e == 0.0) return x;
    (e > 0.0 ? hi : lo) = x;
    double next = x - e / df(x);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // outside the bracket (or NaN)
    const double step = std::fabs(next - x);
    x = next;
    if (step < 1e-15 * (1.0 + x)) break;
  }
  return x;
}

// The first x in (0, x_max] where slope(x) <= 0, or -1 if there is none: sampled every
// x_max/4096, then bisected (for the polynomial laws' slopes: few sign changes, far apart).
template <class S>
double first_fold(const S& slope, double x_max) {
  constexpr int kSteps = 4096;
  for (int i = 1; i <= kSteps; ++i) {
    const double x = x_max * i / kSteps;
    if (slope(x) <= 0.0) {
      double lo = x_max * (i - 1) / kSteps, hi = x;
      for (int j = 0; j < 60; ++j) {
        const double mid = 0.5 * (lo + hi);
        (slope(mid) > 0.0 ? lo : hi) = mid;
      }
      return hi;
    }
  }
  return -1.0;
}

inline double KannalaBrandtLaw::angle(double r, double t_max) const {
  return bracketed_newton([this](double t) { return radius(t); }, [this](double t) { return slope(t); }, r, t_max);
}

struct PTLensLaw {
  double a = 0.0, b = 0.0, c = 0.0, s = 1.0;  // s: focal length / half the shorter side
  double scale(double u) const { return d() + u * (c + u * (b + u * a)); }  // g(u) / u
  double g(double u) const { return u * scale(u); }
  double slope(double u) const { return d() + u * (2.0 * c + u * (3.0 * b + u * 4.0 * a)); }
  double d() const { return 1.0 - a - b - c; }
  double radius(double t) const { return t >= kHalfPi ? HUGE_VAL : g(s * std::tan(t)) / s; }
  double angle(double r, double t_max) const {
    const double u = bracketed_newton([this](double x) { return g(x); }, [this](double x) { return slope(x); }, s * r,
                                      s * std::tan(t_max));
    return std::atan(u / s);
  }
  double limit() const { return kHalfPi; }
  bool bounded() const { return false; }
  double slope0() const { return d(); }
};

using LensLaw = std::variant<KannalaBrandtLaw, DoubleSphereLaw, UnifiedLaw, ExtendedUnifiedLaw, PTLensLaw>;

}  // namespace panoproj
