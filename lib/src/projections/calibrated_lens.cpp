// The calibrated-lens module (module.hpp): every calibrated camera model on one CalibratedLens type
// (a radial law, OpenCV's plane distortion, an affine map to pixels): OpenCV's Brown-Conrady with
// its rational and thin-prism terms, Kannala-Brandt, Double Sphere, unified, extended unified,
// Mei's omnidirectional model with radtan, COLMAP's two thin-prism fisheyes, FOV, division,
// PTLens, NVIDIA's F-theta and OCamCalib.
#include <algorithm>
#include <sstream>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

ParamDef numbers_key(const char* key, const char* help) {
  return {key, ParamType::Text, "", 0, 0, false, false, "", help};
}

// The calibrated image's size: a frame of another size is refused (make).
std::vector<ParamDef> with_size(std::vector<ParamDef> p) {
  p.push_back(number(
      "width", "", 0, kInf, true, true,
      "the calibrated image's width (pixels): a frame of another size is refused; default: any"));
  p.push_back(number("height", "", 0, kInf, true, true, "the calibrated image's height (pixels)"));
  return p;
}

// fov, fx, fy, cx, cy, then the law's own keys. fov_default "": as the module's default field.
std::vector<ParamDef> lens_params(const char* fov_default, std::vector<ParamDef> law,
                                  const char* fov_help = nullptr, const char* fx_help = nullptr) {
  std::vector<ParamDef> p{
      number("fov", fov_default, 0, 360, true, false,
             fov_help ? fov_help
                      : "full field of view across the image circle (deg); default: the model's "
                        "whole domain if R stays finite there, else 180"),
      number(
          "fx", "", 0, kInf, true, true,
          fx_help
              ? fx_help
              : "focal length in pixels along x; default: the image circle fills the shorter side"),
      number("fy", "", 0, kInf, true, true, "focal length in pixels along y; default: fx"),
      center("cx"), center("cy")};
  p.insert(p.end(), law.begin(), law.end());
  return with_size(p);
}

constexpr const char* kPlaneFov =
    "full field of view the model is used in (deg); default: up to where the distortion folds, at "
    "most 160";
constexpr const char* kPlaneFx =
    "focal length in pixels along x; default: half the width (hfov 90 undistorted)";

std::vector<ParamDef> affine_keys(std::vector<ParamDef> p) {
  p.push_back(
      number("c", "1", -kInf, kInf, true, true, "affine term c (the calibration's; 1: none)"));
  p.push_back(number("d", "0", -kInf, kInf, true, true, "affine term d"));
  p.push_back(number("e", "0", -kInf, kInf, true, true, "affine term e"));
  return with_size(p);
}

std::vector<ProjectionDef> catalog() {
  std::vector<ParamDef> brown;
  for (const char* k : {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6", "s1", "s2", "s3", "s4"})
    brown.push_back(coefficient(k));
  std::vector<ParamDef> prism, radtan;
  for (const char* k : {"k1", "k2", "p1", "p2", "k3", "k4", "sx1", "sy1"})
    prism.push_back(coefficient(k));
  for (const char* k : {"k0", "k1", "k2", "k3", "k4", "k5", "p0", "p1", "s0", "s1", "s2", "s3"})
    radtan.push_back(coefficient(k));
  std::vector<ParamDef> omni{
      number("xi", "1", 0, kInf, false, true, "xi: the unit sphere's offset (Mei's model)")};
  for (const char* k : {"k1", "k2", "p1", "p2", "k3"}) omni.push_back(coefficient(k));
  return {
      {"brown-conrady",
       "calibrated pinhole camera with OpenCV's distortion: radial k1..k6 (rational), tangential "
       "p1, p2, thin prism s1..s4",
       lens_params("", brown, kPlaneFov, kPlaneFx)},
      {"kannala-brandt", "calibrated fisheye, OpenCV's fisheye model (k1..k4), fov up to 360 deg",
       lens_params("180",
                   {coefficient("k1"), coefficient("k2"), coefficient("k3"), coefficient("k4")})},
      {"double-sphere", "calibrated fisheye, Double Sphere model (Usenko et al. 2018)",
       lens_params("", {number("xi", "0", -1, 1, false, false, "xi: the second sphere's offset"),
                        number("alpha", "0.5", 0, 1, false, false, "alpha")})},
      {"unified", "calibrated fisheye or catadioptric, unified model (Mei and Rives 2007)",
       lens_params("", {number("xi", "1", 0, kInf, false, true,
                               "xi: the sphere's offset (0: pinhole, 1: stereographic)")})},
      {"extended-unified", "calibrated fisheye, extended unified model (Khomutenko et al. 2016)",
       lens_params("", {number("alpha", "0.5", 0, 1, false, false, "alpha"),
                        number("beta", "1", 0, kInf, true, true, "beta (1: the unified model)")})},
      {"omni-radtan",
       "calibrated omnidirectional camera, Mei's model with radtan distortion (Kalibr's "
       "omni-radtan, cv2.omnidir)",
       lens_params("", omni,
                   "full field of view (deg); default: the model's whole domain (at most 180 where "
                   "R is unbounded), up to where the distortion folds")},
      {"thin-prism-fisheye",
       "calibrated fisheye, COLMAP's THIN_PRISM_FISHEYE (k1..k4 on the equidistant plane, p1, p2, "
       "sx1, sy1)",
       lens_params("180", prism)},
      {"rad-tan-thin-prism-fisheye",
       "calibrated fisheye, COLMAP's RAD_TAN_THIN_PRISM_FISHEYE (Project Aria's: k0..k5 in theta, "
       "p0, p1, s0..s3)",
       lens_params("180", radtan)},
      {"devernay-faugeras",
       "calibrated wide-angle camera, the FOV model (Devernay and Faugeras 2001; COLMAP's FOV)",
       lens_params("",
                   {number("omega", "0.5", 0, kPi, true, true,
                           "omega, in radians as COLMAP and Kalibr give it")},
                   "full field of view (deg); default: the model's whole domain (360)", kPlaneFx)},
      {"division",
       "calibrated camera, the one-parameter division model (Fitzgibbon 2001; COLMAP's "
       "SIMPLE_DIVISION and DIVISION)",
       lens_params("", {coefficient("k")},
                   "full field of view (deg); default: 160 where k >= 0 (k > 0: up to where the "
                   "law folds), 180 where k < 0",
                   kPlaneFx)},
      {"ptlens",
       "rectilinear lens with Panorama Tools' a, b, c radial polynomial (lensfun's ptlens model)",
       {number("hfov", "90", 0, 180, true, true,
               "horizontal field of view of the ideal (undistorted) pinhole (deg)"),
        number("fov", "", 0, 180, true, true,
               "full field of view the model is used in (deg); default: up to where the polynomial "
               "folds, at most 160"),
        number("a", "0", -kInf, kInf, true, true,
               "a of r_src = (a r^3 + b r^2 + c r + 1 - a - b - c) r_dst"),
        number("b", "0", -kInf, kInf, true, true, "b"),
        number("c", "0", -kInf, kInf, true, true, "c"), center("cx"), center("cy")}},
      {"f-theta", "calibrated camera, NVIDIA's f-theta model: pixel distance a polynomial in theta",
       affine_keys(
           {number("fov", "", 0, 360, true, false,
                   "full field of view (deg; twice max_angle); default: up to where the polynomial "
                   "folds, at most 180"),
            center("cx"), center("cy"),
            numbers_key("poly",
                        "c0/c1/.../c5: angle_to_pixeldist, pixels at theta^0..theta^5 (c0 = 0)"),
            numbers_key("bw_poly",
                        "pixeldist_to_angle, as the calibration fitted it: only compared with the "
                        "law (info)")})},
      {"ocamcalib",
       "calibrated fisheye or catadioptric camera, Scaramuzza's OCamCalib model "
       "(calib_results.txt)",
       affine_keys(
           {number("fov", "", 0, 360, true, false,
                   "full field of view (deg); default: to the frame's farthest corner, up to where "
                   "pol folds"),
            number("xc", "", -kInf, kInf, true, true,
                   "centre's row (OCamCalib's xc, pixel centres at integers)"),
            number("yc", "", -kInf, kInf, true, true, "centre's column (OCamCalib's yc)"),
            numbers_key("pol", "a0/a1/...: the pixel -> ray polynomial (cam2world's), a0 < 0"),
            numbers_key("invpol",
                        "the fitted inverse (world2cam's): only compared with the law (panoproj "
                        "accuracy)")})},
  };
}

// The plane distortion a spec's keys give (plane_distortion.hpp's coefficients).
PlaneDistortion distortion_of(const ProjectionSpec& s) {
  const std::string& n = s.name();
  auto k = [&](const char* key) { return *s.number(key); };
  PlaneDistortion d;
  if (n == "brown-conrady") {
    d.a = {k("k1"), k("k2"), k("k3"), 0};
    d.b = {k("k4"), k("k5"), k("k6")};
    d.p1 = k("p1"), d.p2 = k("p2");
    d.s = {k("s1"), k("s2"), k("s3"), k("s4")};
  } else if (n == "omni-radtan") {
    d.a = {k("k1"), k("k2"), k("k3"), 0};
    d.p1 = k("p1"), d.p2 = k("p2");
  } else if (n == "thin-prism-fisheye") {
    d.a = {k("k1"), k("k2"), k("k3"), k("k4")};
    d.p1 = k("p1"), d.p2 = k("p2");
    d.s = {k("sx1"), 0, k("sy1"), 0};
  } else if (n == "rad-tan-thin-prism-fisheye") {  // p0 is OpenCV's p2 (COLMAP's formula)
    d.p1 = k("p1"), d.p2 = k("p0");
    d.s = {k("s0"), k("s1"), k("s2"), k("s3")};
  }
  return d;
}

// Laws whose radius is in pixels (their affine term maps it to the frame).
bool pixel_law(const std::string& n) {
  return n == "f-theta" || n == "ocamcalib";
}

LensAffine affine_of(const ProjectionSpec& s) {
  const double c = *s.number("c"), d = *s.number("d"), e = *s.number("e");
  // OCamCalib's (row, column) = [c d; e 1] (x', y') with its ray (x', y', pol): in panoproj's axes
  // (x: column, y: row) the plane point is (y', x') and the ray (y', x', -pol), so A = [1 e; d c].
  const LensAffine A = s.name() == "ocamcalib" ? LensAffine{1, e, d, c} : LensAffine{c, d, e, 1};
  if (!(std::isfinite(A.det()) && std::fabs(A.det()) > 1e-12))
    fail(s, "c, d, e make the affine term singular (expected c - d e != 0)");
  if (A.det() < 0) fail(s, "c, d, e mirror the image (expected c - d e > 0)");
  return A;
}

// OCamCalib's law on a frame: pol's radius reaches the frame's farthest corner (`reach`, pixels
// of the law) and the field ends there, at the fov given, or where theta(rho) stops increasing.
OCamLaw ocam_law(const ProjectionSpec& s, double reach, double& theta_max) {
  const auto pol =
      s.numbers("pol", 2, OCamLaw::kMax, "2 to 16 coefficients a0/a1/... of OCamCalib's pol");
  OCamLaw law;
  law.n = static_cast<int>(pol.size());
  std::copy(pol.begin(), pol.end(), law.pol.begin());
  if (!(law.z(0.0) > 0))
    fail(s, "pol's a0 = " + std::to_string(pol[0]) +
                " (expected a negative value: OCamCalib's z = pol(0) points backward)");
  const double fold = first_fold([&](double r) { return law.rise(r); }, 4.0 * reach);
  std::ostringstream o;
  if (s.number("fov")) {
    theta_max = 0.5 * rad(s, "fov");
    const double end = fold >= 0 ? fold : 4.0 * reach;
    if (!(law.theta(end) >= theta_max)) {
      o << "pol reaches only fov=" << 2 * rad2deg(law.theta(end)) << " deg "
        << (fold >= 0 ? "before it folds back" : "within 4x the frame's farthest corner")
        << " (give fov=" << std::floor(2 * rad2deg(law.theta(end)) * 1e3) / 1e3 << " or less)";
      fail(s, o.str());
    }
    law.rho_max = end;
    law.rho_max = law.radius(theta_max);
  } else {
    law.rho_max = fold >= 0 ? std::fmin(fold, reach) : reach;
    theta_max = law.theta(law.rho_max);
  }
  return law;
}

// A lens spec's law, plane distortion, affine term and field (theta_max) as a CalibratedLens on a
// unit frame: the field must lie in the law's domain, where R increases (the polynomial laws:
// checked) and stays finite, and where the plane distortion does not fold. PTLens's law depends on
// the frame (its radii are in units of half the shorter side), OCamCalib's default field on it (to
// its farthest corner): `frame`, else one the centre keys imply.
CalibratedLens unit_lens(const ProjectionSpec& s, Size frame = {0, 0}) {
  LensLaw law;
  const std::string& n = s.name();
  double fx = 1.0, theta_ocam = 0.0;
  LensAffine A;
  auto k = [&](const char* key) { return *s.number(key); };
  if (n == "kannala-brandt") {
    law = KannalaBrandtLaw{{k("k1"), k("k2"), k("k3"), k("k4"), 0, 0}};
  } else if (n == "thin-prism-fisheye") {
    law = KannalaBrandtLaw{};
  } else if (n == "rad-tan-thin-prism-fisheye") {
    law = KannalaBrandtLaw{{k("k0"), k("k1"), k("k2"), k("k3"), k("k4"), k("k5")}};
  } else if (n == "double-sphere") {
    law = DoubleSphereLaw{k("xi"), k("alpha")};
  } else if (n == "unified" || n == "omni-radtan") {
    law = UnifiedLaw{k("xi")};
  } else if (n == "brown-conrady") {
    law = UnifiedLaw{0.0};
  } else if (n == "extended-unified") {
    law = ExtendedUnifiedLaw{k("alpha"), k("beta")};
  } else if (n == "devernay-faugeras") {
    law = FovLaw{k("omega")};
  } else if (n == "division") {
    law = DivisionLaw{k("k")};
  } else if (n == "f-theta") {
    const auto c = s.numbers("poly", 2, 6, "2 to 6 coefficients c0/c1/... of angle_to_pixeldist");
    FThetaLaw f;
    std::copy(c.begin(), c.end(), f.c.begin());
    if (f.c[0] != 0)
      fail(s, "poly's c0 = " + std::to_string(f.c[0]) +
                  " (expected 0: the axis meets the principal point)");
    law = f;
    A = affine_of(s);
  } else if (n == "ocamcalib") {
    if (!s.given("xc") || !s.given("yc"))
      fail(s,
           "xc and yc are required (the centre's row and column, as calib_results.txt gives them)");
    A = affine_of(s);
    // The frame's farthest corner from the centre, in the law's pixels.
    const double w = frame.width > 0    ? static_cast<double>(frame.width)
                     : s.given("width") ? k("width")
                                        : 2.0 * k("yc") + 1.0;
    const double h = frame.height > 0    ? static_cast<double>(frame.height)
                     : s.given("height") ? k("height")
                                         : 2.0 * k("xc") + 1.0;
    const double det = A.det();
    double reach = 0.0;
    for (double x : {0.0, w})
      for (double y : {0.0, h}) {
        const double px = x - k("yc") - kCvPixelShift, py = y - k("xc") - kCvPixelShift;
        reach =
            std::fmax(reach, std::hypot((A.d * px - A.b * py) / det, (-A.c * px + A.a * py) / det));
      }
    law = ocam_law(s, std::fmax(reach, 1.0), theta_ocam);
  } else {
    const double w = std::fmax(1.0, static_cast<double>(frame.width)),
                 h = std::fmax(1.0, static_cast<double>(frame.height));
    fx = 0.5 * w / std::tan(0.5 * rad(s, "hfov"));
    law = PTLensLaw{k("a"), k("b"), k("c"), fx / (0.5 * std::min(w, h))};
  }
  const double limit = std::visit([](const auto& l) { return l.limit(); }, law);
  const bool bounded = std::visit([](const auto& l) { return l.bounded(); }, law);
  const auto* kb = std::get_if<KannalaBrandtLaw>(&law);
  const auto* pt = std::get_if<PTLensLaw>(&law);
  const auto* ft = std::get_if<FThetaLaw>(&law);
  const PlaneDistortion D = distortion_of(s);
  std::ostringstream o;
  // Default field: the whole domain where R stays finite up to its edge; else 180 degrees if the
  // domain is wider, 160 if it is not (a rectilinear lens); PTLens: up to where its law folds, at
  // most 160; F-theta: at most 180.
  double theta_max = limit;
  if (n == "ocamcalib") {
    theta_max = theta_ocam;
  } else if (s.number("fov")) {
    theta_max = 0.5 * rad(s, "fov");
  } else if (pt || (!bounded && limit <= kHalfPi)) {
    theta_max = deg2rad(80.0);
  } else if (ft) {
    theta_max = kHalfPi;
  } else if (!bounded) {
    theta_max = std::fmin(kHalfPi, limit * (1 - 1e-3));  // short of an edge just past 90 degrees
  }
  if (bounded ? theta_max > limit * (1 + 1e-12) : theta_max >= limit * (1 - 1e-9)) {
    o << "fov=" << 2 * rad2deg(theta_max) << " is past the model's domain (expected fov " << (bounded ? "<= " : "< ")
      << 2 * rad2deg(limit) << ")";
    fail(s, o.str());
  }
  if (const double slope0 = std::visit([](const auto& l) { return l.slope0(); }, law); !(slope0 > 0)) {
    o << "the law does not increase from the centre (R'(0) = " << slope0
      << (pt   ? "; expected a + b + c < 1)"
          : ft ? "; expected c1 > 0)"
               : "; expected a positive value)");
    fail(s, o.str());
  }
  // Where a polynomial law stops increasing: refused inside a given field, the default's end.
  double fold = -1.0;
  if (kb) fold = first_fold([kb](double t) { return kb->slope(t); }, theta_max);
  if (ft) fold = first_fold([ft](double t) { return ft->slope(t); }, theta_max);
  if (pt) {
    const double u = first_fold([pt](double x) { return pt->slope(x); }, pt->s * std::tan(theta_max));
    fold = u < 0 ? -1.0 : std::atan(u / pt->s);
  }
  const char* coefficients = kb   ? (n == "kannala-brandt"       ? "k1..k4"
                                     : n == "thin-prism-fisheye" ? "(none)"
                                                                 : "k0..k5")
                             : ft ? "poly"
                                  : "a, b, c";
  if (fold >= 0 && s.number("fov")) fail_fold(s, coefficients, fold, theta_max);
  if (fold >= 0) theta_max = fold;
  // The plane distortion: its radial part r N(r^2) / D(r^2) must increase (D > 0) and its Jacobian
  // stay positive over the image circle's plane disk.
  if (!D.identity()) {
    const CalibratedLens plain({1, 1}, {}, 0, 0, law, theta_max);
    const double r_end = plain.rd_max();
    auto slope = [&](double r) { return D.denominator(r * r) > 0 ? D.radius_slope(r) : -1.0; };
    if (const double rf = std::isfinite(r_end) ? first_fold(slope, r_end) : -1.0; rf >= 0) {
      const double t = plain.angle(rf);
      if (s.number("fov")) fail_fold(s, "the distortion's radial terms", t, theta_max);
      theta_max = t;
    }
    // The Jacobian on rings of the disk: a defaulted field ends before the first ring where it
    // falls under 1/100 of the centre's (1): nearer a fold the inverse loses digits.
    const CalibratedLens field({1, 1}, {}, 0, 0, law, theta_max);
    for (int i = 0; i < 32; ++i)
      for (int a = 0; a < 64; ++a) {
        const double r = field.rd_max() * (i + 0.5) / 32, phi = 2.0 * kPi * a / 64;
        double j[4];
        D.jacobian(r * std::cos(phi), r * std::sin(phi), j);
        const double det = j[0] * j[3] - j[1] * j[2];
        if (det > (s.number("fov") ? 0.0 : 1e-2)) continue;
        if (s.number("fov") || i == 0) {
          o << "the distortion's tangential or thin-prism terms fold the image "
            << rad2deg(field.angle(r))
            << " deg off axis (expected a distortion without folds: give a smaller fov)";
          fail(s, o.str());
        }
        theta_max = field.angle(field.rd_max() * i / 32);
        i = 32;
        break;
      }
  }
  const CalibratedLens lens({1, 1}, pixel_law(n) ? A : LensAffine::focal(fx, fx), 0, 0, law,
                            theta_max, D);
  if (!(std::isfinite(lens.rd_max()) && lens.rd_max() > 0)) {
    o << "the law reaches R = " << lens.rd_max() << " at fov/2 = " << rad2deg(theta_max)
      << " deg (expected a finite value: give a smaller fov" << (n == "kannala-brandt" ? " or smaller coefficients" : "") << ")";
    fail(s, o.str());
  }
  return lens;
}

// Forms whose default focal length and frame are a pinhole's (hfov 90 undistorted).
bool pinhole_framed(const std::string& n) {
  return n == "brown-conrady" || n == "devernay-faugeras" || n == "division";
}

Projection make(const ProjectionSpec& s, Size size) {
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  // A calibration's focal lengths, centre and pixel laws are in its image's pixels.
  if ((s.given("width") && *s.number("width") != w) ||
      (s.given("height") && *s.number("height") != h)) {
    std::ostringstream o;
    o << "the calibration is of " << (s.given("width") ? *s.number("width") : w) << "x"
      << (s.given("height") ? *s.number("height") : h) << " images, this frame is " << size.width
      << "x" << size.height
      << " (expected the calibrated size: its focal lengths and centre are in its pixels)";
    fail(s, o.str());
  }
  const CalibratedLens unit = unit_lens(s, size);
  const std::string& n = s.name();
  if (n == "ocamcalib")
    return CalibratedLens(size, unit.affine(), *s.number("yc") + kCvPixelShift,
                          *s.number("xc") + kCvPixelShift, unit.law(), unit.theta_max());
  const double cx = center_of(s, "cx", w), cy = center_of(s, "cy", h);
  if (n == "ptlens" || n == "f-theta")
    return CalibratedLens(size, unit.affine(), cx, cy, unit.law(), unit.theta_max());
  // Default focal length: the image circle fills the shorter side (a pinhole's: half the width).
  const auto [fx, fy] =
      focal_lengths(s, pinhole_framed(n) ? 0.5 * w : 0.5 * std::min(w, h) / unit.rd_max());
  return CalibratedLens(size, LensAffine::focal(fx, fy), cx, cy, unit.law(), unit.theta_max(),
                        unit.distortion());
}

Size size_for(const ProjectionSpec& s, double density) {
  const std::string& n = s.name();
  if (s.given("width") && s.given("height")) {  // the calibrated image
    unit_lens(s);
    return framed_size(s, *s.number("width"), *s.number("height"));
  }
  if (n == "ptlens") {  // a square frame (PTLens radii are in its half side)
    unit_lens(s);
    const double w = 2.0 * density / (1.0 - *s.number("a") - *s.number("b") - *s.number("c")) * std::tan(0.5 * rad(s, "hfov"));
    return framed_size(s, w, w);
  }
  const CalibratedLens unit = unit_lens(s);
  if (n == "ocamcalib")  // the frame its centre is the middle of
    return framed_size(s, 2.0 * *s.number("yc") + 1.0, 2.0 * *s.number("xc") + 1.0);
  if (n == "f-theta") {  // the image circle's bounding box; its scale is the calibration's
    const LensAffine& A = unit.affine();
    return framed_size(s, 2.0 * unit.rd_max() * std::hypot(A.a, A.b),
                       2.0 * unit.rd_max() * std::hypot(A.c, A.d));
  }
  // A 90-degree undistorted pinhole's frame, or the image circle's diameter, at the given focal
  // lengths, else at `density` pixels per radian at the centre (f R'(0) = density).
  const auto [fx, fy] = focal_lengths(s, density / unit.center_density());
  const double extent = pinhole_framed(n) ? 1.0 : unit.rd_max();
  return framed_size(s, 2.0 * fx * extent, 2.0 * fy * extent);
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  const auto& q = std::get<CalibratedLens>(p);
  return CalibratedLens(size, q.affine().scaled(sx, sy), q.cx() * sx, q.cy() * sy, q.law(),
                        q.theta_max(), q.distortion());
}

// Kannala-Brandt: the equidistant law, tiny and 360-degree fields, a field ending 0.01 degree
// before the law folds back (theta (1 - 0.1 theta^2): the Newton inverse's slope tends to 0 at
// the rim), calibrations from real lenses. The closed-form laws over their whole domain, and
// unbounded ones at their default 180 degrees: where R stays bounded (unified xi > 1, extended
// unified alpha > 1/2) its slope reaches 0 at the domain's edge, so theta(R) has the conditioning
// of sqrt there, as the orthographic fisheye's: 1.1e-6 px at the rim of a 40000-px image.
// PTLens: a plain rectilinear lens to 160 degrees, one whose polynomial folds (the field ends
// there). Brown-Conrady: a pinhole to 160 degrees, barrel distortion up to its fold, tangential,
// rational and thin-prism terms (the focal lengths scaled with the frame). The new models at
// calibrations of their kind, their parameters' extremes and their widest fields.
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
  c.push_back({"brown-conrady", {kTinyFrame, {1920, 1080}, {40000, 22500}}});
  c.push_back({"brown-conrady:k1=-0.3", {{1920, 1080}, {40000, 22500}}});
  c.push_back(
      {"brown-conrady:fx=1000,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0.01", {{1920, 1080}}});
  c.push_back(
      {"brown-conrady:fx=20833,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0.01", {{40000, 22500}}});
  c.push_back(
      {"brown-conrady:fx=1000,fy=1002,cx=959.5,cy=539.5,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0."
       "01",
       {{1920, 1080}}});
  c.push_back({"brown-conrady:fx=800,k1=0.15,k2=0.02,p1=-0.004,p2=0.003", {{1920, 1080}}});
  c.push_back({"brown-conrady:fov=100,fx=600,k1=-0.3,k2=0.1", {{1920, 1080}}});
  // The models added with OpenCV's rational and thin-prism terms round-trip within 1e-9 px (5e-11
  // px measured, 40000-px frames included).
  constexpr double kExact = 1e-9;
  // OpenCV's rational and thin-prism terms (a wide lens as calibrateCamera fits them).
  c.push_back(
      {"brown-conrady:fx=700,fy=702,cx=958.3,cy=541.2,k1=2.1,k2=0.9,p1=0.0004,p2=-0.0003,k3=0.02,"
       "k4=2.45,k5=1.6,"
       "k6=0.15,s1=0.001,s2=-0.0002,s3=-0.0008,s4=0.0001",
       {{1920, 1080}},
       kExact});
  c.push_back(
      {"brown-conrady:k1=2.1,k2=0.9,p1=0.0004,p2=-0.0003,k3=0.02,k4=2.45,k5=1.6,k6=0.15,s1=0.001,"
       "s2=-0.0002,"
       "s3=-0.0008,s4=0.0001",
       {kTinyFrame, {40000, 22500}},
       kExact});
  c.push_back(
      {"brown-conrady:fov=90,fx=500,k1=-0.25,k4=0.1,s1=0.004,s3=-0.003", {{1920, 1080}}, kExact});
  // Mei's omni-radtan (an Insta360 lens as Kalibr fits it; xi = 0, 1 and past 1: the domain's
  // edge), to its widest field.
  c.push_back(
      {"omni-radtan:xi=1.82,fx=741.5,fy=740.7,cx=639.6,cy=511.2,k1=-0.0346,k2=0.0236,p1=0.0004,p2=-"
       "0.0009",
       {{1280, 1024}},
       kExact});
  c.push_back({"omni-radtan:xi=1.82,k1=-0.0346,k2=0.0236,p1=0.0004,p2=-0.0009",
               {kTinyFrame, {40000, 32000}},
               kExact});
  c.push_back({"omni-radtan:xi=0.9,fov=200,k1=-0.1,k2=0.02,p1=0.001,p2=0.002,k3=-0.001",
               {{1024, 1024}},
               kExact});
  c.push_back({"omni-radtan:xi=0,k1=-0.2", {{1920, 1080}}, kExact});
  c.push_back({"omni-radtan:xi=1.5,k1=0.01", {{1024, 1024}, {40000, 40000}}, kExact});
  // COLMAP's thin-prism fisheyes to 180 and 220 degrees (Project Aria's calibration form).
  c.push_back(
      {"thin-prism-fisheye:fx=620,fy=621,cx=959.5,cy=539.5,k1=0.03,k2=-0.01,p1=0.0005,p2=-0.0004,"
       "k3=0.002,"
       "k4=-0.0003,sx1=0.0006,sy1=-0.0007",
       {{1920, 1080}},
       kExact});
  c.push_back(
      {"thin-prism-fisheye:k1=0.03,k2=-0.01,p1=0.0005,p2=-0.0004,k3=0.002,k4=-0.0003,sx1=0.0006,"
       "sy1=-0.0007",
       {kTinyFrame, {40000, 22500}},
       kExact});
  c.push_back({"thin-prism-fisheye:fov=220,k1=0.02,p1=0.001,sx1=0.002", {{2048, 2048}}, kExact});
  c.push_back(
      {"rad-tan-thin-prism-fisheye:fx=241.2,fy=241.2,cx=316.6,cy=237.9,k0=-0.0255,k1=0.0998,k2=-0."
       "0697,k3=0.0132,"
       "k4=0.0034,k5=-0.0012,p0=0.0003,p1=-0.0002,s0=-0.0004,s1=0.0001,s2=0.0005,s3=-0.0001",
       {{640, 480}},
       kExact});
  c.push_back(
      {"rad-tan-thin-prism-fisheye:k0=-0.0255,k1=0.0998,k2=-0.0697,k3=0.0132,k4=0.0034,k5=-0.0012,"
       "p0=0.0003,"
       "p1=-0.0002,s0=-0.0004,s1=0.0001,s2=0.0005,s3=-0.0001",
       {kTinyFrame, {40000, 30000}},
       kExact});
  c.push_back(
      {"rad-tan-thin-prism-fisheye:fov=220,k0=0.01,p0=0.001,s2=0.002", {{2048, 2048}}, kExact});
  // FOV: a calibration, omega near 0 (the pinhole) and near pi, the whole 360-degree domain.
  c.push_back(
      {"devernay-faugeras:fx=500,fy=501,cx=640.2,cy=360.7,omega=0.93", {{1280, 720}}, kExact});
  c.push_back({"devernay-faugeras:omega=0.93", {kTinyFrame, {40000, 22500}}, kExact});
  c.push_back({"devernay-faugeras:omega=1e-6", {{1280, 720}}, kExact});
  c.push_back({"devernay-faugeras:fov=360,omega=3", {{1024, 1024}, {40000, 40000}}, kExact});
  c.push_back({"devernay-faugeras:fov=120,omega=0.5", {{1280, 720}}, kExact});
  // Division: barrel (past 90 degrees: to 300), pincushion up to its fold, k = 0.
  c.push_back({"division:fx=800,k=-0.25", {kTinyFrame, {1920, 1080}, {40000, 22500}}, kExact});
  c.push_back({"division:fov=300,k=-0.8", {{2048, 2048}, {40000, 40000}}, kExact});
  c.push_back({"division:k=0.05", {{1920, 1080}}, kExact});
  c.push_back({"division:k=0", {{1920, 1080}}, kExact});
  // F-theta: an automotive wide camera's polynomial (all powers), and one folding past 180.
  c.push_back(
      {"f-theta:fov=200,cx=1925.4,cy=1084.6,poly=0/1090.6/-12.8/-34.1/6.2/"
       "-0.55,c=1.0003,d=0.0002,e=-0.0001",
       {{3848, 2168}},
       kExact});
  c.push_back({"f-theta:poly=0/500/0/-20", {kTinyFrame, {1920, 1080}}, kExact});
  // OCamCalib: the toolbox's example calibration (a 190-degree fisheye on 1024x768), and its
  // field to a given fov.
  c.push_back(
      {"ocamcalib:xc=383.943115,yc=511.652588,pol=-244.5239/0/0.0017486/-2.904e-06/"
       "1.046e-08,c=1.000144,d=0.000114,"
       "e=-0.000153",
       {kTinyFrame, {1024, 768}},
       kExact});
  c.push_back({"ocamcalib:xc=383.9,yc=511.6,pol=-244.5239/0/0.0017486/-2.904e-06/1.046e-08,fov=190",
               {{1024, 768}},
               kExact});
  return c;
}

}  // namespace

const ProjectionModule kCalibratedLensModule{catalog, [](const ProjectionSpec& s) { unit_lens(s); }, make, size_for, rescale, cases};

}  // namespace panoproj
