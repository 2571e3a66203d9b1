#pragma once
// A pinhole camera with Brown-Conrady distortion, as OpenCV calibrates it (cv::calibrateCamera's
// (k1, k2, p1, p2, k3)): with (x, y) = (X / Z, Y / Z) and r^2 = x^2 + y^2,
//   x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
//   y_d = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
//   pixel = (cx + fx x_d, cy + fy y_d)
// (Brown, "Decentering distortion of lenses", Photogrammetric Engineering 32(3), 1966; Conrady
// 1919; OpenCV's documentation of its camera model). Valid: rays within theta_max of the axis
// (r <= tan theta_max: half the fov), where the distortion must not fold (checked when made: the
// radial factor's r (1 + ...) increases and the map's Jacobian stays positive). The inverse has
// no closed form: Newton in 2-D from the distorted point, with a step halved while it does not
// reduce the residual; converged when a step is under 1e-15 (1 + r), at most 100 steps.
#include <array>
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

class BrownConrady {
 public:
  // d = (k1, k2, p1, p2, k3), OpenCV's order; (cx, cy) in panoproj's pixel convention.
  BrownConrady(Size size, double fx, double fy, double cx, double cy, const std::array<double, 5>& d, double theta_max)
      : size_(size), fx_(fx), fy_(fy), cx_(cx), cy_(cy), d_(d), theta_max_(theta_max), r_max_(std::tan(theta_max)) {
    // The largest circle about the centre inside the valid region's image (from its boundary,
    // sampled finely): pixels within it need no inverse to be known valid (covers).
    inner_ = HUGE_VAL;
    for (int i = 0; i < 1024; ++i) {
      double xd, yd;
      const double a = 2.0 * kPi * i / 1024;
      distort(r_max_ * std::cos(a), r_max_ * std::sin(a), xd, yd);
      inner_ = std::fmin(inner_, std::hypot(xd, yd));
    }
    inner_ *= 1.0 - 1e-3;
  }

  void distort(double x, double y, double& xd, double& yd) const {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (d_[0] + r2 * (d_[1] + r2 * d_[4]));
    xd = x * radial + 2.0 * d_[2] * x * y + d_[3] * (r2 + 2.0 * x * x);
    yd = y * radial + d_[2] * (r2 + 2.0 * y * y) + 2.0 * d_[3] * x * y;
  }
  // d(xd, yd) / d(x, y), row-major.
  void jacobian(double x, double y, double j[4]) const {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (d_[0] + r2 * (d_[1] + r2 * d_[4]));
    const double dradial = 2.0 * (d_[0] + r2 * (2.0 * d_[1] + 3.0 * r2 * d_[4]));  // d radial / d(r^2), times 2
    j[0] = radial + x * x * dradial + 2.0 * d_[2] * y + 6.0 * d_[3] * x;
    j[1] = x * y * dradial + 2.0 * d_[2] * x + 2.0 * d_[3] * y;
    j[2] = x * y * dradial + 2.0 * d_[2] * x + 2.0 * d_[3] * y;
    j[3] = radial + y * y * dradial + 6.0 * d_[2] * y + 2.0 * d_[3] * x;
  }
  // (x, y) with distort(x, y) = (xd, yd) and r <= r_max; false where there is none.
  bool undistort(double xd, double yd, double& x, double& y) const {
    x = xd, y = yd;
    double fx, fy;
    distort(x, y, fx, fy);
    fx -= xd, fy -= yd;
    double res = std::hypot(fx, fy);
    for (int i = 0; i < 100 && res > 0.0; ++i) {
      double j[4];
      jacobian(x, y, j);
      const double det = j[0] * j[3] - j[1] * j[2];
      if (!(std::fabs(det) > 1e-300)) return false;
      double sx = (j[3] * fx - j[1] * fy) / det, sy = (j[0] * fy - j[2] * fx) / det;
      // Halve the step while it does not reduce the residual.
      double nx = x, ny = y, nres = res, gx = fx, gy = fy;
      for (int h = 0; h < 40; ++h, sx *= 0.5, sy *= 0.5) {
        nx = x - sx, ny = y - sy;
        distort(nx, ny, gx, gy);
        gx -= xd, gy -= yd;
        nres = std::hypot(gx, gy);
        if (nres < res) break;
      }
      const double step = std::hypot(nx - x, ny - y);
      if (!(nres < res)) break;  // no step reduces it: converged to rounding
      x = nx, y = ny, fx = gx, fy = gy, res = nres;
      if (step < 1e-15 * (1.0 + std::hypot(x, y))) break;
    }
    return res <= 1e-12 * (1.0 + std::hypot(xd, yd)) && std::hypot(x, y) <= r_max_ * (1.0 + kEdgeSlack);
  }

  bool to_ray(double px, double py, Ray& d) const {
    double x, y;
    if (!undistort((px - cx_) / fx_, (py - cy_) / fy_, x, y)) return false;
    d = Ray(x, y, 1.0).normalized();
    return true;
  }

  bool to_pixel(const Ray& d, double& px, double& py) const {
    if (!(d.z() > 0.0)) return false;
    const double x = d.x() / d.z(), y = d.y() / d.z();
    if (!(std::hypot(x, y) <= r_max_ * (1.0 + kEdgeSlack))) return false;
    double xd, yd;
    distort(x, y, xd, yd);
    px = cx_ + fx_ * xd;
    py = cy_ + fy_ * yd;
    return in_frame(px, py, size_);
  }

  bool contains(double px, double py) const {
    if (!in_frame(px, py, size_)) return false;
    const double u = (px - cx_) / fx_, v = (py - cy_) / fy_;
    if (std::hypot(u, v) < inner_) return true;
    double x, y;
    return undistort(u, v, x, y);
  }
  // True only where every position has a ray: the four corners inside the inner circle (an
  // ellipse in pixels, convex).
  bool covers(double x0, double y0, double x1, double y1) const {
    auto in = [&](double px, double py) {
      return in_frame(px, py, size_) && std::hypot((px - cx_) / fx_, (py - cy_) / fy_) < inner_;
    };
    return in(x0, y0) && in(x1, y0) && in(x0, y1) && in(x1, y1);
  }

  Size size() const { return size_; }
  double center_density() const { return fx_; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  const std::array<double, 5>& coefficients() const { return d_; }
  double theta_max() const { return theta_max_; }

 private:
  Size size_;
  double fx_, fy_, cx_, cy_;
  std::array<double, 5> d_;
  double theta_max_, r_max_, inner_;
};

}  // namespace panoproj
