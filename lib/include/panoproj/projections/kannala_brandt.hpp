#pragma once
// Kannala-Brandt fisheye, as OpenCV's fisheye module calibrates it (cv::fisheye): with theta the
// angle from the optical axis (+z) and phi the azimuth,
//   theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
//   (x, y) = (cx + fx theta_d cos phi, cy + fy theta_d sin phi)
// (Kannala and Brandt, "A generic camera model and calibration method for conventional,
// wide-angle, and fish-eye lenses", IEEE TPAMI 28(8), 2006; OpenCV's documentation of
// cv::fisheye, without its skew). Unlike OpenCV's own functions, which work on x/z and y/z and so
// stop short of 180 degrees, the ray is built from theta: fields of view up to 360 degrees.
// Valid: theta <= theta_max (half the fov, the image circle), where theta_d must increase
// (checked when made: a law that folds back has no inverse). Inverse: Newton on
// theta_d(theta) = r from theta = r, kept inside a bisection bracket [0, theta_max]; it stops
// when a step is under 1e-15 rad (double's resolution near theta_max <= pi) or after 60 steps.
#include <array>
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

class KannalaBrandt {
 public:
  // (cx, cy) in panoproj's pixel convention (centres at i + 0.5); k = k1..k4; theta_max (radians,
  // at most pi) must lie where theta_d increases: see fold_back.
  KannalaBrandt(Size size, double fx, double fy, double cx, double cy, const std::array<double, 4>& k, double theta_max)
      : size_(size), fx_(fx), fy_(fy), cx_(cx), cy_(cy), k_(k), theta_max_(theta_max), rd_max_(distort(theta_max)) {}

  // theta_d(theta) and its derivative.
  double distort(double t) const {
    const double t2 = t * t;
    return t * (1.0 + t2 * (k_[0] + t2 * (k_[1] + t2 * (k_[2] + t2 * k_[3]))));
  }
  double slope(double t) const {
    const double t2 = t * t;
    return 1.0 + t2 * (3.0 * k_[0] + t2 * (5.0 * k_[1] + t2 * (7.0 * k_[2] + t2 * 9.0 * k_[3])));
  }
  // The first angle in (0, theta] where theta_d stops increasing (its slope reaches 0), or a
  // negative value if it increases all the way: sampled every 1/4096 of theta, then refined by
  // bisection (the slope is a polynomial of degree 4 in theta^2: at most 4 sign changes, far
  // apart for any lens a calibration returns).
  double fold_back(double theta) const {
    constexpr int kSteps = 4096;
    double prev = 0.0;
    for (int i = 1; i <= kSteps; ++i) {
      const double t = theta * i / kSteps;
      if (slope(t) <= 0.0) {
        double lo = prev, hi = t;
        for (int j = 0; j < 60; ++j) {
          const double mid = 0.5 * (lo + hi);
          (slope(mid) > 0.0 ? lo : hi) = mid;
        }
        return hi;
      }
      prev = t;
    }
    return -1.0;
  }

  // theta from theta_d = r in [0, rd_max]: Newton, bracketed (theta_d increases on [0, theta_max]).
  double undistort(double r) const {
    double lo = 0.0, hi = theta_max_, t = std::fmin(r, theta_max_);
    for (int i = 0; i < 60; ++i) {
      const double f = distort(t) - r;
      if (f == 0.0) return t;
      (f > 0.0 ? hi : lo) = t;
      double next = t - f / slope(t);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // outside the bracket (or NaN): bisect
      const double step = std::fabs(next - t);
      t = next;
      if (step < 1e-15) break;
    }
    return t;
  }

  bool to_ray(double x, double y, Ray& d) const {
    const double u = (x - cx_) / fx_, v = (y - cy_) / fy_;
    const double r = std::hypot(u, v);
    if (!(r <= rd_max_ * (1.0 + kEdgeSlack))) return false;
    if (r == 0.0) {
      d = Ray(0.0, 0.0, 1.0);
      return true;
    }
    const double t = undistort(std::fmin(r, rd_max_));
    const double s = std::sin(t) / r;
    d = Ray(s * u, s * v, std::cos(t));
    return true;
  }

  bool to_pixel(const Ray& d, double& x, double& y) const {
    const double s = std::hypot(d.x(), d.y());
    const double t = std::atan2(s, d.z());
    if (t > theta_max_ * (1.0 + kEdgeSlack) && distort(std::fmin(t, kPi)) > rd_max_ * (1.0 + kEdgeSlack)) return false;
    const double r = distort(std::fmin(t, theta_max_));
    // On the axis the azimuth is undefined: the front pole maps to the centre, the back pole
    // (theta = pi, a 360-degree circle's rim) to phi = 0.
    const double cu = s > 0.0 ? d.x() / s : 1.0, cv = s > 0.0 ? d.y() / s : 0.0;
    x = cx_ + fx_ * r * cu;
    y = cy_ + fy_ * r * cv;
    return in_frame(x, y, size_);
  }

  // Whether pixel position (x, y) has a ray (to_ray's test alone).
  bool contains(double x, double y) const {
    return in_frame(x, y, size_) && std::hypot((x - cx_) / fx_, (y - cy_) / fy_) <= rd_max_ * (1.0 + kEdgeSlack);
  }
  // The valid region (an ellipse within the frame) is convex: its four corners decide.
  bool covers(double x0, double y0, double x1, double y1) const {
    return contains(x0, y0) && contains(x1, y0) && contains(x0, y1) && contains(x1, y1);
  }

  Size size() const { return size_; }
  double center_density() const { return fx_; }  // theta_d'(0) = 1
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  const std::array<double, 4>& k() const { return k_; }
  double theta_max() const { return theta_max_; }
  double rd_max() const { return rd_max_; }  // theta_d at the image circle

 private:
  Size size_;
  double fx_, fy_, cx_, cy_;
  std::array<double, 4> k_;
  double theta_max_, rd_max_;
};

}  // namespace panoproj
