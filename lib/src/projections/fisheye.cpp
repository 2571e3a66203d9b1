// The fisheye module (module.hpp): one of four radial laws, fov up to 360 degrees, a circle or a
// stretched ellipse.
#include <algorithm>
#include <sstream>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {

namespace spec_support {

FisheyeModel fisheye_model(const std::string& m) {
  if (m == "equisolid") return FisheyeModel::Equisolid;
  if (m == "orthographic") return FisheyeModel::Orthographic;
  if (m == "stereographic") return FisheyeModel::Stereographic;
  if (m == "thoby") return FisheyeModel::Thoby;
  return FisheyeModel::Equidistant;
}

void check_fisheye_fov(const ProjectionSpec& s, const char* key, double fov) {
  const auto model = fisheye_model(s.choice("model"));
  std::ostringstream o;
  o << key << "=" << fov;
  if (model == FisheyeModel::Orthographic && fov > 180) fail(s, o.str() + " is too wide for model=orthographic (expected <= 180)");
  if (model == FisheyeModel::Stereographic && fov >= 360)
    fail(s, o.str() + " is not reachable with model=stereographic (expected < 360)");
  if (model == FisheyeModel::Thoby) {
    const double widest = 2.0 * rad2deg(Fisheye::law_limit(model, *s.number("k2")));
    if (fov > widest || (fov == widest && widest < 360)) {
      std::ostringstream w;
      w << o.str() << " is past where model=thoby with k2=" << *s.number("k2") << " turns back (expected < " << widest << ")";
      fail(s, w.str());
    }
  }
}

Fisheye fisheye_scaled(const Fisheye& q, Size size, double sx, double sy) {
  return Fisheye(size, q.psi_max(), q.model(), q.clip(), q.cx() * sx, q.cy() * sy, q.rx() * sx, q.ry() * sy, q.k2());
}

}  // namespace spec_support

namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"fisheye", "fisheye lens with a radial law, fov up to 360 deg",
           {number("fov", "180", 0, 360, true, false, "full field of view across the image circle"),
            choice("model", "equidistant", "equidistant|equisolid|orthographic|stereographic|thoby",
                   "lens law (orthographic: fov <= 180; stereographic: fov < 360; thoby: r ~ sin(k2 theta), fov < 180/k2)"),
            number("k2", "0.713", 0, 10, true, false, "model=thoby's k2 (r = k1 f sin(k2 theta); k1 f is set by the image circle)"),
            choice("clip", "circle", "circle|none", "circle: pixels outside the image circle are invalid; none: keep rays past fov/2"),
            choice("aspect", "keep", "keep|stretch", "keep: a circle of square pixels; stretch: an ellipse filling the frame"),
            number("radius", "", 0, kInf, true, true, "image-circle radius in pixels (aspect=keep); default: half the shorter side"),
            center("cx"), center("cy")}}};
}

void check(const ProjectionSpec& s) {
  check_fisheye_fov(s, "fov", *s.number("fov"));
  if (s.given("k2") && s.choice("model") != "thoby") fail(s, "k2 applies to model=thoby");
  if (s.given("radius") && s.choice("aspect") == "stretch") fail(s, "radius applies to aspect=keep only (stretch fills the frame)");
}

Projection make(const ProjectionSpec& s, Size size) {
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  const double psi_max = 0.5 * rad(s, "fov");
  double rx, ry;
  if (s.choice("aspect") == "stretch") {
    rx = 0.5 * w;
    ry = 0.5 * h;
  } else {
    rx = ry = s.given("radius") ? *s.number("radius") : 0.5 * std::min(w, h);
  }
  return Fisheye(size, psi_max, fisheye_model(s.choice("model")), s.choice("clip") == "circle", center_of(s, "cx", w),
                 center_of(s, "cy", h), rx, ry, *s.number("k2"));
}

Size size_for(const ProjectionSpec& s, double density) {
  const double r =
      s.given("radius") ? *s.number("radius")
                        : density * Fisheye::law(fisheye_model(s.choice("model")), 0.5 * rad(s, "fov"), *s.number("k2"));
  return framed_size(s, 2.0 * r, 2.0 * r);
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  return fisheye_scaled(std::get<Fisheye>(p), size, sx, sy);
}

// Every law from 0.001 degrees to its domain's end (360, or 180 for orthographic), unclipped
// circles, a stretched frame, an explicit circle.
std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> c;
  for (const char* m : {"equidistant", "equisolid", "orthographic", "stereographic"})
    for (const char* f : {"0.01", "1", "90", "180", "270", "359.99"}) {
      const double fov = std::stod(f);
      const bool ortho = std::string(m) == "orthographic";
      if ((ortho && fov > 180) || (std::string(m) == "stereographic" && fov > 359)) continue;
      const std::string spec = std::string("fisheye:fov=") + f + ",model=" + m;
      // Orthographic r = sin(psi): its inverse's condition 1 / cos(psi) grows towards 90 degrees
      // (1.5e-6 px at the rim of a 40000-px 180-degree image).
      c.push_back({spec, {kTinyFrame, {2048, 2048}}});
      c.push_back({spec, {{40000, 40000}}, ortho ? 1e-5 : 1e-6});
    }
  for (const char* s : {"fisheye:fov=0.001", "fisheye:fov=359.9", "fisheye:fov=360,clip=none"})
    c.push_back({s, {{512, 256}}});
  for (const char* s : {"fisheye:fov=0.001", "fisheye:fov=360", "fisheye:fov=359.9", "fisheye:fov=360,model=equisolid",
                        "fisheye:fov=0.001,model=equisolid", "fisheye:fov=60,model=orthographic",
                        "fisheye:fov=359.9,model=stereographic", "fisheye:fov=200,clip=none",
                        "fisheye:fov=190,radius=900,cx=1000,cy=1020.5"})
    c.push_back({s, {{2048, 2048}}});
  c.push_back({"fisheye:fov=210", {{512, 512}}});
  c.push_back({"fisheye:fov=180,clip=none", {{3000, 2000}}});
  c.push_back({"fisheye:fov=120,model=equisolid,clip=none", {{3000, 2000}}});
  c.push_back({"fisheye:fov=200,aspect=stretch", {{4096, 2048}}});
  // Thoby: the default lens, near its turning point, a k2 under 1/2 (monotonic to 360 degrees).
  for (const char* s : {"fisheye:model=thoby", "fisheye:model=thoby,fov=252.4", "fisheye:model=thoby,fov=0.01",
                        "fisheye:model=thoby,k2=0.4,fov=360", "fisheye:model=thoby,k2=2,fov=89,clip=none"})
    c.push_back({s, {kTinyFrame, {2048, 2048}, {40000, 40000}}, 1e-9});
  return c;
}

Projection window(const Projection& p, const PixelRect& r) {
  const auto& q = std::get<Fisheye>(p);
  return Fisheye(r.size(), q.psi_max(), q.model(), q.clip(), q.cx() - static_cast<double>(r.x0),
                 q.cy() - static_cast<double>(r.y0), q.rx(), q.ry(), q.k2());
}

}  // namespace

const ProjectionModule kFisheyeModule{catalog, check,   make,    size_for, rescale,
                                      cases,   nullptr, nullptr, window};

}  // namespace panoproj
