// The Mollweide module (module.hpp): the equal-area world map in a 2:1 ellipse.
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"mollweide",
           "Mollweide equal-area world map (2:1 ellipse)",
           {lon0(), map_aspect(), map_hfov()}}};
}

Projection make(const ProjectionSpec& s, Size size) { return map_framed(s, Mollweide(size, rad(s, "lon0"))); }

// `density` pixels per radian along the equator at the centre, where X = (2 sqrt 2 / pi) lambda.
Size size_for(const ProjectionSpec& s, double density) {
  return map_size(s, Mollweide({1000, 1000}, rad(s, "lon0")).frame(), density * kPi / (2.0 * Mollweide::kSqrt2));
}

Projection rescale(const Projection& p, Size size, double, double) { return std::get<Mollweide>(p).resized(size); }

// Round trips within 1e-9 px, from 1x1 to 40000 px; a square frame; a turned central meridian.
std::vector<ProjectionCase> cases() {
  return {{"mollweide:aspect=stretch", {kTinyFrame}, 1e-9}, {"mollweide", {{512, 256}, kPhotoFrame, kHugeFrame}, 1e-9},
          {"mollweide:lon0=-75", {{1024, 1024}}, 1e-9},
          {"mollweide:aspect=stretch", {{1024, 1024}}, 1e-9}};
}

}  // namespace

const ProjectionModule kMollweideModule{
    catalog, nullptr, make, size_for, rescale, cases, always, nullptr, map_window<Mollweide>};

}  // namespace panoproj
