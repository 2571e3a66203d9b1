#pragma once
// Panini-type views: the plane X = F(lambda), Y = tan(phi) K(lambda) (lambda = atan2(x, z), phi the
// latitude), x = cx + f X, y = cy - f Y. Verticals stay vertical; F'(0) = 1.
//   sharpless (General Panini; Sharpless, Postle and German, "Pannini: A New Projection for
//     Rendering Wide Angle Perspective Images", CAe 2010; Hugin's, v360's pannini):
//     S = (d + 1) / (d + cos lambda),  F = S sin lambda,  K = (1 - vc) S + vc.
//     d = 0 is rectilinear, d = 1 the classic Panini; vc is the vertical compression (Sharpless'
//     own filters scale the x-dependent factor S by Vfac = 1 - vc): 0 keeps every line through
//     the centre straight, 1 leaves tan phi alone.
//     Inverse: q = X / (d + 1), R = sqrt(1 + q^2 (1 - d^2)), lambda = atan2(q (d + R), R - d q^2)
//     (the ray's sin and cos, times 1 + q^2), defined for lambda up to acos(-min(d, 1/d)).
//   opencv (cv::PaniniProjector): F = a tan(lambda / a),  K = b F / sin lambda.
//   compressed (cv::CompressedRectilinearProjector): F = a tan(lambda / a),  K = b / cos lambda.
// OpenCV's v (y down) is -f Y here, its u f X: the same picture.
#include <algorithm>
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

enum class PaniniLaw { Sharpless, OpenCV, Compressed };

class Panini : public FramedBounds {
 public:
  // p1, p2: (d, vc) for sharpless, (a, b) for the OpenCV forms. fx, fy: pixels per plane unit.
  Panini(Size size, PaniniLaw law, double p1, double p2, double fx, double fy, double cx, double cy)
      : FramedBounds(size), law_(law), p1_(p1), p2_(p2), fx_(fx), fy_(fy), cx_(cx), cy_(cy),
        lam_max_(lambda_max(law, p1)) {}

  // The widest |lambda| the law maps one to one.
  static double lambda_max(PaniniLaw law, double p1) {
    switch (law) {
      case PaniniLaw::Sharpless: return std::acos(-std::min(p1, 1.0 / p1));
      case PaniniLaw::OpenCV: return std::min(kPi, 0.5 * kPi * p1);
      case PaniniLaw::Compressed: return std::min(kHalfPi, 0.5 * kPi * p1);
    }
    return 0.0;
  }
  static double F(PaniniLaw law, double p1, double lam) {
    if (law == PaniniLaw::Sharpless) return (p1 + 1.0) * std::sin(lam) / sharpless_denominator(p1, lam);
    return p1 * std::tan(lam / p1);
  }
  // d + cos lambda; past 90 degrees as (d - 1) + 2 cos^2(lambda/2), which keeps its digits where
  // cos lambda nears -1 (d = 1 towards 180 degrees).
  static double sharpless_denominator(double d, double lam) {
    const double c = std::cos(lam);
    if (c >= 0) return d + c;
    const double h = std::cos(0.5 * lam);
    return (d - 1.0) + 2.0 * h * h;
  }
  double F(double lam) const { return F(law_, p1_, lam); }
  // K(0), the vertical scale on the centre line: 1 for Sharpless' (S(0) = 1), b for OpenCV's.
  static double center_k(PaniniLaw law, double p2) { return law == PaniniLaw::Sharpless ? 1.0 : p2; }
  double K(double lam) const {
    switch (law_) {
      case PaniniLaw::Sharpless: return (1.0 - p2_) * (p1_ + 1.0) / sharpless_denominator(p1_, lam) + p2_;
      case PaniniLaw::OpenCV: {
        // a tan(lambda/a) / sin(lambda) -> 1 + lambda^2 (1/(3 a^2) + 1/6) near 0
        if (std::fabs(lam) < 1e-5) return p2_ * (1.0 + lam * lam * (1.0 / (3.0 * p1_ * p1_) + 1.0 / 6.0));
        return p2_ * F(lam) / std::sin(lam);
      }
      case PaniniLaw::Compressed: return p2_ / std::cos(lam);
    }
    return 1.0;
  }
  double lambda_of(double X) const {
    if (law_ != PaniniLaw::Sharpless) return p1_ * std::atan(X / p1_);
    const double d = p1_, q = X / (d + 1.0);
    const double R = std::sqrt(std::fmax(0.0, 1.0 + q * q * (1.0 - d * d)));
    return std::atan2(q * (d + R), R - d * q * q);
  }

  bool to_ray(double x, double y, Ray& d) const {
    const double lam = lambda_of((x - cx_) / fx_);
    if (!(std::fabs(lam) <= lam_max_)) return false;
    const double t = (cy_ - y) / fy_ / K(lam);  // tan phi
    d = Ray(std::sin(lam), -t, std::cos(lam)).normalized();
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    const double c = std::hypot(d.x(), d.z());
    if (!(c > 0.0)) return false;
    const double lam = std::atan2(d.x(), d.z());
    if (std::fabs(lam) > lam_max_ * (1.0 + kEdgeSlack) || std::fabs(lam) >= kPi) return false;
    x = cx_ + fx_ * F(lam);
    y = cy_ + fy_ * (d.y() / c) * K(lam);
    return in_frame(x, y, size_);
  }

  double center_density() const { return fx_; }  // F'(0) = 1
  PaniniLaw law() const { return law_; }
  double p1() const { return p1_; }
  double p2() const { return p2_; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }

 private:
  PaniniLaw law_;
  double p1_, p2_, fx_, fy_, cx_, cy_, lam_max_;
};

}  // namespace panoproj
