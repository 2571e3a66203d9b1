// The Aitoff module (module.hpp): the world map in a 2:1 ellipse.
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"aitoff", "Aitoff world map (2:1 ellipse)", {lon0(), map_aspect(), map_hfov()}}};
}

Projection make(const ProjectionSpec& s, Size size) { return map_framed(s, Aitoff(size, rad(s, "lon0"))); }

// Unit scale at the centre: the frame in plane units.
Size size_for(const ProjectionSpec& s, double density) {
  return map_size(s, Aitoff({1000, 1000}, rad(s, "lon0")).frame(), density);
}

Projection rescale(const Projection& p, Size size, double, double) { return std::get<Aitoff>(p).resized(size); }

// The Newton inverse from 1x1 to 40000 px; a turned central meridian.
std::vector<ProjectionCase> cases() {
  return {{"aitoff:aspect=stretch", {kTinyFrame}}, {"aitoff", {{512, 256}, kPhotoFrame, kHugeFrame}}, {"aitoff:lon0=45", {{1024, 512}}}, {"aitoff", {{1024, 1024}, {2048, 512}}}};
}

}  // namespace

const ProjectionModule kAitoffModule{catalog, nullptr, make,    size_for,          rescale,
                                     cases,   always,  nullptr, map_window<Aitoff>};

}  // namespace panoproj
