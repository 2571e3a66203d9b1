// The cylindrical module (module.hpp): a panorama linear in longitude and in tan(latitude).
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"cylindrical", "cylindrical panorama (vertical extent vfov < 180 deg)",
           {number("hfov", "360", 0, 360, true, false, "longitude span (deg)"),
            number("vfov", "100", 0, 180, true, true, "vertical span (deg), linear in tan(latitude)"), lon0(), lat0()}}};
}

Projection make(const ProjectionSpec& s, Size size) {
  return Cylindrical(size, rad(s, "hfov"), rad(s, "vfov"), rad(s, "lon0"), rad(s, "lat0"));
}

Size size_for(const ProjectionSpec& s, double density) {
  const double top = rad(s, "lat0") + 0.5 * rad(s, "vfov");
  const double bottom = rad(s, "lat0") - 0.5 * rad(s, "vfov");
  return framed_size(s, density * rad(s, "hfov"), density * (std::tan(top) - std::tan(bottom)));
}

Projection rescale(const Projection& p, Size size, double, double) {
  const auto& q = std::get<Cylindrical>(p);
  const double top = std::atan(q.t_top()), bottom = std::atan(q.t_bottom());
  return Cylindrical(size, q.axis().hfov, top - bottom, q.axis().lon0, 0.5 * (top + bottom));
}

// Vertical fields from 0.01 to 179.99 degrees, partial and off-centre ones.
// A full one wraps; its poles are at infinity, never in the frame.
SamplingFacts sampling(const Projection& p) {
  SamplingFacts f = framed_facts(p);
  f.wraps_x = std::get<Cylindrical>(p).full_longitude();
  return f;
}

std::vector<ProjectionCase> cases() {
  return {{"cylindrical", {kTinyFrame, {4096, 1400}, kPhotoFrame, kHugeFrame}},
          {"cylindrical:vfov=179.99", {kPhotoFrame}},
          {"cylindrical:vfov=0.01", {kPhotoFrame}},
          {"cylindrical:hfov=120,vfov=179", {{2048, 4096}}},
          {"cylindrical:vfov=179", {{512, 256}}},
          {"cylindrical:vfov=60,lat0=20,lon0=-90", {{4096, 1024}}}};
}

// Longitude and tan(latitude) are linear in x and y: the window's span and centre.
Projection window(const Projection& p, const PixelRect& r) {
  const auto& q = std::get<Cylindrical>(p);
  const Size s = q.size();
  const auto t_at = [&](int64_t y) {
    return q.t_top() +
           (q.t_bottom() - q.t_top()) * static_cast<double>(y) / static_cast<double>(s.height);
  };
  const double top = std::atan(t_at(r.y0)), bottom = std::atan(t_at(r.y1));
  return Cylindrical(r.size(),
                     q.axis().hfov * static_cast<double>(r.width()) / static_cast<double>(s.width),
                     top - bottom, q.axis().longitude_at(0.5 * static_cast<double>(r.x0 + r.x1)),
                     0.5 * (top + bottom));
}

}  // namespace

const ProjectionModule kCylindricalModule{
    catalog, [](const ProjectionSpec& s) { check_latitude_span(s, true); },
    make,    size_for,
    rescale, cases,
    nullptr, sampling,
    window};

}  // namespace panoproj
