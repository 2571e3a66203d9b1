// The normal cylindrical world maps' module (module.hpp): Mercator, Miller and the cylindrical
// equal-area map.
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

ParamDef lat_max(const char* def, bool open) {
  return number("lat_max", def, 0, 90, true, open, "the latitude the map ends at, north and south (deg)");
}

std::vector<ProjectionDef> catalog() {
  return {{"mercator",
           "Mercator conformal world map (to lat_max; 85.0511: a square, as web maps)",
           {lat_max("85.0511287798066", true), lon0(), map_aspect(), map_hfov()}},
          {"miller",
           "Miller cylindrical world map",
           {lat_max("90", false), lon0(), map_aspect(), map_hfov()}},
          {"cylindrical-equal-area",
           "cylindrical equal-area world map (Lambert's at lat_ts=0, Gall-Peters at 45)",
           {number("lat_ts", "0", -90, 90, true, true, "standard parallel (deg): true scale there"),
            lat_max("90", false), lon0(), map_aspect(), map_hfov()}}};
}

CylindricalMap map_of(const ProjectionSpec& s, Size size) {
  const CylindricalLaw law = s.name() == "mercator" ? CylindricalLaw::Mercator
                             : s.name() == "miller" ? CylindricalLaw::Miller
                                                    : CylindricalLaw::EqualArea;
  return CylindricalMap(size, law, rad(s, "lat_max"), law == CylindricalLaw::EqualArea ? rad(s, "lat_ts") : 0.0,
                        rad(s, "lon0"));
}

Projection make(const ProjectionSpec& s, Size size) { return map_framed(s, map_of(s, size)); }

Size size_for(const ProjectionSpec& s, double density) { return map_size(s, map_of(s, {1000, 1000}).frame(), density); }

Projection rescale(const Projection& p, Size size, double, double) { return std::get<CylindricalMap>(p).resized(size); }

// The outline's box (inside a keep-aspect frame: fractional pixels) holds a whole turn; Miller and
// the equal-area map to 90 degrees end at the pole lines, whose taps continue over the pole as an
// equirect's (their Y is symmetric about the pole, so the mirrored row is the far side's);
// Mercator never reaches its pole.
SamplingFacts sampling(const Projection& p) {
  const auto& m = std::get<CylindricalMap>(p);
  const MapFrame& fr = m.frame();
  SamplingFacts f;
  f.x0 = fr.pixel_x(-kPi), f.x1 = fr.pixel_x(kPi);
  f.y0 = fr.pixel_y(m.y_max()), f.y1 = fr.pixel_y(-m.y_max());
  f.wraps_x = true;
  f.north_pole = f.south_pole =
      m.law() != CylindricalLaw::Mercator && m.phi_max() >= kHalfPi * (1.0 - 1e-12);
  return f;
}

// Round trips within 1e-9 px. Each law at its defaults from 1x1 to 40000 px; Mercator near its pole; Gall-Peters, a standard
// parallel near the pole; stretched and square frames.
std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> c;
  for (const char* s : {"mercator", "miller", "cylindrical-equal-area"})
    c.push_back({s, {kTinyFrame, {512, 512}, kPhotoFrame, kHugeFrame}, 1e-9});
  for (const char* s :
       {"mercator:lat_max=89.999", "mercator:lat_max=1e-6,aspect=stretch",
        "cylindrical-equal-area:lat_ts=45", "cylindrical-equal-area:lat_ts=-89.9,aspect=stretch",
        "miller:lat_max=60,lon0=-120", "mercator:aspect=stretch",
        "mercator:lat_max=89.999999,hfov=300", "miller:hfov=0.5",
        "cylindrical-equal-area:hfov=360"})
    c.push_back({s, {{2048, 1024}}, 1e-9});
  return c;
}

}  // namespace

const ProjectionModule kCylindricalMapModule{
    catalog, nullptr, make, size_for, rescale, cases, always, sampling, map_window<CylindricalMap>};

}  // namespace panoproj
