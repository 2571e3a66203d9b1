// The Hammer module (module.hpp): Hammer-Wagner equal-area world maps, Eckert-Greifendorff among
// them.
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {
      {"hammer",
       "Hammer(-Wagner) equal-area world map",
       {number("w", "0.5", 0, 1, true, true, "Wagner's W (0.5: Hammer, 0.25: Eckert-Greifendorff)"),
        lon0(), map_aspect(), map_hfov()}},
      {"eckert-greifendorff",
       "Eckert-Greifendorff equal-area map (Hammer W = 0.25)",
       {number("w", "0.25", 0, 1, true, true, "Wagner's W"), lon0(), map_aspect(), map_hfov()}}};
}

Projection make(const ProjectionSpec& s, Size size) { return map_framed(s, Hammer(size, *s.number("w"), rad(s, "lon0"))); }

// Unit scale at the centre: the frame in plane units.
Size size_for(const ProjectionSpec& s, double density) {
  return map_size(s, Hammer({1000, 1000}, *s.number("w"), rad(s, "lon0")).frame(), density);
}

Projection rescale(const Projection& p, Size size, double, double) { return std::get<Hammer>(p).resized(size); }

// Hammer from 1x1 to 40000 px, Eckert-Greifendorff (W = 0.25), a W near 1.
std::vector<ProjectionCase> cases() {
  return {{"hammer:aspect=stretch", {kTinyFrame}},
          {"hammer", {{512, 256}, kPhotoFrame, kHugeFrame}},
          {"eckert-greifendorff", {{512, 256}, kPhotoFrame, {4096, 1892}}},
          {"hammer:w=0.9", {{2048, 1024}}},
          {"hammer:hfov=200", {{2048, 1024}}},
          {"hammer", {{1000, 1000}}},
          {"eckert-greifendorff:aspect=stretch", {{1000, 1000}}}};
}

}  // namespace

const ProjectionModule kHammerModule{catalog, nullptr, make,    size_for,          rescale,
                                     cases,   always,  nullptr, map_window<Hammer>};

}  // namespace panoproj
