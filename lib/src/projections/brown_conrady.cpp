// The Brown-Conrady module (module.hpp): OpenCV's calibrated pinhole with radial and tangential
// distortion.
#include <sstream>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"brown-conrady",
           "calibrated pinhole camera with OpenCV's radial and tangential distortion (k1, k2, p1, p2, k3)",
           {number("fov", "", 0, 180, true, true,
                   "full field of view the model is used in (deg); default: up to where the radial distortion folds, at most 160"),
            number("fx", "", 0, kInf, true, true, "focal length in pixels along x; default: half the width (hfov 90 undistorted)"),
            number("fy", "", 0, kInf, true, true, "focal length in pixels along y; default: fx"), center("cx"), center("cy"),
            coefficient("k1"), coefficient("k2"), coefficient("p1"), coefficient("p2"), coefficient("k3")}}};
}

// The coefficients and field (theta_max) on a unit frame: the field must end before the radial
// factor r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing, and the map's Jacobian must stay
// positive over it (tangential terms).
BrownConrady unit_camera(const ProjectionSpec& s) {
  const std::array<double, 5> d{*s.number("k1"), *s.number("k2"), *s.number("p1"), *s.number("p2"), *s.number("k3")};
  // The radial factor's slope 1 + 3 k1 r^2 + 5 k2 r^4 + 7 k3 r^6: its first zero up to r_cap.
  auto slope = [&](double r) {
    const double r2 = r * r;
    return 1.0 + r2 * (3.0 * d[0] + r2 * (5.0 * d[1] + r2 * 7.0 * d[4]));
  };
  const double r_cap = std::tan(deg2rad(s.number("fov") ? 0.5 * *s.number("fov") : 80.0));
  const double fold = first_fold(slope, r_cap);
  if (fold >= 0 && s.number("fov")) fail_fold(s, "k1, k2, k3", std::atan(fold), 0.5 * rad(s, "fov"));
  const double theta_max = std::atan(fold >= 0 ? fold : r_cap);
  const BrownConrady cam({1, 1}, 1, 1, 0, 0, d, theta_max);
  for (int i = 0; i < 32; ++i)
    for (int a = 0; a < 64; ++a) {
      const double r = std::tan(theta_max) * (i + 0.5) / 32, phi = 2.0 * kPi * a / 64;
      double j[4];
      cam.jacobian(r * std::cos(phi), r * std::sin(phi), j);
      if (!(j[0] * j[3] - j[1] * j[2] > 0.0)) {
        std::ostringstream o;
        o << "p1, p2 fold the image " << rad2deg(std::atan(r)) << " deg off axis (expected a distortion without folds: "
          << "give a smaller fov)";
        fail(s, o.str());
      }
    }
  return cam;
}

Projection make(const ProjectionSpec& s, Size size) {
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  const BrownConrady unit = unit_camera(s);
  const auto [fx, fy] = focal_lengths(s, 0.5 * w);
  return BrownConrady(size, fx, fy, center_of(s, "cx", w), center_of(s, "cy", h), unit.coefficients(), unit.theta_max());
}

// The frame of a 90-degree undistorted pinhole at the given focal lengths, else at `density`
// pixels per radian at the centre.
Size size_for(const ProjectionSpec& s, double density) {
  unit_camera(s);
  const auto [fx, fy] = focal_lengths(s, density);
  return framed_size(s, 2.0 * fx, 2.0 * fy);
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  const auto& q = std::get<BrownConrady>(p);
  return BrownConrady(size, q.fx() * sx, q.fy() * sy, q.cx() * sx, q.cy() * sy, q.coefficients(), q.theta_max());
}

// A pinhole to 160 degrees, barrel distortion up to its fold, tangential terms (the focal
// lengths scaled with the frame), unequal focal lengths.
std::vector<ProjectionCase> cases() {
  return {{"brown-conrady", {kTinyFrame, {1920, 1080}, {40000, 22500}}},
          {"brown-conrady:k1=-0.3", {{1920, 1080}, {40000, 22500}}},
          {"brown-conrady:fx=1000,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0.01", {{1920, 1080}}},
          {"brown-conrady:fx=20833,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0.01", {{40000, 22500}}},
          {"brown-conrady:fx=1000,fy=1002,cx=959.5,cy=539.5,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0.01",
           {{1920, 1080}}},
          {"brown-conrady:fx=800,k1=0.15,k2=0.02,p1=-0.004,p2=0.003", {{1920, 1080}}},
          {"brown-conrady:fov=100,fx=600,k1=-0.3,k2=0.1", {{1920, 1080}}}};
}

}  // namespace

const ProjectionModule kBrownConradyModule{catalog, [](const ProjectionSpec& s) { unit_camera(s); }, make, size_for,
                                           rescale, cases};

}  // namespace panoproj
