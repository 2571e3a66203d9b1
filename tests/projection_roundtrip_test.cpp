// Round trips for every row of every projection's case table (projections/module.hpp) at each
// of its sizes from 32 px up:
//  - pixels: to_pixel(to_ray(p)) == p on dense grids that include borders and centres, within the
//    row's bound; a pixel that comes back elsewhere is accepted only on a declared identity set
//    (seam, pole rows, cube face edges, the 360-degree fisheye rim, the cartographic outline and
//    poles, a dual fisheye's overlap) and only when the ray it comes back to is the same (angle);
//  - rays: random directions d with a pixel come back as the same ray (angle).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "panoproj/projection.hpp"
#include "projections/module.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

struct Case {
  std::string spec;
  Size size;
  double pixel_bound;  // px
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.spec << " at " << c.size.width << "x" << c.size.height; }

// The tables' rows at each size with at least 32 px each way (smaller frames have too few grid
// points for the identity count; the stability report covers them).
std::vector<Case> cases() {
  std::vector<Case> v;
  for (const ProjectionCase& row : projection_cases())
    for (Size s : row.sizes)
      if (std::min(s.width, s.height) >= 32) v.push_back({row.spec, s, row.bound_px});
  return v;
}

// Where one ray has several pixels (or none is unique), for the case's projection.
bool on_identity_set(const Projection& p, double lon0, double x, double y, const Ray& d) {
  const Size s = size_of(p);
  const double W = static_cast<double>(s.width), H = static_cast<double>(s.height);
  if (const auto* e = std::get_if<Equirect>(&p)) {
    return (e->full_longitude() && (x == 0 || x == W)) ||
           (e->reaches_north_pole() && y == 0) || (e->reaches_south_pole() && y == H);
  }
  if (const auto* c = std::get_if<Cylindrical>(&p)) return c->full_longitude() && (x == 0 || x == W);
  if (const auto* c = std::get_if<Cubemap>(&p)) {
    // A cell's edge; or (padding, FFmpeg's EAC border) a ray its cell shows past the face's 90
    // degrees, which comes back through the face that holds it.
    const auto& ax = c->x_axis();
    const auto& ay = c->y_axis();
    for (int k = 0; k <= ax.n; ++k)
      if (x == static_cast<double>(ax.edge[k])) return true;
    for (int k = 0; k <= ay.n; ++k)
      if (y == static_cast<double>(ay.edge[k])) return true;
    const int f = c->face_at(x, y);
    return f >= 0 && cube_face_of(d) != f;
  }
  if (const auto* f = std::get_if<Fisheye>(&p)) {
    return f->psi_max() >= kPi * (1 - 1e-12) && std::atan2(std::hypot(d.x(), d.y()), d.z()) > kPi - 1e-6;
  }
  if (const auto* m = std::get_if<GoProMax>(&p)) {
    // The band: a ray both lenses see comes back through the one it lies deeper inside; a cell's
    // edge (the faces').
    const auto& ax = m->lens(0).x_axis();
    for (int k = 0; k <= ax.n; ++k)
      if (x == static_cast<double>(ax.edge[k])) return true;
    if (y == 0 || y == 0.5 * H || y == H) return true;
    return m->margin(1 - m->lens_at(x, y), d) >= 0 ||
           cube_face_of(d) != m->lens(m->lens_at(x, y)).face_at(x, y);
  }
  if (const auto* dual = std::get_if<DualFisheye>(&p)) {
    // The overlap: a ray seen by both lenses comes back through the one it lies deeper inside.
    return dual->margin(1 - dual->lens_at(x, y), d) >= 0;
  }
  if (const auto* k = std::get_if<CalibratedLens>(&p)) {
    return k->theta_max() >= kPi * (1 - 1e-12) && std::atan2(std::hypot(d.x(), d.y()), d.z()) > kPi - 1e-6;
  }
  // Transverse Mercator: Y = +-pi is one line, the equator's back half.
  if (std::holds_alternative<TransverseMercator>(p)) {
    return std::fabs(latitude(d)) < 1e-6 && std::cos(wrap_pi(longitude(d) - lon0)) < 0;
  }
  // Cartographic: the outline meridian (180 degrees from lon0, drawn on both sides) and the
  // poles (a pole is one point; Aitoff and Hammer draw it as one, Bonne as a line or a point).
  const double lon_rel = wrap_pi(longitude(d) - lon0);
  return std::fabs(latitude(d)) > kHalfPi - 1e-6 || std::fabs(std::fabs(lon_rel) - kPi) < 1e-6;
}

class RoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(RoundTrip, PixelsAndRays) {
  const Case& c = GetParam();
  const char* name = c.spec.c_str();
  const ProjectionSpec spec = parse_spec(c.spec);
  const Projection p = make_projection(spec, c.size);
  // (lon0: the world maps' central meridian; equirect and cylindrical decide before using it.)
  const bool has_lon0 = std::any_of(spec.def().params.begin(), spec.def().params.end(),
                                    [](const ParamDef& k) { return std::string_view(k.key) == "lon0"; });
  const double lon0 = has_lon0 ? deg2rad(*spec.number("lon0")) : 0.0;
  const double W = static_cast<double>(c.size.width), H = static_cast<double>(c.size.height);
  // Grid: every step-th pixel edge and centre, plus the exact borders and the frame centre.
  std::vector<double> xs, ys;
  auto axis = [](double extent, std::vector<double>& v) {
    const double step = std::max(1.0, std::floor(extent / 181.0));
    for (double t = 0; t < extent; t += step) v.insert(v.end(), {t, t + 0.5});
    v.insert(v.end(), {extent - 0.5, extent, 0.5 * extent, 1e-7, extent - 1e-7});
  };
  axis(W, xs);
  axis(H, ys);
  double max_err = 0;
  int64_t tested = 0, identities = 0;
  // A dual fisheye's overlap, a padded cube's borders: no small set.
  const auto* cube = std::get_if<Cubemap>(&p);
  const bool dual = std::holds_alternative<DualFisheye>(p) || std::holds_alternative<GoProMax>(p) ||
                    (cube && (cube->format().pad > 0 || cube->format().ffmpeg_border));
  for (double y : ys)
    for (double x : xs) {
      if (x > W || y > H) continue;
      Ray d;
      if (!to_ray(p, x, y, d)) continue;
      ASSERT_TRUE(d.allFinite()) << c.spec << " at " << x << "," << y;
      ASSERT_NEAR(d.norm(), 1.0, 1e-12);
      double qx, qy;
      ASSERT_TRUE(to_pixel(p, d, qx, qy)) << c.spec << ": ray of " << x << "," << y << " has no pixel";
      ++tested;
      const double err = std::hypot(qx - x, qy - y);
      if (err <= c.pixel_bound) {
        max_err = std::max(max_err, err);
        continue;
      }
      ASSERT_TRUE(on_identity_set(p, lon0, x, y, d))
          << c.spec << ": " << x << "," << y << " -> " << qx << "," << qy << " (error " << err << " px)";
      Ray d2;
      ASSERT_TRUE(to_ray(p, qx, qy, d2));
      ASSERT_LT(test::angle(d, d2), 1e-9) << c.spec << ": identity at " << x << "," << y;
      ++identities;
    }
  EXPECT_GT(tested, 1000) << c.spec;
  if (!dual) {
    EXPECT_LT(identities, tested / 50 + 8) << c.spec << ": too many identity points";
  }

  // Ray round trips from random directions.
  std::mt19937 rng(11);
  std::normal_distribution<double> n01;
  double max_angle = 0;
  int with_pixel = 0;
  for (int i = 0; i < 20000; ++i) {
    Ray d(n01(rng), n01(rng), n01(rng));
    d.normalize();
    double qx, qy;
    if (!to_pixel(p, d, qx, qy)) continue;
    ++with_pixel;
    Ray d2;
    ASSERT_TRUE(to_ray(p, qx, qy, d2)) << c.spec;
    max_angle = std::max(max_angle, test::angle(d, d2));
  }
  // FFmpeg's EAC frame leaves slivers of rays in no cell (where a face's 90 degrees reach past
  // its cell, the neighbour's linear border covers less): they land on the nearest cell edge,
  // within 0.05 px.
  const double ray_bound = cube && cube->format().ffmpeg_border ? 0.05 / cube->center_density() : 1e-9;
  EXPECT_LT(max_angle, ray_bound) << c.spec;
  std::printf("[roundtrip] %-48s %6lldx%-6lld max pixel error %.2e px, max ray error %.2e rad "
              "(%lld grid points, %lld identities, %d rays)\n",
              name, static_cast<long long>(c.size.width), static_cast<long long>(c.size.height),
              max_err, max_angle, static_cast<long long>(tested),
              static_cast<long long>(identities), with_pixel);
}

INSTANTIATE_TEST_SUITE_P(AllProjections, RoundTrip, ::testing::ValuesIn(cases()), [](const auto& info) {
  return test::case_name(info.index, info.param.spec + " " + std::to_string(info.param.size.width) + "x" +
                                         std::to_string(info.param.size.height));
});

}  // namespace
}  // namespace panoproj
