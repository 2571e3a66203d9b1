#pragma once
// A calibrated lens: a radial law (lens_laws.hpp) between the angle theta from the optical axis
// and the radius R on the normalized image plane, m = ((x - cx) / fx, (y - cy) / fy) =
// R(theta) (cos phi, sin phi), in OpenCV's intrinsics (cx, cy given in OpenCV's convention at the
// spec, held here in panoproj's). The ray is built from theta and the azimuth (not from the
// pinhole plane, which ends at 90 degrees), so a lens sees up to 360 degrees where its law does.
// Valid: theta <= theta_max (half the fov: the image circle, an ellipse in pixels where fx != fy),
// which must lie within the law's domain and where R increases (checked when the spec is made).
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"
#include "panoproj/projections/lens_laws.hpp"

namespace panoproj {

class CalibratedLens {
 public:
  CalibratedLens(Size size, double fx, double fy, double cx, double cy, const LensLaw& law, double theta_max)
      : size_(size), fx_(fx), fy_(fy), cx_(cx), cy_(cy), law_(law), theta_max_(theta_max),
        rd_max_(radius(theta_max)), limit_(std::visit([](const auto& l) { return l.limit(); }, law)) {}

  double radius(double t) const {
    return std::visit([t](const auto& l) { return l.radius(t); }, law_);
  }
  // theta for radius r in [0, rd_max].
  double angle(double r) const {
    return std::visit([&](const auto& l) { return l.angle(r, theta_max_); }, law_);
  }

  bool to_ray(double x, double y, Ray& d) const {
    const double u = (x - cx_) / fx_, v = (y - cy_) / fy_;
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
  double center_density() const {  // fx R'(0)
    return fx_ * std::visit([](const auto& l) { return l.slope0(); }, law_);
  }
  double limit() const { return limit_; }  // the law's domain (lens_laws.hpp)
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  const LensLaw& law() const { return law_; }
  double theta_max() const { return theta_max_; }
  double rd_max() const { return rd_max_; }  // R at the image circle

 private:
  Size size_;
  double fx_, fy_, cx_, cy_;
  LensLaw law_;
  double theta_max_, rd_max_, limit_;
};

}  // namespace panoproj
