// The Hammer module (module.hpp): Hammer-Wagner equal-area world maps, Eckert-Greifendorff among
// them.
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"hammer", "Hammer(-Wagner) equal-area world map",
           {number("w", "0.5", 0, 1, true, true, "Wagner's W (0.5: Hammer, 0.25: Eckert-Greifendorff)"), lon0()}},
          {"eckert-greifendorff", "Eckert-Greifendorff equal-area map (Hammer W = 0.25)",
           {number("w", "0.25", 0, 1, true, true, "Wagner's W"), lon0()}}};
}

Projection make(const ProjectionSpec& s, Size size) { return Hammer(size, *s.number("w"), rad(s, "lon0")); }

// Unit scale at the centre: the frame in plane units.
Size size_for(const ProjectionSpec& s, double density) {
  return map_size(s, Hammer({1000, 1000}, *s.number("w"), rad(s, "lon0")).frame(), density);
}

Projection rescale(const Projection& p, Size size, double, double) {
  const auto& q = std::get<Hammer>(p);
  return Hammer(size, q.w(), q.lon0());
}

}  // namespace

const ProjectionModule kHammerModule{catalog, nullptr, make, size_for, rescale, always};

}  // namespace panoproj
