// The pinhole's module (module.hpp): a rectilinear camera given by hfov/vfov or a focal length.
#include <cmath>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"pinhole", "rectilinear camera (fov < 180 deg)",
           {number("hfov", "", 0, 180, true, true, "horizontal field of view (deg); default 90 unless focal or vfov is given"),
            number("vfov", "", 0, 180, true, true, "vertical field of view (deg); default: square pixels"),
            number("focal", "", 0, kInf, true, true, "focal length in pixels (instead of hfov)"), center("cx"),
            center("cy")}}};
}

void check(const ProjectionSpec& s) {
  if (s.given("hfov") && s.given("focal")) fail(s, "give hfov or focal, not both");
  if (s.given("vfov") && s.given("focal")) fail(s, "give vfov or focal, not both");
}

Projection make(const ProjectionSpec& s, Size size) {
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  double fx, fy;
  if (s.given("focal")) {
    fx = fy = *s.number("focal");
  } else if (s.given("hfov")) {
    fx = 0.5 * w / std::tan(0.5 * rad(s, "hfov"));
    fy = s.given("vfov") ? 0.5 * h / std::tan(0.5 * rad(s, "vfov")) : fx;
  } else if (s.given("vfov")) {
    fx = fy = 0.5 * h / std::tan(0.5 * rad(s, "vfov"));
  } else {
    fx = fy = 0.5 * w / std::tan(deg2rad(45.0));  // hfov 90
  }
  return Pinhole(size, fx, fy, center_of(s, "cx", w), center_of(s, "cy", h));
}

// Focal length = density (pixels per radian on the axis).
Size size_for(const ProjectionSpec& s, double density) {
  const double f = s.given("focal") ? *s.number("focal") : density;
  const double hf = s.given("hfov") ? rad(s, "hfov") : (s.given("vfov") ? 0.0 : deg2rad(90));
  const double vf = s.given("vfov") ? rad(s, "vfov") : hf;
  return framed_size(s, 2.0 * f * std::tan(0.5 * (hf > 0 ? hf : vf)), 2.0 * f * std::tan(0.5 * vf));
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  const auto& q = std::get<Pinhole>(p);
  return Pinhole(size, q.fx() * sx, q.fy() * sy, q.cx() * sx, q.cy() * sy);
}

// Fields of view from 0.01 to 179.99 degrees; an off-centre principal point; a wide 3:2 frame.
std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> c;
  for (const char* f : {"0.01", "1", "90", "179", "179.99"})
    c.push_back({std::string("pinhole:hfov=") + f, {kTinyFrame, {512, 256}, {1920, 1080}, kHugeFrame}});
  c.push_back({"pinhole:hfov=150,vfov=100", {{1920, 1080}}});
  c.push_back({"pinhole:focal=1000,cx=900.25,cy=500", {{1920, 1080}}});
  return c;
}

Projection window(const Projection& p, const PixelRect& r) {
  const auto& q = std::get<Pinhole>(p);
  return Pinhole(r.size(), q.fx(), q.fy(), q.cx() - static_cast<double>(r.x0),
                 q.cy() - static_cast<double>(r.y0));
}

}  // namespace

const ProjectionModule kPinholeModule{catalog, check,   make,    size_for, rescale,
                                      cases,   nullptr, nullptr, window};

}  // namespace panoproj
