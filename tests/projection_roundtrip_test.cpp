// Round trips for every projection over a spread of parameters, at sample sizes:
//  - pixels: to_pixel(to_ray(p)) == p on dense grids that include borders and centres, within a
//    bound per case; a pixel that comes back elsewhere is accepted only on a declared identity set
//    (seam, pole rows, cube face edges, the 360-degree fisheye rim, the cartographic outline and
//    poles) and only when the ray it comes back to is the same (angle);
//  - rays: random directions d with a pixel come back as the same ray (angle).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "panoproj/projection.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

struct Case {
  const char* spec;
  Size size;
  double pixel_bound;  // px
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.spec << " at " << c.size.width << "x" << c.size.height; }

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
    const double f = static_cast<double>(c->face_size());
    return std::fmod(x, f) == 0 || std::fmod(y, f) == 0;
  }
  if (const auto* f = std::get_if<Fisheye>(&p)) {
    return f->psi_max() >= kPi * (1 - 1e-12) && std::atan2(std::hypot(d.x(), d.y()), d.z()) > kPi - 1e-6;
  }
  if (const auto* k = std::get_if<Lens>(&p)) {
    return k->theta_max() >= kPi * (1 - 1e-12) && std::atan2(std::hypot(d.x(), d.y()), d.z()) > kPi - 1e-6;
  }
  // Cartographic: the outline meridian (180 degrees from lon0, drawn on both sides) and the
  // poles (a pole is one point; Aitoff and Hammer draw it as one, Bonne as a line or a point).
  const double lon_rel = wrap_pi(longitude(d) - lon0);
  return std::fabs(latitude(d)) > kHalfPi - 1e-6 || std::fabs(std::fabs(lon_rel) - kPi) < 1e-6;
}

class RoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(RoundTrip, PixelsAndRays) {
  const Case& c = GetParam();
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
  EXPECT_LT(identities, tested / 50 + 8) << c.spec << ": too many identity points";

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
  // Angle bound: the pixel bound at the projection's centre density.
  EXPECT_LT(max_angle, 1e-9) << c.spec;
  std::printf("[roundtrip] %-48s %6lldx%-6lld max pixel error %.2e px, max ray error %.2e rad "
              "(%lld grid points, %lld identities, %d rays)\n",
              c.spec, static_cast<long long>(c.size.width), static_cast<long long>(c.size.height),
              max_err, max_angle, static_cast<long long>(tested),
              static_cast<long long>(identities), with_pixel);
}

// Bounds: 1e-3 px is what the issue asks; double geometry does far better, and each case states
// the bound it holds (cases near singular parameters get a looser one).
const Case kCases[] = {
    {"pinhole:hfov=90", {1920, 1080}, 1e-6},
    {"pinhole:hfov=1", {1920, 1080}, 1e-6},
    {"pinhole:hfov=150,vfov=100", {1920, 1080}, 1e-6},
    {"pinhole:hfov=179", {1920, 1080}, 1e-6},
    {"pinhole:focal=1000,cx=900.25,cy=500", {1920, 1080}, 1e-6},
    {"brown-conrady", {1920, 1080}, 1e-6},
    {"brown-conrady:fx=1000,fy=1002,cx=959.5,cy=539.5,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0.01", {1920, 1080}, 1e-6},
    {"brown-conrady:fx=800,k1=0.15,k2=0.02,p1=-0.004,p2=0.003", {1920, 1080}, 1e-6},
    {"brown-conrady:fov=100,fx=600,k1=-0.3,k2=0.1", {1920, 1080}, 1e-6},
    {"fisheye:fov=180", {2048, 2048}, 1e-6},
    {"fisheye:fov=0.001", {2048, 2048}, 1e-6},
    {"fisheye:fov=210", {512, 512}, 1e-6},
    {"fisheye:fov=360", {2048, 2048}, 1e-6},
    {"fisheye:fov=359.9", {2048, 2048}, 1e-6},
    {"fisheye:fov=180,model=equisolid", {2048, 2048}, 1e-6},
    {"fisheye:fov=360,model=equisolid", {2048, 2048}, 1e-6},
    {"fisheye:fov=0.001,model=equisolid", {2048, 2048}, 1e-6},
    {"fisheye:fov=180,model=orthographic", {2048, 2048}, 1e-6},
    {"fisheye:fov=60,model=orthographic", {2048, 2048}, 1e-6},
    {"fisheye:fov=180,model=stereographic", {2048, 2048}, 1e-6},
    {"fisheye:fov=359.9,model=stereographic", {2048, 2048}, 1e-6},
    {"fisheye:fov=180,clip=none", {3000, 2000}, 1e-6},
    {"fisheye:fov=120,model=equisolid,clip=none", {3000, 2000}, 1e-6},
    {"fisheye:fov=200,aspect=stretch", {4096, 2048}, 1e-6},
    {"fisheye:fov=190,radius=900,cx=1000,cy=1020.5", {2048, 2048}, 1e-6},
    {"kannala-brandt", {2048, 2048}, 1e-6},
    {"kannala-brandt:fov=0.01,k1=0.3", {2048, 2048}, 1e-6},
    {"kannala-brandt:fov=220,k1=0.02,k2=-0.005,k3=0.001,k4=-0.0001", {2048, 2048}, 1e-6},
    {"kannala-brandt:fov=360,k1=-0.01,k2=0.0005", {2048, 2048}, 1e-6},
    {"kannala-brandt:fov=195,fx=620.5,fy=621.3,cx=959.2,cy=541.7,k1=0.0361,k2=-0.0112,k3=0.0028,k4=-0.0004",
     {1920, 1080}, 1e-6},
    {"double-sphere:xi=-0.18,alpha=0.59", {1024, 1024}, 1e-6},
    {"double-sphere:xi=-0.18,alpha=0.59,fov=190,fx=313.2,fy=313.1,cx=638.9,cy=514.6", {1280, 1024}, 1e-6},
    {"double-sphere:xi=0.3,alpha=0.4", {1024, 1024}, 1e-6},
    {"unified", {1024, 1024}, 1e-6},
    {"unified:xi=0.8", {1024, 1024}, 1e-6},
    {"unified:xi=2.5", {1024, 1024}, 1e-6},
    {"extended-unified:alpha=0.63,beta=1.04", {1024, 1024}, 1e-6},
    {"extended-unified:alpha=0.3,beta=2,fov=200", {1024, 1024}, 1e-6},
    {"ptlens:hfov=70,a=0.01,b=-0.05,c=0.02", {1920, 1080}, 1e-6},
    {"ptlens:hfov=100,b=-0.1", {1920, 1280}, 1e-6},
    {"equirect", {4096, 2048}, 1e-6},
    {"equirect", {40000, 20000}, 1e-5},
    {"equirect:hfov=120,vfov=60,lon0=170,lat0=-20", {2048, 1024}, 1e-6},
    {"equirect:vfov=101.25,lat0=-39.375", {2048, 512}, 1e-6},
    {"cylindrical", {4096, 1400}, 1e-6},
    {"cylindrical:hfov=120,vfov=179", {2048, 4096}, 1e-6},
    {"cylindrical:vfov=60,lat0=20,lon0=-90", {4096, 1024}, 1e-6},
    {"cubemap", {6 * 512, 512}, 1e-6},
    {"cubemap:layout=1x6", {512, 6 * 512}, 1e-6},
    {"cubemap:layout=3x2", {3 * 512, 2 * 512}, 1e-6},
    {"cubemap:layout=cross", {4 * 512, 3 * 512}, 1e-6},
    {"aitoff", {4096, 2048}, 1e-6},
    {"aitoff:lon0=45", {1024, 512}, 1e-6},
    {"hammer", {4096, 2048}, 1e-6},
    {"eckert-greifendorff", {4096, 1892}, 1e-6},
    {"hammer:w=0.9", {2048, 1024}, 1e-6},
    {"bonne", {2784, 2643}, 1e-6},
    {"bonne:phi1=0", {4096, 2048}, 1e-6},
    {"bonne:phi1=1e-9", {4096, 2048}, 1e-6},
    {"bonne:phi1=5.72", {4096, 2048}, 1e-6},
    {"bonne:phi1=5.73", {4096, 2048}, 1e-6},
    {"bonne:phi1=90", {2048, 2048}, 1e-6},
    {"bonne:phi1=-30,lon0=10", {2048, 2048}, 1e-6},
};

INSTANTIATE_TEST_SUITE_P(AllProjections, RoundTrip, ::testing::ValuesIn(kCases), [](const auto& info) {
  return test::case_name(info.index, std::string(info.param.spec) + " " + std::to_string(info.param.size.width) + "x" +
                                         std::to_string(info.param.size.height));
});

}  // namespace
}  // namespace panoproj
