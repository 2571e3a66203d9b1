// Fixed values in the quick loop, against which a law wrong the same way in both directions
// fails (round trips cannot see it): the world maps' pixels from PROJ, taken once
// (scripts/fixed_truth.py, fixed_truth_maps.inc), and per form a few pixel <-> ray values derived
// by hand from the published laws and panoproj's frame conventions (pixel centres at i + 0.5; a
// calibration's cx, cy at OpenCV's integer centres; x right, y down, z forward; longitude
// atan2(x, z), latitude up).
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/spec.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

struct MapTruth {
  const char* spec;
  double lon, lat, x, y;
};
const MapTruth kMaps[] = {
#include "fixed_truth_maps.inc"
};

// A pixel <-> ray fact: the ray (any length) and the pixel it maps to, both ways.
struct Fact {
  const char* spec;
  Size size;
  Ray ray;
  double x, y;
  const char* why;
};

Ray lonlat(double lon_deg, double lat_deg) {
  return ray_from_lonlat(deg2rad(lon_deg), deg2rad(lat_deg));
}
// A camera ray theta off the axis (z), at azimuth phi from x towards y (down).
Ray camera(double theta_deg, double phi_deg) {
  const double t = deg2rad(theta_deg), p = deg2rad(phi_deg);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

std::vector<Fact> facts() {
  std::vector<Fact> f;
  const double d = kPi / 180;
  // Equirect: x linear in longitude over hfov, y linear in latitude over vfov, centred on
  // lon0/lat0.
  f.push_back({"equirect",
               {3600, 1800},
               lonlat(90, 45),
               2700,
               450,
               "x = W/2 + lon W/360, y = H/2 - lat H/180"});
  f.push_back({"equirect",
               {3600, 1800},
               lonlat(-179, -89),
               10,
               1790,
               "the frame's corner pixels' centres"});
  f.push_back({"equirect:hfov=120,vfov=60,lon0=170,lat0=-20",
               {2048, 1024},
               lonlat(-160, -5),
               1536,
               256,
               "30 deg right of lon0 across the seam: W/4; 15 deg above lat0: H/4"});
  // Cylindrical (full turn): x as the equirect's, y = H/2 - f tan(lat), f = (H/2) / tan(vfov/2).
  f.push_back({"cylindrical:vfov=90",
               {2000, 1000},
               lonlat(-45, std::atan(0.5) / d),
               750,
               250,
               "tan(lat) = 0.5: halfway up with f = H/2"});
  f.push_back({"cylindrical:vfov=90",
               {2000, 1000},
               lonlat(180 - 0.09, 0),
               2000 - 0.5,
               500,
               "the last column's centre"});
  // Cube faces: a = s (tangent) on plain faces, a = tan(pi/4 s) on EAC's; slots f r b l u d in a
  // 6x1 strip, l f r / d b u in EAC's 3x2 (front in the middle of the top row).
  f.push_back({"cubemap",
               {6 * 512, 512},
               lonlat(22.5, 0),
               256 + 256 * std::tan(22.5 * d),
               256,
               "front, tangent plane: s = tan(22.5 deg)"});
  f.push_back(
      {"cubemap", {6 * 512, 512}, Ray(1, 0, 0), 512 + 256, 256, "+x: the right face's centre"});
  f.push_back({"cubemap",
               {6 * 512, 512},
               Ray(0, -1, 0),
               4 * 512 + 256,
               256,
               "-y (up): the up face's centre"});
  f.push_back({"cubemap:layout=eac",
               {3 * 512, 2 * 512},
               lonlat(22.5, 0),
               512 + 256 + 128,
               256,
               "EAC front: 22.5 deg is half way to the edge"});
  f.push_back(
      {"cubemap:layout=eac", {3 * 512, 2 * 512}, lonlat(0, 0), 768, 256, "EAC front's centre"});
  // Fisheye laws, the image circle (radius W/2) at fov/2: r = R g(theta) / g(fov/2).
  const double R = 1024;
  auto circle = [&](const char* spec, double theta, double fov2, double (*g)(double)) {
    f.push_back(
        {spec, {2048, 2048}, camera(theta, 0), 1024 + R * g(theta * d) / g(fov2 * d), 1024, spec});
  };
  circle("fisheye:fov=180,model=equidistant", 40, 90, [](double t) { return t; });
  circle("fisheye:fov=180,model=equisolid", 40, 90, [](double t) { return 2 * std::sin(t / 2); });
  circle("fisheye:fov=180,model=orthographic", 40, 90, [](double t) { return std::sin(t); });
  circle("fisheye:fov=270,model=stereographic", 100, 135,
         [](double t) { return 2 * std::tan(t / 2); });
  circle("fisheye:model=thoby,fov=252.4", 100, 126.2, [](double t) { return std::sin(0.713 * t); });
  // Dual fisheye (side by side, equidistant): lens 0 looks forward in the left half, lens 1 back
  // in the right half, each the front lens turned half a turn about the vertical.
  f.push_back({"dual-fisheye:fov=200", {4096, 2048}, lonlat(0, 0), 1024, 1024, "lens 0's centre"});
  f.push_back(
      {"dual-fisheye:fov=200", {4096, 2048}, lonlat(180, 0), 3072, 1024, "lens 1's centre"});
  f.push_back({"dual-fisheye:fov=200",
               {4096, 2048},
               lonlat(-150, 0),
               3072 + 1024 * 30.0 / 100,
               1024,
               "30 deg to lens 1's right: r = R theta / (fov/2)"});
  // Calibrations with their parameters given: OpenCV's and the published models' pixel of a ray.
  {
    const double fx = 620.5, fy = 621.3, cx = 959.2, cy = 541.7,
                 k[4] = {0.0361, -0.0112, 0.0028, -0.0004};
    const double t = 70 * d, t2 = t * t;
    const double td =
        t * (1 + k[0] * t2 + k[1] * t2 * t2 + k[2] * t2 * t2 * t2 + k[3] * t2 * t2 * t2 * t2);
    f.push_back(
        {"kannala-brandt:fov=195,fx=620.5,fy=621.3,cx=959.2,cy=541.7,k1=0.0361,k2=-0.0112,k3=0."
         "0028,k4=-0.0004",
         {1920, 1080},
         camera(70, 30),
         cx + 0.5 + fx * td * std::cos(30 * d),
         cy + 0.5 + fy * td * std::sin(30 * d),
         "Kannala-Brandt: theta_d = theta (1 + k1 theta^2 + ... + k4 theta^8)"});
  }
  {
    const double xi = -0.18, alpha = 0.59, fx = 313.2, fy = 313.1, cx = 638.9, cy = 514.6;
    const Ray p = camera(80, -60);
    const double d1 = p.norm(), zx = xi * d1 + p.z(),
                 d2 = std::sqrt(p.x() * p.x() + p.y() * p.y() + zx * zx);
    const double den = alpha * d2 + (1 - alpha) * zx;
    f.push_back({"double-sphere:xi=-0.18,alpha=0.59,fov=190,fx=313.2,fy=313.1,cx=638.9,cy=514.6",
                 {1280, 1024},
                 p,
                 cx + 0.5 + fx * p.x() / den,
                 cy + 0.5 + fy * p.y() / den,
                 "Usenko et al. 2018, eq. 40-45"});
  }
  {
    const double fx = 1000, fy = 1002, cx = 959.5, cy = 539.5, k1 = -0.28, k2 = 0.09, k3 = -0.01,
                 p1 = 0.001, p2 = -0.0005;
    const double x = 0.3, y = -0.2, r2 = x * x + y * y,
                 rad = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
    const double xd = x * rad + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                 yd = y * rad + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    f.push_back(
        {"brown-conrady:fx=1000,fy=1002,cx=959.5,cy=539.5,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-"
         "0.01",
         {1920, 1080},
         Ray(x, y, 1),
         cx + 0.5 + fx * xd,
         cy + 0.5 + fy * yd,
         "OpenCV's distortion model"});
  }
  f.push_back({"pinhole:focal=1000,cx=900.25,cy=500",
               {1920, 1080},
               Ray(0.25, -0.125, 1),
               900.75 + 250,
               500.5 - 125,
               "u = cx + 0.5 + f x / z"});
  return f;
}

TEST(FixedTruth, WorldMapsMatchProj) {
  int n = 0;
  for (const MapTruth& t : kMaps) {
    const Projection p = make_projection(parse_spec(t.spec), {1500, 1100});
    double x = 0, y = 0;
    ASSERT_TRUE(to_pixel(p, lonlat(t.lon, t.lat), x, y)) << t.spec;
    EXPECT_NEAR(x, t.x, 1e-6) << t.spec << " at " << t.lon << ", " << t.lat;
    EXPECT_NEAR(y, t.y, 1e-6) << t.spec << " at " << t.lon << ", " << t.lat;
    Ray d;
    ASSERT_TRUE(to_ray(p, t.x, t.y, d)) << t.spec;
    // (1e-8 rad: transverse Mercator to 89.999 degrees spans 22 plane units over 1500 px, so the
    // tables' 1e-7 px of rounding is 1.5e-9 rad there)
    EXPECT_LT((d.normalized() - lonlat(t.lon, t.lat)).norm(), 1e-8) << t.spec;
    ++n;
  }
  EXPECT_GE(n, 90);
}

TEST(FixedTruth, FramesAndLensLawsMatchTheirDefinitions) {
  for (const Fact& f : facts()) {
    const Projection p = make_projection(parse_spec(f.spec), f.size);
    double x = 0, y = 0;
    ASSERT_TRUE(to_pixel(p, f.ray, x, y)) << f.spec << ": " << f.why;
    EXPECT_NEAR(x, f.x, 1e-7) << f.spec << ": " << f.why;
    EXPECT_NEAR(y, f.y, 1e-7) << f.spec << ": " << f.why;
    Ray d;
    ASSERT_TRUE(to_ray(p, f.x, f.y, d)) << f.spec << ": " << f.why;
    EXPECT_LT((d.normalized() - f.ray.normalized()).norm(), 1e-9) << f.spec << ": " << f.why;
  }
}

}  // namespace
}  // namespace panoproj
