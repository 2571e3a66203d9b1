// The transverse Mercator module (module.hpp): Mercator turned a quarter, conformal along a meridian.
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"transverse-mercator",
           "transverse Mercator map (the central meridian straight; to x_max either side)",
           {number("x_max", "85.0511287798066", 0, 90, true, true,
                   "the angle from the central meridian the map ends at (deg; 85.0511: a square)"),
            lon0(), map_aspect(), map_hfov()}}};
}

TransverseMercator map_of(const ProjectionSpec& s, Size size) {
  return TransverseMercator(size, rad(s, "x_max"), rad(s, "lon0"));
}

Projection make(const ProjectionSpec& s, Size size) { return map_framed(s, map_of(s, size)); }

Size size_for(const ProjectionSpec& s, double density) { return map_size(s, map_of(s, {1000, 1000}).frame(), density); }

Projection rescale(const Projection& p, Size size, double, double) { return std::get<TransverseMercator>(p).resized(size); }

// Round trips within 1e-9 px; 1e-6 where |X| reaches 19.2 (x_max where sin rounds to 1): the map
// magnifies a ray's last-bit rounding by cosh X = 1e8 there. The default from 1x1 to 40000 px;
// near its singular points; a narrow strip; a turned meridian.
std::vector<ProjectionCase> cases() {
  return {{"transverse-mercator", {kTinyFrame, {512, 512}, kPhotoFrame, kHugeFrame}, 1e-9},
          {"transverse-mercator:x_max=89.999", {{2048, 2048}}, 1e-9},
          {"transverse-mercator:x_max=89.999999,hfov=120", {{2048, 1024}}, 1e-9},
          {"transverse-mercator:x_max=89.9999995", {{2048, 2048}}, 1e-6},
          {"transverse-mercator:x_max=3,lon0=9", {{256, 4096}}, 1e-9},
          {"transverse-mercator:aspect=stretch", {{2048, 1024}}, 1e-9}};
}

}  // namespace

// Every ray but the two singular points: shown whole, as a target.
const ProjectionModule kTransverseMercatorModule{catalog,  nullptr, make,
                                                 size_for, rescale, cases,
                                                 always,   nullptr, map_window<TransverseMercator>};

}  // namespace panoproj
