#pragma once
// A calibrated lens: a radial law (lens_laws.hpp) between the angle theta from the optical axis
// and the radius R on the lens's undistorted plane, m = R(theta) (cos phi, sin phi) (phi the ray's
// azimuth), then optionally OpenCV's plane distortion m_d = D(m) (plane_distortion.hpp), then an
// affine map to pixels: (x, y) = (cx, cy) + A m_d. A = diag(fx, fy) for OpenCV's intrinsics (cx, cy
// given in OpenCV's convention at the spec, held here in panoproj's); the F-theta and OCamCalib
// laws are in pixels and A is their affine term. The pinhole is the unified law with xi = 0, so
// Brown-Conrady (OpenCV's full model) is this class too. The ray is built from theta and the
// azimuth (not from the pinhole plane, which ends at 90 degrees), so a lens sees up to 360
// degrees where its law does. Valid: theta <= theta_max (half the fov: the image circle, an
// ellipse in pixels), which must lie within the law's domain where R increases and D does not
// fold (checked when the spec is made).
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"
#include "panoproj/projections/lens_laws.hpp"
#include "panoproj/projections/plane_distortion.hpp"

namespace panoproj {

// (x, y) = A (u, v) = (a u + b v, c u + d v).
struct LensAffine {
  double a = 1, b = 0, c = 0, d = 1;
  static LensAffine focal(double fx, double fy) { return {fx, 0, 0, fy}; }
  double det() const { return a * d - b * c; }
  LensAffine scaled(double sx, double sy) const { return {a * sx, b * sx, c * sy, d * sy}; }
};

class CalibratedLens {
 public:
  CalibratedLens(Size size, const LensAffine& A, double cx, double cy, const LensLaw& law,
                 double theta_max, const PlaneDistortion& distortion = {})
      : size_(size),
        A_(A),
        cx_(cx),
        cy_(cy),
        law_(law),
        distortion_(distortion),
        theta_max_(theta_max),
        rd_max_(radius(theta_max)),
        limit_(std::visit([](const auto& l) { return l.limit(); }, law)),
        distorted_(!distortion.identity()) {
    const double det = A.det();
    inv_ = {A.d / det, -A.b / det, -A.c / det, A.a / det};
    // The largest circle about the centre inside the distorted image circle (its boundary sampled
    // finely): points within it need no inverse to be known valid (contains, covers).
    inner_ = rd_max_;
    if (distorted_) {
      inner_ = HUGE_VAL;
      for (int i = 0; i < 1024; ++i) {
        double xd, yd;
        const double t = 2.0 * kPi * i / 1024;
        distortion_.apply(rd_max_ * std::cos(t), rd_max_ * std::sin(t), xd, yd);
        inner_ = std::fmin(inner_, std::hypot(xd, yd));
      }
      inner_ *= 1.0 - 1e-3;
    }
  }

  double radius(double t) const {
    return std::visit([t](const auto& l) { return l.radius(t); }, law_);
  }
  // theta for radius r in [0, rd_max].
  double angle(double r) const {
    return std::visit([&](const auto& l) { return l.angle(r, theta_max_); }, law_);
  }

  bool to_ray(double x, double y, Ray& d) const {
    double u, v;
    if (!undistorted(x, y, u, v)) return false;
    const double r = std::hypot(u, v);
    if (!(r <= rd_max_ * (1.0 + kEdgeSlack))) return false;
    if (r == 0.0) {
      d = Ray(0.0, 0.0, 1.0);
      return true;
    }
    d = radial_ray(angle(std::fmin(r, rd_max_)), u, v, r);
    return true;
  }

  bool to_pixel(const Ray& d, double& x, double& y) const {
    double cu, cv;
    const double t = off_axis(d, cu, cv);
    // The rim's slack in theta, or, just past the rim, as to_ray gives it: in R (where the law
    // flattens toward a bounded domain's edge, theta(R) is ill-conditioned). Only just past it:
    // beyond a polynomial law's fold R comes back down.
    if (t > theta_max_ * (1.0 + kEdgeSlack) &&
        !(t <= std::fmin(limit(), theta_max_ + 1e-6) && radius(t) <= rd_max_ * (1.0 + kEdgeSlack)))
      return false;
    const double r = radius(std::fmin(t, theta_max_));
    double u = r * cu, v = r * cv;
    if (distorted_) distortion_.apply(r * cu, r * cv, u, v);
    x = cx_ + A_.a * u + A_.b * v;
    y = cy_ + A_.c * u + A_.d * v;
    return in_frame(x, y, size_);
  }

  // Whether pixel position (x, y) has a ray (to_ray's test alone).
  bool contains(double x, double y) const {
    if (!in_frame(x, y, size_)) return false;
    if (inside_inner(x, y)) return true;
    double u, v;
    return distorted_ && undistorted(x, y, u, v) &&
           std::hypot(u, v) <= rd_max_ * (1.0 + kEdgeSlack);
  }
  // True only where every position has a ray: the four corners inside the inner circle (an
  // ellipse in pixels, convex).
  bool covers(double x0, double y0, double x1, double y1) const {
    auto in = [&](double px, double py) { return in_frame(px, py, size_) && inside_inner(px, py); };
    return in(x0, y0) && in(x1, y0) && in(x0, y1) && in(x1, y1);
  }

  Size size() const { return size_; }
  double center_density() const {  // A's first diagonal term times R'(0)
    return A_.a * std::visit([](const auto& l) { return l.slope0(); }, law_);
  }
  double limit() const { return limit_; }  // the law's domain (lens_laws.hpp)
  const LensAffine& affine() const { return A_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  const LensLaw& law() const { return law_; }
  const PlaneDistortion& distortion() const { return distortion_; }
  double theta_max() const { return theta_max_; }
  double rd_max() const { return rd_max_; }  // R at the image circle

 private:
  // The undistorted plane's point of pixel (x, y); false where D has no inverse there.
  bool undistorted(double x, double y, double& u, double& v) const {
    const double px = x - cx_, py = y - cy_;
    u = inv_.a * px + inv_.b * py;
    v = inv_.c * px + inv_.d * py;
    if (!distorted_) return true;
    const double ud = u, vd = v;
    return distortion_.invert(ud, vd, u, v);
  }
  bool inside_inner(double x, double y) const {
    const double px = x - cx_, py = y - cy_;
    const double u = inv_.a * px + inv_.b * py, v = inv_.c * px + inv_.d * py;
    return distorted_ ? std::hypot(u, v) < inner_
                      : std::hypot(u, v) <= rd_max_ * (1.0 + kEdgeSlack);
  }

  Size size_;
  LensAffine A_, inv_;
  double cx_, cy_;
  LensLaw law_;
  PlaneDistortion distortion_;
  double theta_max_, rd_max_, limit_, inner_;
  bool distorted_;
};

}  // namespace panoproj
