// The calibrated-lens module (module.hpp): Kannala-Brandt, Double Sphere, unified, extended
// unified and PTLens laws on one CalibratedLens type.
#include <algorithm>
#include <sstream>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

// fov, fx, fy, cx, cy, then the law's own keys. fov_default "": the law's whole domain.
std::vector<ParamDef> lens_params(const char* fov_default, std::vector<ParamDef> law) {
  std::vector<ParamDef> p{
      number("fov", fov_default, 0, 360, true, false,
             "full field of view across the image circle (deg); default: the model's whole domain if R stays finite there, else 180"),
      number("fx", "", 0, kInf, true, true, "focal length in pixels along x; default: the image circle fills the shorter side"),
      number("fy", "", 0, kInf, true, true, "focal length in pixels along y; default: fx"), center("cx"), center("cy")};
  p.insert(p.end(), law.begin(), law.end());
  return p;
}

std::vector<ProjectionDef> catalog() {
  return {
      {"kannala-brandt", "calibrated fisheye, OpenCV's fisheye model (k1..k4), fov up to 360 deg",
       lens_params("180", {coefficient("k1"), coefficient("k2"), coefficient("k3"), coefficient("k4")})},
      {"double-sphere", "calibrated fisheye, Double Sphere model (Usenko et al. 2018)",
       lens_params("", {number("xi", "0", -1, 1, false, false, "xi: the second sphere's offset"),
                        number("alpha", "0.5", 0, 1, false, false, "alpha")})},
      {"unified", "calibrated fisheye or catadioptric, unified model (Mei and Rives 2007)",
       lens_params("", {number("xi", "1", 0, kInf, false, true, "xi: the sphere's offset (0: pinhole, 1: stereographic)")})},
      {"extended-unified", "calibrated fisheye, extended unified model (Khomutenko et al. 2016)",
       lens_params("", {number("alpha", "0.5", 0, 1, false, false, "alpha"),
                        number("beta", "1", 0, kInf, true, true, "beta (1: the unified model)")})},
      {"ptlens", "rectilinear lens with Panorama Tools' a, b, c radial polynomial (lensfun's ptlens model)",
       {number("hfov", "90", 0, 180, true, true, "horizontal field of view of the ideal (undistorted) pinhole (deg)"),
        number("fov", "", 0, 180, true, true,
               "full field of view the model is used in (deg); default: up to where the polynomial folds, at most 160"),
        number("a", "0", -kInf, kInf, true, true, "a of r_src = (a r^3 + b r^2 + c r + 1 - a - b - c) r_dst"),
        number("b", "0", -kInf, kInf, true, true, "b"), number("c", "0", -kInf, kInf, true, true, "c"), center("cx"),
        center("cy")}},
  };
}

// A lens spec's law and field (theta_max): the field must lie in the law's domain, where R
// increases (the polynomial laws: checked) and stays finite. PTLens's law depends on the frame
// (its radii are in units of half the shorter side): `frame`, or a square one for checks.
CalibratedLens unit_lens(const ProjectionSpec& s, Size frame = {1, 1}) {
  LensLaw law;
  const std::string& n = s.name();
  double fx = 1.0;
  if (n == "kannala-brandt") {
    law = KannalaBrandtLaw{{*s.number("k1"), *s.number("k2"), *s.number("k3"), *s.number("k4")}};
  } else if (n == "double-sphere") {
    law = DoubleSphereLaw{*s.number("xi"), *s.number("alpha")};
  } else if (n == "unified") {
    law = UnifiedLaw{*s.number("xi")};
  } else if (n == "extended-unified") {
    law = ExtendedUnifiedLaw{*s.number("alpha"), *s.number("beta")};
  } else {
    const auto w = static_cast<double>(frame.width), h = static_cast<double>(frame.height);
    fx = 0.5 * w / std::tan(0.5 * rad(s, "hfov"));
    law = PTLensLaw{*s.number("a"), *s.number("b"), *s.number("c"), fx / (0.5 * std::min(w, h))};
  }
  const double limit = std::visit([](const auto& l) { return l.limit(); }, law);
  const bool bounded = std::visit([](const auto& l) { return l.bounded(); }, law);
  const auto* kb = std::get_if<KannalaBrandtLaw>(&law);
  const auto* pt = std::get_if<PTLensLaw>(&law);
  std::ostringstream o;
  // Default field: the whole domain where R stays finite up to its edge; else 180 degrees if the
  // domain is wider; PTLens (a rectilinear lens): up to where its law folds, at most 160.
  double theta_max = limit;
  if (s.number("fov")) {
    theta_max = 0.5 * rad(s, "fov");
  } else if (pt) {
    theta_max = deg2rad(80.0);
  } else if (!bounded) {
    if (limit <= kHalfPi) {
      o << "R grows without bound toward the model's domain edge at " << rad2deg(limit)
        << " deg off axis: give fov below " << 2 * rad2deg(limit);
      fail(s, o.str());
    }
    theta_max = std::fmin(kHalfPi, limit * (1 - 1e-3));  // short of an edge just past 90 degrees
  }
  if (bounded ? theta_max > limit * (1 + 1e-12) : theta_max >= limit * (1 - 1e-9)) {
    o << "fov=" << 2 * rad2deg(theta_max) << " is past the model's domain (expected fov " << (bounded ? "<= " : "< ")
      << 2 * rad2deg(limit) << ")";
    fail(s, o.str());
  }
  if (const double slope0 = std::visit([](const auto& l) { return l.slope0(); }, law); !(slope0 > 0)) {
    o << "the law does not increase from the centre (R'(0) = " << slope0
      << (pt ? "; expected a + b + c < 1)" : "; expected a positive value)");
    fail(s, o.str());
  }
  // Where a polynomial law stops increasing: refused inside a given field, the default's end.
  double fold = -1.0;
  if (kb) fold = first_fold([kb](double t) { return kb->slope(t); }, theta_max);
  if (pt) {
    const double u = first_fold([pt](double x) { return pt->slope(x); }, pt->s * std::tan(theta_max));
    fold = u < 0 ? -1.0 : std::atan(u / pt->s);
  }
  if (fold >= 0 && (kb || s.number("fov"))) fail_fold(s, kb ? "k1..k4" : "a, b, c", fold, theta_max);
  if (fold >= 0) theta_max = fold;
  const CalibratedLens lens({1, 1}, fx, fx, 0, 0, law, theta_max);
  if (!(std::isfinite(lens.rd_max()) && lens.rd_max() > 0)) {
    o << "the law reaches R = " << lens.rd_max() << " at fov/2 = " << rad2deg(theta_max)
      << " deg (expected a finite value: give a smaller fov" << (n == "kannala-brandt" ? " or smaller coefficients" : "") << ")";
    fail(s, o.str());
  }
  return lens;
}

Projection make(const ProjectionSpec& s, Size size) {
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  const CalibratedLens unit = unit_lens(s, size);
  const double cx = center_of(s, "cx", w), cy = center_of(s, "cy", h);
  if (s.name() == "ptlens") return CalibratedLens(size, unit.fx(), unit.fx(), cx, cy, unit.law(), unit.theta_max());
  // Default focal length: the image circle fills the shorter side.
  const auto [fx, fy] = focal_lengths(s, 0.5 * std::min(w, h) / unit.rd_max());
  return CalibratedLens(size, fx, fy, cx, cy, unit.law(), unit.theta_max());
}

Size size_for(const ProjectionSpec& s, double density) {
  if (s.name() == "ptlens") {  // a square frame (PTLens radii are in its half side)
    unit_lens(s);
    const double w = 2.0 * density / (1.0 - *s.number("a") - *s.number("b") - *s.number("c")) * std::tan(0.5 * rad(s, "hfov"));
    return framed_size(s, w, w);
  }
  // The image circle's diameter at the given focal lengths, else at `density` pixels per radian
  // at the centre (f R'(0) = density).
  const CalibratedLens unit = unit_lens(s);
  const auto [fx, fy] = focal_lengths(s, density / unit.center_density());
  return framed_size(s, 2.0 * fx * unit.rd_max(), 2.0 * fy * unit.rd_max());
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  const auto& q = std::get<CalibratedLens>(p);
  return CalibratedLens(size, q.fx() * sx, q.fy() * sy, q.cx() * sx, q.cy() * sy, q.law(), q.theta_max());
}

// Kannala-Brandt: the equidistant law, tiny and 360-degree fields, a field ending 0.01 degree
// before the law folds back (theta (1 - 0.1 theta^2): the Newton inverse's slope tends to 0 at
// the rim), calibrations from real lenses. The closed-form laws over their whole domain, and
// unbounded ones at their default 180 degrees: where R stays bounded (unified xi > 1, extended
// unified alpha > 1/2) its slope reaches 0 at the domain's edge, so theta(R) has the conditioning
// of sqrt there, as the orthographic fisheye's: 1.1e-6 px at the rim of a 40000-px image.
// PTLens: a plain rectilinear lens to 160 degrees, one whose polynomial folds (the field ends
// there).
std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> c;
  for (const char* f : {"0.01", "180", "360"})
    c.push_back({std::string("kannala-brandt:fov=") + f + ",k1=-0.01,k2=0.0005", {kTinyFrame, {2048, 2048}, {40000, 40000}}});
  c.push_back({"kannala-brandt:fov=209.2,k1=-0.1", {{2048, 2048}, {40000, 40000}}});
  c.push_back({"kannala-brandt", {{2048, 2048}}});
  c.push_back({"kannala-brandt:fov=0.01,k1=0.3", {{2048, 2048}}});
  c.push_back({"kannala-brandt:fov=220,k1=0.02,k2=-0.005,k3=0.001,k4=-0.0001", {{2048, 2048}}});
  c.push_back({"kannala-brandt:fov=195,fx=620.5,fy=621.3,cx=959.2,cy=541.7,k1=0.0361,k2=-0.0112,k3=0.0028,k4=-0.0004",
               {{1920, 1080}}});
  for (const char* s : {"double-sphere:xi=-0.18,alpha=0.59", "double-sphere:xi=0.3,alpha=0.4", "unified:xi=2.5",
                        "unified:xi=0.8", "extended-unified:alpha=0.63,beta=1.04", "extended-unified:alpha=0.3,beta=2"}) {
    c.push_back({s, {kTinyFrame, {1024, 1024}, {2048, 2048}}});
    c.push_back({s, {{40000, 40000}}, 1e-5});
  }
  c.push_back({"double-sphere:xi=-0.18,alpha=0.59,fov=190,fx=313.2,fy=313.1,cx=638.9,cy=514.6", {{1280, 1024}}});
  c.push_back({"unified", {{1024, 1024}}});
  c.push_back({"extended-unified:alpha=0.3,beta=2,fov=200", {{1024, 1024}}});
  c.push_back({"ptlens", {kTinyFrame, {1920, 1080}, {40000, 22500}}});
  c.push_back({"ptlens:hfov=100,a=-0.2,b=0.05,c=-0.01", {{1920, 1080}, {40000, 22500}}});
  c.push_back({"ptlens:hfov=70,a=0.01,b=-0.05,c=0.02", {{1920, 1080}}});
  c.push_back({"ptlens:hfov=100,b=-0.1", {{1920, 1280}}});
  return c;
}

}  // namespace

const ProjectionModule kCalibratedLensModule{catalog, [](const ProjectionSpec& s) { unit_lens(s); }, make, size_for, rescale, cases};

}  // namespace panoproj
