#pragma once
// An image as Panorama Tools (libpano13) and Hugin describe it: a lens law (the i line's f) at a
// horizontal field hfov (v), then the radial polynomial a b c, the shift d e and the shear g t.
// Ray -> pixel, in pixels from the frame's centre (libpano13's SetMakeParams stack, adjust.c):
//   ideal (u, v) = f L(ray): rectilinear (X/Z, Y/Z); cylindrical (lon, tan lat); equirect
//     (lon, lat) (lat positive down); the fisheyes g(psi) (cos, sin) of the azimuth, g the
//     fisheye.hpp law; f puts hfov/2 at half the width: (w/2) / L(hfov/2) along x;
//   radial: r = |(u, v)| / R0, R0 = min(w, h) / 2, (u, v) *= a r^3 + b r^2 + c r + 1 - a - b - c
//     for r below the first fold of r P(r) (libpano13's correction radius; none past it);
//   shift: u += d, v += e; shear: (x, y) = (u + (g / h) v, v + (t / w) u);
//   pixel = (w/2 + x, h/2 + y) (Hugin's pixel centres are panoproj's, checked against nona).
// Pixel -> ray inverts each step: the shear and shift in closed form, the polynomial by a
// bracketed Newton below its fold, the law in closed form.
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/fisheye.hpp"
#include "panoproj/projections/frame.hpp"
#include "panoproj/projections/lens_laws.hpp"

namespace panoproj {

// libpano13's bound on the correction radius where the polynomial never folds.
inline constexpr double kPanoToolsMaxRadius = 1000.0;

enum class PanoToolsLens { Rectilinear, Cylindrical, Equirect, Fisheye };

struct PanoToolsDistortion {
  double a = 0, b = 0, c = 0;  // the radial polynomial (PTLensLaw's: ideal and distorted radii in
                               // half the shorter side, s = 1)
  double d = 0, e = 0;         // the shift (pixels)
  double g = 0, t = 0;         // the shear (pixels over the height, the width)
  PTLensLaw radial() const { return {a, b, c, 1.0}; }
};

class PanoTools {
 public:
  // lens with model (its fisheye law where lens is Fisheye); hfov in radians; fold: where the
  // polynomial's r P(r) first stops increasing, at most kPanoToolsMaxRadius (normalized radius).
  PanoTools(Size size, PanoToolsLens lens, FisheyeModel model, double hfov,
            const PanoToolsDistortion& dist, double fold)
      : size_(size), lens_(lens), model_(model), hfov_(hfov), dist_(dist), fold_(fold) {
    const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
    f_ = 0.5 * w / unit_law(0.5 * hfov);
    r0_ = 0.5 * std::fmin(w, h);
    g_ = dist.g / h;
    t_ = dist.t / w;
    rs_max_ = dist.radial().g(fold);
  }

  bool to_pixel(const Ray& ray, double& x, double& y) const {
    double u, v;
    if (!ideal(ray, u, v)) return false;
    const double r = std::hypot(u, v) / r0_;
    if (!(r < fold_)) return false;
    const double s = dist_.radial().scale(r);
    u = u * s + dist_.d;
    v = v * s + dist_.e;
    x = 0.5 * static_cast<double>(size_.width) + u + g_ * v;
    y = 0.5 * static_cast<double>(size_.height) + v + t_ * u;
    return in_frame(x, y, size_);
  }

  bool to_ray(double x, double y, Ray& ray) const {
    if (!in_frame(x, y, size_)) return false;
    const double xs = x - 0.5 * static_cast<double>(size_.width),
                 ys = y - 0.5 * static_cast<double>(size_.height);
    double v = (ys - t_ * xs) / (1.0 - t_ * g_);
    double u = xs - g_ * v;
    u -= dist_.d;
    v -= dist_.e;
    const double rs = std::hypot(u, v) / r0_;
    if (!(rs <= rs_max_ * (1.0 + kEdgeSlack))) return false;
    const double s = undistort_scale(rs);
    return from_ideal(u * s, v * s, ray);
  }

  bool contains(double x, double y) const {
    Ray d;
    return to_ray(x, y, d);
  }
  // The valid region is convex (an ellipse or half plane cut by the frame) where the lens is
  // radial or the polynomial is the identity: the corners decide; otherwise never claimed.
  bool covers(double x0, double y0, double x1, double y1) const {
    const bool convex = lens_ == PanoToolsLens::Rectilinear || lens_ == PanoToolsLens::Fisheye ||
                        (dist_.a == 0 && dist_.b == 0 && dist_.c == 0);
    return convex && contains(x0, y0) && contains(x1, y0) && contains(x0, y1) && contains(x1, y1);
  }

  Size size() const { return size_; }
  double center_density() const { return f_ * (1.0 - dist_.a - dist_.b - dist_.c); }
  PanoToolsLens lens() const { return lens_; }
  FisheyeModel model() const { return model_; }
  double hfov() const { return hfov_; }
  const PanoToolsDistortion& distortion() const { return dist_; }
  double fold() const { return fold_; }

 private:
  // The law at angle psi off axis (longitude for the cylinders), with L'(0) = 1.
  double unit_law(double psi) const {
    switch (lens_) {
      case PanoToolsLens::Rectilinear:
        return std::tan(psi);
      case PanoToolsLens::Cylindrical:
      case PanoToolsLens::Equirect:
        return psi;
      case PanoToolsLens::Fisheye:
        return Fisheye::law(model_, psi);
    }
    return psi;
  }

  bool ideal(const Ray& d, double& u, double& v) const {
    switch (lens_) {
      case PanoToolsLens::Rectilinear:
        if (!(d.z() > 0)) return false;
        u = f_ * d.x() / d.z();
        v = f_ * d.y() / d.z();
        return true;
      case PanoToolsLens::Cylindrical: {
        const double hz = std::hypot(d.x(), d.z());
        if (!(hz > 0)) return false;
        u = f_ * std::atan2(d.x(), d.z());
        v = f_ * d.y() / hz;
        return true;
      }
      case PanoToolsLens::Equirect:
        u = f_ * std::atan2(d.x(), d.z());
        v = f_ * std::atan2(d.y(), std::hypot(d.x(), d.z()));
        return true;
      case PanoToolsLens::Fisheye: {
        double cu, cv;
        const double psi = off_axis(d, cu, cv);
        if (psi > Fisheye::law_limit(model_) * (1.0 + kEdgeSlack) ||
            (model_ == FisheyeModel::Stereographic && psi >= kPi))
          return false;
        const double r = f_ * Fisheye::law(model_, psi);
        u = r * cu;
        v = r * cv;
        return true;
      }
    }
    return false;
  }

  bool from_ideal(double u, double v, Ray& d) const {
    const double a = u / f_, b = v / f_;
    switch (lens_) {
      case PanoToolsLens::Rectilinear:
        d = Ray(a, b, 1.0).normalized();
        return true;
      case PanoToolsLens::Cylindrical: {
        if (!(std::fabs(a) <= kPi * (1.0 + kEdgeSlack))) return false;
        const double c = 1.0 / std::sqrt(1.0 + b * b);  // cos lat
        d = Ray(c * std::sin(a), c * b, c * std::cos(a));
        return true;
      }
      case PanoToolsLens::Equirect:
        if (!(std::fabs(a) <= kPi * (1.0 + kEdgeSlack) &&
              std::fabs(b) <= kHalfPi * (1.0 + kEdgeSlack)))
          return false;
        d = ray_from_lonlat(a, -b);
        return true;
      case PanoToolsLens::Fisheye: {
        const double r = std::hypot(a, b);
        double psi;
        if (!Fisheye::inverse_law(model_, r, psi)) return false;
        d = r == 0.0 ? Ray(0.0, 0.0, 1.0) : radial_ray(psi, a, b, r);
        return true;
      }
    }
    return false;
  }

  // r / rs for the ideal radius r with r P(r) = rs (1 / P(0) at the centre).
  double undistort_scale(double rs) const {
    if (dist_.a == 0 && dist_.b == 0 && dist_.c == 0) return 1.0;
    const PTLensLaw law = dist_.radial();
    if (rs == 0.0) return 1.0 / law.d();
    const double r = bracketed_newton([&law](double q) { return law.g(q); },
                                      [&law](double q) { return law.slope(q); }, rs, fold_, rs);
    return r / rs;
  }

  Size size_;
  PanoToolsLens lens_;
  FisheyeModel model_;
  double hfov_;
  PanoToolsDistortion dist_;
  double fold_;
  double f_ = 1, r0_ = 1, g_ = 0, t_ = 0, rs_max_ = 0;
};

}  // namespace panoproj
