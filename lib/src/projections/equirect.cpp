// The equirectangular module (module.hpp): a full or partial longitude-latitude panorama.
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"equirect", "equirectangular (spherical) panorama, full or partial",
           {number("hfov", "360", 0, 360, true, false, "longitude span (deg)"),
            number("vfov", "180", 0, 180, true, false, "latitude span (deg)"), lon0(), lat0()}}};
}

Projection make(const ProjectionSpec& s, Size size) {
  return Equirect(size, rad(s, "hfov"), rad(s, "vfov"), rad(s, "lon0"), rad(s, "lat0"));
}

Size size_for(const ProjectionSpec& s, double density) {
  return framed_size(s, density * rad(s, "hfov"), density * rad(s, "vfov"));
}

Projection rescale(const Projection& p, Size size, double, double) {
  const auto& q = std::get<Equirect>(p);
  return Equirect(size, q.axis().hfov, q.vfov(), q.axis().lon0, q.lat_top() - 0.5 * q.vfov());
}

bool whole_sphere(const Projection& p) {
  const auto& e = std::get<Equirect>(p);
  return e.reaches_north_pole() && e.reaches_south_pole();
}

// Its rows hold a whole turn each; a full one wraps, and continues over a pole its frame reaches.
SamplingFacts sampling(const Projection& p) {
  const auto& e = std::get<Equirect>(p);
  SamplingFacts f = framed_facts(p);
  f.wraps_x = e.full_longitude();
  f.north_pole = e.reaches_north_pole();
  f.south_pole = e.reaches_south_pole();
  f.rows_hold_turn = true;
  return f;
}

// 1x1 to 40000 px, fields of 0.01 degree, a field touching the pole, partial fields across the
// seam and below the equator.
std::vector<ProjectionCase> cases() {
  return {{"equirect", {kTinyFrame, {2, 1}, {512, 256}, kPhotoFrame, kHugeFrame}},
          {"equirect:hfov=10,vfov=10", {{512, 256}}},
          {"equirect:hfov=0.01,vfov=0.01", {kTinyFrame, kPhotoFrame}},
          {"equirect:hfov=120,vfov=60,lat0=59.99", {kPhotoFrame}},
          {"equirect:hfov=120,vfov=60,lon0=170,lat0=-20", {{2048, 1024}}},
          {"equirect:vfov=101.25,lat0=-39.375", {{2048, 512}}}};
}

// Longitudes and latitudes are linear in x and y: the window's span and centre.
Projection window(const Projection& p, const PixelRect& r) {
  const auto& q = std::get<Equirect>(p);
  const Size s = q.size();
  const double fx = static_cast<double>(r.width()) / static_cast<double>(s.width);
  const double fy = static_cast<double>(r.height()) / static_cast<double>(s.height);
  const double top =
      q.lat_top() - static_cast<double>(r.y0) / static_cast<double>(s.height) * q.vfov();
  return Equirect(r.size(), q.axis().hfov * fx, q.vfov() * fy,
                  q.axis().longitude_at(0.5 * static_cast<double>(r.x0 + r.x1)),
                  top - 0.5 * q.vfov() * fy);
}

}  // namespace

const ProjectionModule kEquirectModule{
    catalog,      [](const ProjectionSpec& s) { check_latitude_span(s, false); },
    make,         size_for,
    rescale,      cases,
    whole_sphere, sampling,
    window};

}  // namespace panoproj
