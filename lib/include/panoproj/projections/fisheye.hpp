#pragma once
// Fisheye with a radial lens law. psi = angle from the optical axis (+z), theta = azimuth in the
// image. The law maps psi to an unnormalized radius g(psi), all with g'(0) = 1:
//   equidistant   g = psi             (defined for psi <= pi)
//   equisolid     g = 2 sin(psi/2)    (psi <= pi)
//   orthographic  g = sin(psi)        (psi <= pi/2)
//   stereographic g = 2 tan(psi/2)    (psi <  pi)
//   thoby         g = sin(k2 psi) / k2 (k2 psi < pi/2): Thoby's r = k1 f sin(k2 psi), whose k1 f
//                                       the image circle sets (Thoby, "Nikkor 10.5 mm fisheye"
//                                       measurements, 2006: k1 = 1.47, k2 = 0.713; as in Hugin
//                                       and lensfun)
// Normalized radius r = g(psi) / g(psi_max): r = 1 on the image circle (fov = 2 psi_max).
// Pixel: (x, y) = (cx, cy) + r * (rx cos theta, ry sin theta); rx = ry keeps a circle ("keep"),
// rx != ry draws an ellipse ("stretch"). Formulas: Kingslake, "A History of the Photographic
// Lens"; Bettonvil, "Fisheye lenses", WGN 33 (2005).
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

enum class FisheyeModel { Equidistant, Equisolid, Orthographic, Stereographic, Thoby };

inline constexpr double kThobyK2 = 0.713;

class Fisheye {
 public:
  // psi_max: half the field of view (radians). clip: pixels with r > 1 are invalid.
  // k2: Thoby's (other laws ignore it).
  Fisheye(Size size, double psi_max, FisheyeModel model, bool clip, double cx, double cy,
          double rx, double ry, double k2 = kThobyK2)
      : size_(size), psi_max_(psi_max), model_(model), clip_(clip), cx_(cx), cy_(cy), rx_(rx),
        ry_(ry), k2_(k2), g_max_(law(psi_max)), psi_limit_(law_limit(model, k2)) {}

  static double law(FisheyeModel m, double psi, double k2 = kThobyK2) {
    switch (m) {
      case FisheyeModel::Equidistant: return psi;
      case FisheyeModel::Equisolid: return 2.0 * std::sin(0.5 * psi);
      case FisheyeModel::Orthographic: return std::sin(psi);
      case FisheyeModel::Stereographic: return 2.0 * std::tan(0.5 * psi);
      case FisheyeModel::Thoby: return std::sin(k2 * psi) / k2;
    }
    return psi;
  }
  // Largest psi for which the law is monotonic (and so invertible).
  static double law_limit(FisheyeModel m, double k2 = kThobyK2) {
    if (m == FisheyeModel::Thoby) return std::fmin(kPi, kHalfPi / k2);
    return m == FisheyeModel::Orthographic ? kHalfPi : kPi;
  }
  double law(double psi) const { return law(model_, psi, k2_); }
  // psi from g = law(m, psi); false where the law has no inverse.
  static bool inverse_law(FisheyeModel m, double g, double& psi, double k2 = kThobyK2) {
    switch (m) {
      case FisheyeModel::Equidistant:
        psi = g;
        return g <= kPi * (1.0 + kEdgeSlack);
      case FisheyeModel::Equisolid:
        if (g > 2.0 * (1.0 + kEdgeSlack)) return false;
        psi = 2.0 * std::asin(std::fmin(0.5 * g, 1.0));
        return true;
      case FisheyeModel::Orthographic:
        if (g > 1.0 + kEdgeSlack) return false;
        psi = std::asin(std::fmin(g, 1.0));
        return true;
      case FisheyeModel::Stereographic:
        psi = 2.0 * std::atan(0.5 * g);
        return true;
      case FisheyeModel::Thoby:
        if (g * k2 > 1.0 + kEdgeSlack) return false;
        psi = std::asin(std::fmin(g * k2, 1.0)) / k2;
        return true;
    }
    return false;
  }

  bool to_ray(double x, double y, Ray& d) const {
    const double u = (x - cx_) / rx_, v = (y - cy_) / ry_;
    const double r = std::hypot(u, v);
    if (clip_ && r > 1.0 + kEdgeSlack) return false;
    double psi;
    if (!inverse_law(r * g_max_, psi)) return false;
    if (r == 0.0) {
      d = Ray(0.0, 0.0, 1.0);
      return true;
    }
    d = radial_ray(psi, u, v, r);
    return true;
  }

  bool to_pixel(const Ray& d, double& x, double& y) const {
    double cu, cv;
    const double psi = off_axis(d, cu, cv);
    // The rim's slack in psi, or as to_ray gives it, in r: where the law flattens (equisolid
    // near 360 degrees), r's 1e-9 is far more than psi's (found by the stability report).
    if (clip_ && psi > psi_max_ * (1.0 + kEdgeSlack) && law(psi) > g_max_ * (1.0 + kEdgeSlack)) return false;
    if (psi > psi_limit_ * (1.0 + kEdgeSlack) || (model_ == FisheyeModel::Stereographic && psi >= kPi))
      return false;
    const double r = law(psi) / g_max_;
    x = cx_ + rx_ * r * cu;
    y = cy_ + ry_ * r * cv;
    return in_frame(x, y, size_);
  }

  // Whether pixel position (x, y) has a ray (cheap form of to_ray's test).
  bool contains(double x, double y) const {
    if (!in_frame(x, y, size_)) return false;
    const double r = std::hypot((x - cx_) / rx_, (y - cy_) / ry_);
    if (clip_) return r <= 1.0 + kEdgeSlack;
    double psi;
    return inverse_law(r * g_max_, psi);
  }

  // True only if every position in [x0, x1] x [y0, y1] has a ray: the valid region (an ellipse,
  // or the frame) is convex, so its four corners decide.
  bool covers(double x0, double y0, double x1, double y1) const {
    return contains(x0, y0) && contains(x1, y0) && contains(x0, y1) && contains(x1, y1);
  }
  Size size() const { return size_; }
  double center_density() const { return rx_ / g_max_; }  // g'(0) = 1
  double psi_max() const { return psi_max_; }
  FisheyeModel model() const { return model_; }
  bool clip() const { return clip_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  double rx() const { return rx_; }
  double ry() const { return ry_; }
  double g_max() const { return g_max_; }
  double k2() const { return k2_; }
  double psi_limit() const { return psi_limit_; }  // where the law stops being invertible

 private:
  bool inverse_law(double g, double& psi) const { return inverse_law(model_, g, psi, k2_); }

  Size size_;
  double psi_max_;
  FisheyeModel model_;
  bool clip_;
  double cx_, cy_, rx_, ry_, k2_;
  double g_max_, psi_limit_;
};

}  // namespace panoproj
