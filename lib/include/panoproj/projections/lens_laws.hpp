#pragma once
// Radial laws of calibrated lens models: a ray at angle theta from the optical axis (+z) meets
// the normalized image plane at radius R(theta) (pixels: x = cx + fx R cos phi, y = cy + fy R sin
// phi, phi the ray's azimuth; lens.hpp). Each law gives R, its inverse, R'(0), limit(): the
// largest theta its model projects (the papers' domain Omega), beyond which R is undefined or
// folds back, and bounded(): whether R stays finite up to limit() (else it grows without bound
// toward it, and a field must stop short of it).
//   Kannala-Brandt  R = theta (1 + k1 theta^2 + k2 theta^4 + ... + k6 theta^12)
//                   (Kannala and Brandt, IEEE TPAMI 28(8), 2006; OpenCV's cv::fisheye: k1..k4;
//                   COLMAP's RAD_TAN_THIN_PRISM_FISHEYE: six). No closed inverse: Newton from
//                   theta = R inside a bisection bracket.
//   Double Sphere   R = sin t / (alpha d2 + (1 - alpha)(xi + cos t)), d2 = |(sin t, xi + cos t)|
//                   (Usenko, Demmel and Cremers, "The Double Sphere Camera Model", 3DV 2018,
//                   eqs. 40-47: projection, its domain z > -w2 d, and the closed-form
//                   unprojection).
//   Unified         R = sin t / (cos t + xi) (xi = 0: the pinhole's tan t)  (Geyer and Daniilidis,
//   ECCV 2000; Mei and Rives,
//                   ICRA 2007: the xi form; domain z > -w, w = xi <= 1 ? xi : 1 / xi).
//   Extended unified R = sin t / (alpha d + (1 - alpha) cos t), d = sqrt(beta sin^2 t + cos^2 t)
//                   (Khomutenko, Garcia and Martinet, IEEE RA-L 1(1), 2016; domain and inverse as
//                   summarized in Usenko et al. 2018, eqs. 30-39).
//   PTLens          R = g(s tan t) / s, g(u) = u (a u^3 + b u^2 + c u + d), d = 1 - a - b - c: a
//                   rectilinear lens whose distorted radius is g of the ideal one, both in units
//                   of half the image's shorter side (s = focal length over it); Dersch's Panorama
//                   Tools and lensfun's "ptlens" model. No closed inverse: Newton on g, bracketed.
//   FOV             R = atan2(2 tan(w/2) sin t, cos t) / w  (Devernay and Faugeras, "Straight lines
//                   have to be straight", MVA 13(1), 2001: r_d = atan(2 r_u tan(w/2)) / w with
//                   r_u = tan t, continued past 90 degrees); inverse t = atan2(sin(R w), 2 tan(w/2)
//                   cos(R w)). Increasing up to t = pi, where R = pi / w.
//   Division        tan t = R / (1 + k R^2) (Fitzgibbon, CVPR 2001; COLMAP's DIVISION), continued
//                   past 90 degrees as t = atan2(R, 1 + k R^2); R = 2 sin t / (cos t + sqrt(cos^2 t
//                   - 4 k sin^2 t)). k <= 0: increasing up to pi (R unbounded there; k = 0: the
//                   pinhole, to 90 degrees); k > 0: folds at tan t = 1 / (2 sqrt k), R = 1 / sqrt
//                   k.
//   F-theta         R = c0 + c1 t + ... + c5 t^5 in pixels (NVIDIA's f-theta "angle_to_pixeldist"
//                   polynomial, all powers); c0 = 0. Inverse: bracketed Newton.
//   OCamCalib       a pixel at radius rho (pixels) sees the ray (rho cos phi, rho sin phi,
//   -pol(rho)),
//                   pol(rho) = a0 + a1 rho + ... (Scaramuzza, Martinelli and Siegwart, ICVS 2006;
//                   OCamCalib's cam2world, whose z = pol points backward): t = atan2(rho,
//                   -pol(rho)), closed; R(t) = rho by bracketed Newton on [0, rho_max].
// The closed forms return theta = atan2(radial, z) of the papers' unprojected ray.
#include <array>
#include <cmath>
#include <variant>

#include "panoproj/conventions.hpp"

namespace panoproj {

struct KannalaBrandtLaw {
  std::array<double, 6> k{};
  double radius(double t) const {
    const double t2 = t * t;
    return t *
           (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * (k[3] + t2 * (k[4] + t2 * k[5]))))));
  }
  double slope(double t) const {
    const double t2 = t * t;
    return 1.0 + t2 * (3.0 * k[0] +
                       t2 * (5.0 * k[1] +
                             t2 * (7.0 * k[2] +
                                   t2 * (9.0 * k[3] + t2 * (11.0 * k[4] + t2 * 13.0 * k[5])))));
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

// The bracketed Newton the polynomial laws invert with: x in [0, x_max] with f(x) = y, for f
// increasing there (df its derivative); from x0 (clamped to the bracket), a step leaving the
// bracket replaced by bisection; stops when a step is under 1e-15 (1 + x) or after 100 steps
// (bisection alone narrows the bracket below that in 60).
template <class F, class DF>
double bracketed_newton(const F& f, const DF& df, double y, double x_max, double x0) {
  double lo = 0.0, hi = x_max, x = std::fmin(std::fmax(x0, 0.0), x_max);
  for (int i = 0; i < 100; ++i) {
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
  return bracketed_newton([this](double t) { return radius(t); },
                          [this](double t) { return slope(t); }, r, t_max, r);
}

struct FovLaw {
  double w = 0.5;  // omega (radians), 0 < w < pi
  double radius(double t) const {
    return std::atan2(2.0 * std::tan(0.5 * w) * std::sin(t), std::cos(t)) / w;
  }
  double angle(double r, double) const {
    return std::atan2(std::sin(r * w), 2.0 * std::tan(0.5 * w) * std::cos(r * w));
  }
  double limit() const { return kPi; }
  bool bounded() const { return true; }
  double slope0() const { return 2.0 * std::tan(0.5 * w) / w; }
};

struct DivisionLaw {
  double k = 0.0;
  double radius(double t) const {
    const double s = std::sin(t), c = std::cos(t);
    const double root = std::sqrt(std::fmax(0.0, c * c - 4.0 * k * s * s));
    // Past 90 degrees (k < 0) c + root cancels: its conjugate form.
    return c >= 0.0 ? 2.0 * s / (c + root) : (root - c) / (-2.0 * k * s);
  }
  double angle(double r, double) const { return std::atan2(r, 1.0 + k * r * r); }
  double limit() const { return k > 0 ? std::atan(0.5 / std::sqrt(k)) : k == 0 ? kHalfPi : kPi; }
  bool bounded() const { return k > 0; }
  double slope0() const { return 1.0; }
};

// A polynomial sum c[0] + c[1] x + ... + c[n - 1] x^(n - 1), and its derivative.
template <size_t N>
double polynomial(const std::array<double, N>& c, int n, double x) {
  double v = 0.0;
  for (int i = n - 1; i >= 0; --i) v = v * x + c[i];
  return v;
}
template <size_t N>
double polynomial_slope(const std::array<double, N>& c, int n, double x) {
  double v = 0.0;
  for (int i = n - 1; i >= 1; --i) v = v * x + i * c[i];
  return v;
}

struct FThetaLaw {
  std::array<double, 6> c{};  // pixels at t^0 .. t^5
  double radius(double t) const { return polynomial(c, 6, t); }
  double slope(double t) const { return polynomial_slope(c, 6, t); }
  double angle(double r, double t_max) const {
    return bracketed_newton([this](double t) { return radius(t); },
                            [this](double t) { return slope(t); }, r, t_max, r / c[1]);
  }
  double limit() const { return kPi; }
  bool bounded() const { return true; }
  double slope0() const { return c[1]; }
};

struct OCamLaw {
  static constexpr int kMax = 16;
  std::array<double, kMax> pol{};  // a0 .. a(n-1)
  int n = 1;
  double rho_max = 0.0;  // the field's edge, set when the field is known
  double z(double rho) const { return -polynomial(pol, n, rho); }
  double theta(double rho) const { return std::atan2(rho, z(rho)); }
  // d theta / d rho = (z - rho z') / (rho^2 + z^2); its numerator is positive where t increases.
  double rise(double rho) const { return z(rho) + rho * polynomial_slope(pol, n, rho); }
  double radius(double t) const {
    return bracketed_newton([this](double r) { return theta(r); },
                            [this](double r) { return rise(r) / (r * r + z(r) * z(r)); }, t,
                            rho_max, z(0.0) * std::tan(std::fmin(t, 1.5)));
  }
  double angle(double r, double) const { return theta(r); }
  double limit() const { return kPi; }
  bool bounded() const { return true; }
  double slope0() const { return z(0.0); }
};

struct PTLensLaw {
  double a = 0.0, b = 0.0, c = 0.0, s = 1.0;  // s: focal length / half the shorter side
  double scale(double u) const { return d() + u * (c + u * (b + u * a)); }  // g(u) / u
  double g(double u) const { return u * scale(u); }
  double slope(double u) const { return d() + u * (2.0 * c + u * (3.0 * b + u * 4.0 * a)); }
  double d() const { return 1.0 - a - b - c; }
  double radius(double t) const { return t >= kHalfPi ? HUGE_VAL : g(s * std::tan(t)) / s; }
  double angle(double r, double t_max) const {
    const double u =
        bracketed_newton([this](double x) { return g(x); }, [this](double x) { return slope(x); },
                         s * r, s * std::tan(t_max), s * r);
    return std::atan(u / s);
  }
  double limit() const { return kHalfPi; }
  bool bounded() const { return false; }
  double slope0() const { return d(); }
};

using LensLaw = std::variant<KannalaBrandtLaw, DoubleSphereLaw, UnifiedLaw, ExtendedUnifiedLaw,
                             PTLensLaw, FovLaw, DivisionLaw, FThetaLaw, OCamLaw>;

}  // namespace panoproj
