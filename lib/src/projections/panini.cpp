// The Panini module (module.hpp): General Panini (Sharpless) and OpenCV's Panini and compressed
// rectilinear warpers, views of up to 360 degrees with straight verticals.
#include <cmath>
#include <sstream>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

ParamDef hfov() { return number("hfov", "120", 0, 360, true, true, "horizontal field of view (deg)"); }
ParamDef vfov() {
  return number("vfov", "", 0, 180, true, true,
                "vertical field of view along the centre line (deg); default: square pixels at the centre");
}

std::vector<ProjectionDef> catalog() {
  return {{"panini", "Panini view: General Panini (Sharpless, Hugin, v360) or OpenCV's Panini warper",
           {choice("model", "sharpless", "sharpless|opencv",
                   "sharpless: x = (d + 1) sin(lon) / (d + cos(lon)); opencv: OpenCV's PaniniProjector (a, b)"),
            number("d", "1", 0, kInf, false, true, "sharpless: 0 rectilinear, 1 classic Panini, larger compresses more"),
            number("vc", "0", 0, 1, false, false, "sharpless: vertical compression (0: lines through the centre straight)"),
            number("a", "2", 0, kInf, true, true, "opencv: u = a tan(lon / a)"),
            number("b", "1", 0, kInf, true, true, "opencv: v = b u tan(lat) / sin(lon)"), hfov(), vfov()}},
          {"compressed-rectilinear", "OpenCV's compressed rectilinear warper (compressedPlane)",
           {number("a", "2", 0, kInf, true, true, "u = a tan(lon / a)"),
            number("b", "1", 0, kInf, true, true, "v = b tan(lat) / cos(lon)"), hfov(), vfov()}}};
}

PaniniLaw law_of(const ProjectionSpec& s) {
  if (s.name() == "compressed-rectilinear") return PaniniLaw::Compressed;
  return s.choice("model") == "opencv" ? PaniniLaw::OpenCV : PaniniLaw::Sharpless;
}
double p1(const ProjectionSpec& s) { return law_of(s) == PaniniLaw::Sharpless ? *s.number("d") : *s.number("a"); }
double p2(const ProjectionSpec& s) { return law_of(s) == PaniniLaw::Sharpless ? *s.number("vc") : *s.number("b"); }

void check(const ProjectionSpec& s) {
  const PaniniLaw law = law_of(s);
  if (law == PaniniLaw::Sharpless && (s.given("a") || s.given("b"))) fail(s, "a and b apply to model=opencv (sharpless takes d and vc)");
  if (law == PaniniLaw::OpenCV && (s.given("d") || s.given("vc"))) fail(s, "d and vc apply to model=sharpless (opencv takes a and b)");
  const double widest = 2.0 * rad2deg(Panini::lambda_max(law, p1(s)));
  if (*s.number("hfov") >= widest) {
    std::ostringstream o;
    o << "hfov=" << *s.number("hfov") << " is past what the law maps one to one (expected < " << widest << " deg here)";
    fail(s, o.str());
  }
}

// Pixels per plane unit: fx from hfov across the width, fy from vfov along the centre line (else fx).
Projection make(const ProjectionSpec& s, Size size) {
  const PaniniLaw law = law_of(s);
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  const double fx = 0.5 * w / Panini::F(law, p1(s), 0.5 * rad(s, "hfov"));
  const double fy = s.given("vfov") ? 0.5 * h / (std::tan(0.5 * rad(s, "vfov")) * Panini::center_k(law, p2(s))) : fx;
  return Panini(size, law, p1(s), p2(s), fx, fy, 0.5 * w, 0.5 * h);
}

// `density` pixels per radian at the centre (F'(0) = 1); the height from vfov, else 3/4 of the width.
Size size_for(const ProjectionSpec& s, double density) {
  const PaniniLaw law = law_of(s);
  const double w = 2.0 * density * Panini::F(law, p1(s), 0.5 * rad(s, "hfov"));
  const double h =
      s.given("vfov") ? 2.0 * density * Panini::center_k(law, p2(s)) * std::tan(0.5 * rad(s, "vfov")) : 0.75 * w;
  return framed_size(s, w, h);
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  const auto& q = std::get<Panini>(p);
  return Panini(size, q.law(), q.p1(), q.p2(), q.fx() * sx, q.fy() * sy, q.cx() * sx, q.cy() * sy);
}

// Round trips within 1e-9 px. Each law from rectilinear to its widest field; vertical compression; 1x1 to 40000 px.
std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> c;
  for (const char* s : {"panini", "panini:model=opencv", "compressed-rectilinear"})
    c.push_back({s, {kTinyFrame, {1920, 1080}, kHugeFrame}, 1e-9});
  for (const char* s : {"panini:d=0,hfov=170", "panini:d=1,hfov=359", "panini:d=3,hfov=200", "panini:d=0.5,vc=1,hfov=200",
                        "panini:d=1e-9,hfov=0.01", "panini:vc=0.5,vfov=100", "panini:model=opencv,a=1,hfov=179",
                        "panini:model=opencv,a=1.5,b=1,hfov=260", "panini:model=opencv,a=3,b=2,hfov=359",
                        "compressed-rectilinear:a=1.5,b=0.5,hfov=170", "compressed-rectilinear:a=0.5,hfov=89"})
    c.push_back({s, {{2048, 1024}}, 1e-9});
  return c;
}

Projection window(const Projection& p, const PixelRect& r) {
  const auto& q = std::get<Panini>(p);
  return Panini(r.size(), q.law(), q.p1(), q.p2(), q.fx(), q.fy(),
                q.cx() - static_cast<double>(r.x0), q.cy() - static_cast<double>(r.y0));
}

}  // namespace

const ProjectionModule kPaniniModule{catalog, check,   make,    size_for, rescale,
                                     cases,   nullptr, nullptr, window};

}  // namespace panoproj
