// The Panorama Tools image's module (module.hpp): Hugin's and libpano13's lens types with their
// radial polynomial, shift and shear (panotools.hpp).
#include <algorithm>
#include <sstream>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

constexpr const char* kLenses =
    "rectilinear|cylindrical|equirect|equidistant|orthographic|stereographic|equisolid|thoby";

std::vector<ProjectionDef> catalog() {
  return {{"panotools",
           "an image as Hugin and Panorama Tools describe it: lens type, hfov, radial a b c, shift "
           "d e, shear g t",
           {choice("lens", "rectilinear", kLenses,
                   "the lens type (Hugin's f: 0 rectilinear, 1 cylindrical, 2 and 3 equidistant, 4 "
                   "equirect, "
                   "8 orthographic, 10 stereographic, 20 thoby, 21 equisolid)"),
            number("hfov", "", 0, 360, true, false,
                   "horizontal field of view (deg, Hugin's v); default 90"),
            number("a", "0", -kInf, kInf, true, true,
                   "a of the radial scale a r^3 + b r^2 + c r + 1 - a - b - c, r in half the "
                   "shorter side"),
            number("b", "0", -kInf, kInf, true, true, "b"),
            number("c", "0", -kInf, kInf, true, true, "c"),
            number("d", "0", -kInf, kInf, true, true, "horizontal shift of the centre (pixels)"),
            number("e", "0", -kInf, kInf, true, true, "vertical shift of the centre (pixels)"),
            number("g", "0", -kInf, kInf, true, true, "shear: x += g y / height"),
            number("t", "0", -kInf, kInf, true, true, "shear: y += t x / width")}}};
}

PanoToolsLens lens_of(const std::string& name) {
  if (name == "rectilinear") return PanoToolsLens::Rectilinear;
  if (name == "cylindrical") return PanoToolsLens::Cylindrical;
  if (name == "equirect") return PanoToolsLens::Equirect;
  return PanoToolsLens::Fisheye;
}

double hfov_deg(const ProjectionSpec& s) {
  return s.number("hfov") ? *s.number("hfov") : 90.0;
}

void check(const ProjectionSpec& s) {
  const std::string lens = s.choice("lens");
  const double v = hfov_deg(s);
  std::ostringstream o;
  o << "hfov=" << v << " is too wide for lens=" << lens;
  if (lens == "rectilinear" && v >= 180) fail(s, o.str() + " (expected < 180)");
  if (lens == "orthographic" && v > 180) fail(s, o.str() + " (expected <= 180)");
  if (lens == "stereographic" && v >= 360) fail(s, o.str() + " (expected < 360)");
  if (lens == "thoby" && 0.5 * deg2rad(v) * kThobyK2 > kHalfPi)
    fail(s, o.str() + " (expected <= 252.45)");
  const PTLensLaw law =
      PanoToolsDistortion{*s.number("a"), *s.number("b"), *s.number("c")}.radial();
  if (!(law.d() > 0)) {
    o.str("");
    o << "the radial scale does not increase from the centre (1 - a - b - c = " << law.d()
      << "; expected a + b + c < 1)";
    fail(s, o.str());
  }
  if (!(std::fabs(*s.number("g")) < 1e6 && std::fabs(*s.number("t")) < 1e6))
    fail(s, "g and t must be below 1e6");
}

// Where r P(r) first stops increasing (libpano13's correction radius), at most its bound: on the
// image's range finely, then beyond it.
double fold_of(const PanoToolsDistortion& d) {
  const PTLensLaw law = d.radial();
  const auto slope = [&law](double r) { return law.slope(r); };
  const double near = first_fold(slope, 4.0);
  if (near >= 0) return near;
  const double far = first_fold(slope, kPanoToolsMaxRadius);
  return far >= 0 ? far : kPanoToolsMaxRadius;
}

PanoTools make_lens(const ProjectionSpec& s, Size size, double scale_x = 1, double scale_y = 1) {
  PanoToolsDistortion d{*s.number("a"),           *s.number("b"),
                        *s.number("c"),           *s.number("d") * scale_x,
                        *s.number("e") * scale_y, *s.number("g") * scale_x,
                        *s.number("t") * scale_y};
  const std::string lens = s.choice("lens");
  const FisheyeModel model =
      lens == "equidistant" ? FisheyeModel::Equidistant : fisheye_model(lens);
  const PanoTools p(size, lens_of(lens), model, deg2rad(hfov_deg(s)), d, fold_of(d));
  if (!(std::fabs(1.0 - p.distortion().t / static_cast<double>(size.width) * p.distortion().g /
                            static_cast<double>(size.height)) > 1e-9))
    fail(s, "the shear g, t is singular (g t = width x height)");
  return p;
}

Projection make(const ProjectionSpec& s, Size size) {
  return make_lens(s, size);
}

// The width that puts `density` pixels per radian at the centre; fisheyes square, the cylinders
// 2:1, rectilinear 3:2.
Size size_for(const ProjectionSpec& s, double density) {
  const PanoTools unit = make_lens(s, {2, 2});
  const double w = 2.0 * density / unit.center_density();
  const double h = unit.lens() == PanoToolsLens::Fisheye
                       ? w
                       : w / (unit.lens() == PanoToolsLens::Rectilinear ? 1.5 : 2.0);
  return framed_size(s, w, h);
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  const auto& q = std::get<PanoTools>(p);
  PanoToolsDistortion d = q.distortion();
  d.d *= sx, d.e *= sy, d.g *= sx, d.t *= sy;
  return PanoTools(size, q.lens(), q.model(), q.hfov(), d, q.fold());
}

// A whole turn across, undistorted (an equirect or cylinder as they are): taps wrap, and an
// equirect twice as wide as high reaches both poles.
SamplingFacts sampling(const Projection& p) {
  const auto& q = std::get<PanoTools>(p);
  SamplingFacts f = framed_facts(p);
  const PanoToolsDistortion& d = q.distortion();
  const bool cylinder =
      q.lens() == PanoToolsLens::Equirect || q.lens() == PanoToolsLens::Cylindrical;
  if (!cylinder || q.hfov() < kTwoPi * (1 - 1e-12) || d.a != 0 || d.b != 0 || d.c != 0 ||
      d.d != 0 || d.g != 0 || d.t != 0)
    return f;
  f.wraps_x = true;
  if (q.lens() == PanoToolsLens::Equirect) {
    f.rows_hold_turn = true;
    const double half =
        kPi * static_cast<double>(q.size().height) / static_cast<double>(q.size().width);
    const double e = d.e / (static_cast<double>(q.size().width) / kTwoPi);  // the shift in radians
    f.north_pole = std::fabs(half + e - kHalfPi) < 1e-12;
    f.south_pole = std::fabs(half - e - kHalfPi) < 1e-12;
  }
  return f;
}

// Every lens type plain and with a b c d e g t; fields near 0 and at each law's widest; a
// polynomial that folds inside the image (its corners have no ray).
std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> c;
  const char* dist = ",a=0.01,b=-0.03,c=0.02,d=12.5,e=-7.25,g=3,t=-2";
  for (const char* l : {"rectilinear", "cylindrical", "equirect", "equidistant", "orthographic",
                        "stereographic", "equisolid", "thoby"}) {
    const std::string base = std::string("panotools:lens=") + l;
    c.push_back({base, {kTinyFrame, {1920, 1080}}});
    c.push_back({base + dist, {{1920, 1080}, {40000, 22500}}});
  }
  c.push_back({"panotools:hfov=0.01", {{1920, 1080}}});
  c.push_back({"panotools:hfov=179", {{1920, 1080}}});
  c.push_back({"panotools:lens=equirect,hfov=360", {{4096, 2048}}});
  c.push_back({"panotools:lens=equidistant,hfov=360,a=0.02,b=-0.05", {{2048, 2048}}});
  c.push_back({"panotools:lens=stereographic,hfov=300", {{2048, 2048}}});
  c.push_back({"panotools:lens=orthographic,hfov=180", {{2048, 2048}}});
  c.push_back({"panotools:lens=thoby,hfov=252", {{2048, 2048}}});
  c.push_back({"panotools:hfov=100,b=-0.3", {{1920, 1280}}});
  return c;
}

}  // namespace

const ProjectionModule kPanoToolsModule{catalog, check, make,    size_for,
                                        rescale, cases, nullptr, sampling};

}  // namespace panoproj
