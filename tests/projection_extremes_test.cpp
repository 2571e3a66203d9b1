// Continuity across the identities (equirect seam and poles, cube edges and corners, fisheye
// rim) and the extremes the projections must survive (fisheye fov 0.001 and 359.9 degrees,
// pinhole 179, Aitoff's Newton inverse at its outline and poles, Bonne phi1 = 0 and 90,
// cylindrical vfov 179), plus degenerate rays on every projection's case table (module.hpp). No
// NaN or inf may come out of a valid mapping.
#include <gtest/gtest.h>

#include <random>

#include "panoproj/projection.hpp"
#include "projections/module.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

Projection make(const char* spec, Size size) { return make_projection(parse_spec(spec), size); }

Ray ray_at(const Projection& p, double x, double y) {
  Ray d;
  EXPECT_TRUE(to_ray(p, x, y, d)) << x << "," << y;
  return d;
}

TEST(Continuity, EquirectSeamAndPoles) {
  const Projection p = make("equirect", {4096, 2048});
  for (double lat : {-1.5, -0.7, 0.0, 0.3, 1.2}) {
    double x1, y1, x2, y2;
    ASSERT_TRUE(to_pixel(p, ray_from_lonlat(kPi - 1e-9, lat), x1, y1));
    ASSERT_TRUE(to_pixel(p, ray_from_lonlat(-kPi + 1e-9, lat), x2, y2));
    // Across the seam the pixels differ by W modulo W: 2e-9 rad is 1.3e-6 px here.
    EXPECT_NEAR(std::fmod(x2 - x1 + 4096.0, 4096.0), 4096 * 2e-9 / kTwoPi, 1e-9);
    EXPECT_NEAR(y1, y2, 1e-9);
  }
  // Near a pole, every longitude maps next to the pole row.
  for (double lon = -kPi; lon < kPi; lon += 0.1) {
    double x, y;
    ASSERT_TRUE(to_pixel(p, ray_from_lonlat(lon, kHalfPi - 1e-10), x, y));
    EXPECT_LT(y, 1e-6);
    ASSERT_TRUE(to_pixel(p, ray_from_lonlat(lon, -kHalfPi + 1e-10), x, y));
    EXPECT_GT(y, 2048 - 1e-6);
  }
  // The pole rays themselves (x = z = 0) are valid and finite.
  double x, y;
  ASSERT_TRUE(to_pixel(p, Ray(0, -1, 0), x, y));
  EXPECT_EQ(y, 0.0);
  ASSERT_TRUE(to_pixel(p, Ray(0, 1, 0), x, y));
  EXPECT_EQ(y, 2048.0);
}

TEST(Continuity, CubeEdgesAndCorners) {
  for (const char* spec : {"cubemap", "cubemap:layout=cross", "cubemap:layout=3x2"}) {
    const Projection p = make(spec, spec == std::string("cubemap") ? Size{6 * 256, 256}
                                    : spec == std::string("cubemap:layout=cross") ? Size{1024, 768}
                                                                                : Size{768, 512});
    const auto& cube = std::get<Cubemap>(p);
    for (int face = 0; face < 6; ++face) {
      for (double t = -1.0; t <= 1.0; t += 0.125) {
        // Each edge at parameter t, with a ray just inside and just outside the face: the outside
        // one lands on the neighbouring face, and mapping it back to a ray is continuous.
        const double edges[4][2] = {{1, t}, {-1, t}, {t, 1}, {t, -1}};
        for (const auto& e : edges) {
          const Ray in = Cubemap::face_ray(face, e[0] * (1 - 1e-9), e[1] * (1 - 1e-9));
          const Ray out = Cubemap::face_ray(face, e[0] * (1 + 1e-9), e[1] * (1 + 1e-9));
          for (const Ray& d : {in, out}) {
            double x, y;
            ASSERT_TRUE(cube.to_pixel(d, x, y));
            const Ray back = ray_at(p, x, y);
            EXPECT_LT(test::angle(back, d), 1e-12) << spec << " face " << face;
          }
          EXPECT_LT(test::angle(in, out), 1e-8);
        }
      }
    }
    // Corners: the three faces around each cube corner agree on the corner ray.
    for (double sx : {-1.0, 1.0})
      for (double sy : {-1.0, 1.0})
        for (double sz : {-1.0, 1.0}) {
          const Ray corner = Ray(sx, sy, sz).normalized();
          for (int k = 0; k < 3; ++k) {
            Ray d = corner;
            d[k] *= 1 + 1e-9;  // nudged so each of the three faces wins once
            double x, y;
            ASSERT_TRUE(cube.to_pixel(d.normalized(), x, y));
            EXPECT_LT(test::angle(ray_at(p, x, y), corner), 1e-8) << spec;
          }
        }
  }
}

TEST(Continuity, FisheyeRim) {
  for (const char* spec : {"fisheye:fov=180,clip=none", "fisheye:fov=200,model=equisolid,clip=none",
                           "fisheye:fov=100,model=stereographic,clip=none"}) {
    const Projection p = make(spec, {4096, 4096});
    const Projection clipped = make(std::string(spec).substr(0, std::string(spec).find(",clip")).c_str(),
                                    {4096, 4096});
    for (double th = 0; th < kTwoPi; th += 0.3) {
      const double rr = 2048;  // the image circle of the 4096 frame
      const Ray a = ray_at(p, 2048 + (rr - 1e-7) * std::cos(th), 2048 + (rr - 1e-7) * std::sin(th));
      const Ray b = ray_at(p, 2048 + (rr + 1e-7) * std::cos(th), 2048 + (rr + 1e-7) * std::sin(th));
      EXPECT_LT(test::angle(a, b), 1e-9) << spec;
      Ray d;
      EXPECT_TRUE(to_ray(clipped, 2048 + (rr - 1e-7) * std::cos(th), 2048 + (rr - 1e-7) * std::sin(th), d));
      EXPECT_FALSE(to_ray(clipped, 2048 + (rr + 1e-3) * std::cos(th), 2048 + (rr + 1e-3) * std::sin(th), d));
    }
  }
  // The 360-degree rim is one point, the back pole. Equisolid's g = 2 sin(psi/2) is flat at
  // psi = pi, so one ulp of r there moves psi by sqrt(eps) ~ 1.5e-8 rad (3e-7 px at the rim):
  // conditioning of the lens law, not of the code.
  for (auto [spec, bound] : {std::pair{"fisheye:fov=360", 1e-12}, {"fisheye:fov=360,model=equisolid", 5e-8}}) {
    const Projection p = make(spec, {2048, 2048});
    for (double th = 0; th < kTwoPi; th += 0.2) {
      const Ray d = ray_at(p, 1024 + 1024 * std::cos(th), 1024 + 1024 * std::sin(th));
      EXPECT_LT(test::angle(d, Ray(0, 0, -1)), bound) << spec;
    }
    double x, y;
    ASSERT_TRUE(to_pixel(p, Ray(0, 0, -1), x, y));
    EXPECT_NEAR(std::hypot(x - 1024, y - 1024), 1024, 1e-9);
  }
}

TEST(Extremes, TinyAndHugeFisheyes) {
  // 0.001 degrees over 2048 px: one pixel from the centre is psi_max / 1024 off axis.
  for (const char* spec : {"fisheye:fov=0.001", "fisheye:fov=0.001,model=equisolid",
                           "fisheye:fov=0.001,model=stereographic", "fisheye:fov=0.001,model=orthographic"}) {
    const Projection p = make(spec, {2048, 2048});
    const Ray d = ray_at(p, 1025, 1024);
    const double expected = deg2rad(0.0005) / 1024;
    EXPECT_NEAR(test::angle(d, Ray(0, 0, 1)), expected, expected * 1e-6) << spec;
    const Ray rim = ray_at(p, 2048, 1024);
    EXPECT_NEAR(test::angle(rim, Ray(0, 0, 1)), deg2rad(0.0005), 1e-15) << spec;
  }
  for (const char* spec : {"fisheye:fov=359.9", "fisheye:fov=359.9,model=equisolid",
                           "fisheye:fov=359.9,model=stereographic"}) {
    const Projection p = make(spec, {2048, 2048});
    const Ray rim = ray_at(p, 2048, 1024);
    EXPECT_NEAR(test::angle(rim, Ray(0, 0, 1)), deg2rad(179.95), 1e-12) << spec;
    // Rays behind the rim (the last 0.05 degrees) have no pixel with the circle clipped.
    double x, y;
    EXPECT_FALSE(to_pixel(p, ray_from_lonlat(0, 0) * -1.0, x, y)) << spec;
  }
}

TEST(Extremes, Pinhole179AndCylindrical179) {
  const Projection pin = make("pinhole:hfov=179", {1920, 1080});
  EXPECT_NEAR(test::angle(ray_at(pin, 1920, 540), Ray(0, 0, 1)), deg2rad(89.5), 1e-12);
  EXPECT_NEAR(test::angle(ray_at(pin, 0, 540), Ray(0, 0, 1)), deg2rad(89.5), 1e-12);
  double x, y;
  EXPECT_FALSE(to_pixel(pin, Ray(1, 0, 0), x, y));   // 90 degrees: at infinity
  EXPECT_FALSE(to_pixel(pin, Ray(0, 0, -1), x, y));  // behind
  const Projection cyl = make("cylindrical:vfov=179", {4096, 4096});
  EXPECT_NEAR(latitude(ray_at(cyl, 100, 0)), deg2rad(89.5), 1e-12);
  EXPECT_NEAR(latitude(ray_at(cyl, 100, 4096)), -deg2rad(89.5), 1e-12);
  EXPECT_FALSE(to_pixel(cyl, Ray(0, -1, 0), x, y));  // the pole is at infinity
  EXPECT_FALSE(to_pixel(cyl, ray_from_lonlat(0.3, deg2rad(89.6)), x, y));
}

TEST(Extremes, AitoffNewtonAtOutlineAndPoles) {
  const Aitoff a({4096, 2048}, 0.0);
  int worst_iterations = 0;
  double worst_residual = 0;
  for (double s : {1 - 1e-3, 1 - 1e-6, 1 - 1e-9, 1 - 1e-12, 1.0})
    for (double th = 0; th < kTwoPi; th += kTwoPi / 360) {
      const double X = s * kPi * std::cos(th), Y = s * kHalfPi * std::sin(th);
      double lam, phi;
      const int it = a.newton_inverse(X, Y, lam, phi);
      ASSERT_GE(it, 0) << s << " " << th;
      ASSERT_TRUE(std::isfinite(lam) && std::isfinite(phi));
      double fx, fy;
      Aitoff::forward(lam, phi, fx, fy);
      worst_iterations = std::max(worst_iterations, it);
      worst_residual = std::max(worst_residual, std::hypot(fx - X, fy - Y));
    }
  std::printf("[aitoff] outline: at most %d Newton iterations, residual %.2e (plane units)\n",
              worst_iterations, worst_residual);
  EXPECT_LE(worst_iterations, 12);
  EXPECT_LT(worst_residual, 1e-9);  // 1e-9 plane units = 1.3e-6 px at 4096 wide
  // Poles: the top and bottom of the ellipse.
  const Projection p = make("aitoff", {4096, 2048});
  EXPECT_LT(test::angle(ray_at(p, 2048, 0), Ray(0, -1, 0)), 1e-9);
  EXPECT_LT(test::angle(ray_at(p, 2048, 2048), Ray(0, 1, 0)), 1e-9);
  // Outside the outline there is no ray and no Newton run.
  Ray d;
  EXPECT_FALSE(to_ray(p, 1, 1, d));
  double lam, phi;
  EXPECT_EQ(a.newton_inverse(kPi * 1.001, 0, lam, phi), -1);
}

TEST(Extremes, BonneLimits) {
  // phi1 -> 0 is the sinusoidal projection: X = lambda cos phi, Y = phi.
  for (double phi1 : {0.0, 1e-12, 1e-6}) {
    const Bonne b({1000, 1000}, phi1, 0.0);
    for (double lam : {-3.0, -1.0, 0.5, 3.1})
      for (double phi : {-1.5, -0.2, 0.0, 0.9, 1.5}) {
        double X, Y;
        b.forward(lam, phi, X, Y);
        ASSERT_TRUE(std::isfinite(X) && std::isfinite(Y));
        EXPECT_NEAR(X, lam * std::cos(phi), 1e-5 + 1e-6 * std::fabs(phi1) * 1e6);
        EXPECT_NEAR(Y, phi, 1e-5 + 1e-6 * std::fabs(phi1) * 1e6);
      }
  }
  // The two forms of the equations meet at kSmallPhi1 without a jump.
  const double e = 1e-12;
  const Bonne lo({1000, 1000}, Bonne::kSmallPhi1 - e, 0.0), hi({1000, 1000}, Bonne::kSmallPhi1 + e, 0.0);
  for (double lam : {-3.0, 0.7, 3.1})
    for (double phi : {-1.5, 0.1, 1.5}) {
      double x1, y1, x2, y2, l1, p1;
      lo.forward(lam, phi, x1, y1);
      hi.forward(lam, phi, x2, y2);
      EXPECT_NEAR(x1, x2, 1e-9);
      EXPECT_NEAR(y1, y2, 1e-9);
      ASSERT_TRUE(lo.inverse(x1, y1, l1, p1));
      EXPECT_NEAR(l1, lam, 1e-9);
      EXPECT_NEAR(p1, phi, 1e-9);
    }
  // phi1 = 90 (Werner): the north pole is the apex, a single point.
  const Projection w = make("bonne:phi1=90", {2048, 2048});
  double x0, y0;
  ASSERT_TRUE(to_pixel(w, ray_from_lonlat(-2.0, kHalfPi), x0, y0));
  for (double lon : {-1.0, 0.0, 1.5, 3.0}) {
    double x, y;
    ASSERT_TRUE(to_pixel(w, ray_from_lonlat(lon, kHalfPi), x, y));
    EXPECT_NEAR(x, x0, 1e-9);
    EXPECT_NEAR(y, y0, 1e-9);
  }
}

// Every row of every projection's case table at each of its sizes: degenerate rays map to a
// finite pixel or none, and every position of the closed frame (half-pixel steps, or a 257 x 257
// lattice on large frames) to a finite ray or none.
TEST(Extremes, DegenerateRaysNeverGiveNonFinitePixels) {
  const double inf = HUGE_VAL, nan = std::nan("");
  const Ray bad[] = {Ray(0, 0, 0), Ray(nan, 0, 1), Ray(inf, 0, 1), Ray(0, -inf, 0), Ray(1e-300, 0, 0)};
  int64_t frames = 0;
  for (const ProjectionCase& row : projection_cases())
    for (Size sz : row.sizes) {
      const Projection p = make_projection(parse_spec(row.spec), sz);
      ++frames;
      for (const Ray& d : bad) {
        double x = 0, y = 0;
        if (to_pixel(p, d, x, y)) {
          EXPECT_TRUE(std::isfinite(x) && std::isfinite(y)) << row.spec;
        }
      }
      const auto W = static_cast<double>(sz.width), H = static_cast<double>(sz.height);
      const double sx = sz.width <= 512 ? 0.5 : W / 256, sy = sz.height <= 512 ? 0.5 : H / 256;
      for (double y = 0; y <= H; y += sy)
        for (double x = 0; x <= W; x += sx) {
          Ray d;
          if (to_ray(p, x, y, d)) {
            ASSERT_TRUE(d.allFinite()) << row.spec << " " << x << "," << y;
          }
        }
    }
  EXPECT_GE(frames, 100);
}

// Mollweide's forward Newton: 2 theta + sin 2 theta = pi sin phi solved for every latitude from the
// pole to the equator (and a pole in floating point, cos phi = 6e-17) within 6 iterations, with the
// equation's residual in the cancellation-free form h(2 delta) = pi (1 - sin phi) at rounding level.
TEST(Extremes, MollweideNewtonConvergesEverywhere) {
  int worst = 0;
  double worst_residual = 0;
  for (int i = 0; i <= 200000; ++i) {
    const double phi = kHalfPi * i / 200000.0;
    int it = 0;
    const double c = std::cos(phi), s = std::sin(phi);
    const double delta = Mollweide::delta_of(c, s, &it);
    worst = std::max(worst, it);
    const double rhs = kPi * c * c / (1.0 + s);
    worst_residual = std::max(worst_residual, std::fabs(Mollweide::h(2 * delta) - rhs) / std::max(rhs, 1e-300));
    ASSERT_GE(delta, 0.0);
    ASSERT_LE(delta, kHalfPi);
  }
  EXPECT_LE(worst, 6);
  EXPECT_LT(worst_residual, 1e-14);  // relative: exact near the poles, where rhs -> 0
  int it = 0;
  EXPECT_EQ(Mollweide::delta_of(0.0, 1.0, &it), 0.0);  // the pole itself
  EXPECT_NEAR(Mollweide::delta_of(1.0, 0.0, &it), kHalfPi, 1e-15);  // the equator
}

}  // namespace
}  // namespace panoproj
