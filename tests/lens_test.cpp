// Calibrated lenses (projections/calibrated_lens.hpp, brown_conrady.hpp): the Double Sphere, unified and extended unified laws
// against their papers' projection and unprojection formulas written on 3-D points; the
// Kannala-Brandt Newton inverse up to the image circle, its agreement with the equidistant
// fisheye when k = 0, and the errors for fields a law cannot hold; Brown-Conrady's folds and its
// covers() test. (Kannala-Brandt and Brown-Conrady against OpenCV: python/tests/test_lens_models.py.)
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>

#include "panoproj/error.hpp"
#include "panoproj/projection.hpp"
#include "test_support.hpp"
#include <cstdio>

namespace panoproj {
namespace {

Projection make(const std::string& spec, Size size) { return make_projection(parse_spec(spec), size); }

// The message of the error making the spec raises ("" if none).
std::string error_of(const std::string& spec, Size size) {
  try {
    make(spec, size);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// A model as its paper writes it: pixel of a 3-D point, unit ray of a pixel (normalized plane
// coordinates mx, my; the intrinsics are applied by the test).
struct PaperModel {
  const char* spec;
  std::function<void(const Ray&, double&, double&)> project;
  std::function<Ray(double, double)> unproject;
};

std::vector<PaperModel> paper_models() {
  // Usenko, Demmel and Cremers 2018, eqs. 40-47.
  const double xi = -0.18, a = 0.59;
  PaperModel ds{"double-sphere:xi=-0.18,alpha=0.59",
                [=](const Ray& X, double& mx, double& my) {
                  const double d1 = X.norm(), t = xi * d1 + X.z();
                  const double d2 = std::sqrt(X.x() * X.x() + X.y() * X.y() + t * t);
                  const double den = a * d2 + (1 - a) * t;
                  mx = X.x() / den, my = X.y() / den;
                },
                [=](double mx, double my) {
                  const double r2 = mx * mx + my * my;
                  const double mz = (1 - a * a * r2) / (a * std::sqrt(1 - (2 * a - 1) * r2) + 1 - a);
                  const double k = (mz * xi + std::sqrt(mz * mz + (1 - xi * xi) * r2)) / (mz * mz + r2);
                  return Ray(k * mx, k * my, k * mz - xi).normalized();
                }};
  // Khomutenko, Garcia and Martinet 2016 (as Usenko et al. 2018, eqs. 30-39).
  const double ea = 0.63, b = 1.04;
  PaperModel eucm{"extended-unified:alpha=0.63,beta=1.04",
                  [=](const Ray& X, double& mx, double& my) {
                    const double d = std::sqrt(b * (X.x() * X.x() + X.y() * X.y()) + X.z() * X.z());
                    const double den = ea * d + (1 - ea) * X.z();
                    mx = X.x() / den, my = X.y() / den;
                  },
                  [=](double mx, double my) {
                    const double r2 = mx * mx + my * my;
                    const double mz = (1 - b * ea * ea * r2) / (ea * std::sqrt(1 - (2 * ea - 1) * b * r2) + 1 - ea);
                    return Ray(mx, my, mz).normalized();
                  }};
  // Mei and Rives 2007: the unit sphere's point seen from (0, 0, -xi).
  const double ux = 1.7;
  PaperModel ucm{"unified:xi=1.7",
                 [=](const Ray& X, double& mx, double& my) {
                   const double den = X.z() + ux * X.norm();
                   mx = X.x() / den, my = X.y() / den;
                 },
                 [=](double mx, double my) {
                   const double r2 = mx * mx + my * my;
                   const double k = (ux + std::sqrt(1 + (1 - ux * ux) * r2)) / (1 + r2);
                   return Ray(k * mx, k * my, k - ux).normalized();
                 }};
  return {ds, eucm, ucm};
}

TEST(CalibratedLens, ClosedFormLawsAreTheirPapersFormulas) {
  const double fx = 300.5, fy = 297.25, cx = 640.5, cy = 512.25;
  std::mt19937 rng(5);
  std::normal_distribution<double> n01;
  for (const PaperModel& m : paper_models()) {
    const std::string spec = std::string(m.spec) + ",fx=" + std::to_string(fx) + ",fy=" + std::to_string(fy) +
                             ",cx=" + std::to_string(cx - 0.5) + ",cy=" + std::to_string(cy - 0.5);
    const Projection p = make(spec, {1280, 1024});
    const auto& lens = std::get<CalibratedLens>(p);
    double worst_px = 0, worst_ray = 0;
    int n = 0;
    for (int i = 0; i < 20000; ++i) {
      // Points at any distance (the papers' projections take unnormalized points).
      Ray X(n01(rng), n01(rng), n01(rng));
      X *= 0.1 + 10 * std::fabs(n01(rng));
      if (std::atan2(std::hypot(X.x(), X.y()), X.z()) > lens.theta_max()) continue;
      double mx, my, x, y;
      m.project(X, mx, my);
      ASSERT_TRUE(to_pixel(p, X.normalized(), x, y) || !in_frame(cx + fx * mx, cy + fy * my, {1280, 1024})) << m.spec;
      if (!in_frame(x, y, {1280, 1024})) continue;
      worst_px = std::max(worst_px, std::hypot(x - (cx + fx * mx), y - (cy + fy * my)));
      Ray d;
      ASSERT_TRUE(to_ray(p, x, y, d)) << m.spec;
      worst_ray = std::max(worst_ray, test::angle(d, m.unproject((x - cx) / fx, (y - cy) / fy)));
      ++n;
    }
    EXPECT_GT(n, 2000) << m.spec;
    EXPECT_LT(worst_px, 1e-9) << m.spec;
    EXPECT_LT(worst_ray, 1e-12) << m.spec;
    std::printf("[lens] %s: %d points, pixels within %.1e px, rays within %.1e rad of the paper's formulas\n", m.spec, n,
                worst_px, worst_ray);
  }
}

TEST(KannalaBrandt, NewtonInverseHoldsUpToTheRim) {
  // Angles from the centre to the image circle, and just inside it (where a Newton step from
  // theta = r overshoots the most): undistort(distort(t)) = t.
  const Projection p = make("kannala-brandt:fov=250,k1=0.05,k2=-0.01,k3=0.0012,k4=-0.00005", {1000, 1000});
  const auto& kb = std::get<CalibratedLens>(p);
  double worst = 0;
  for (int i = 0; i <= 1000; ++i) {
    const double t = kb.theta_max() * i / 1000.0;
    worst = std::max(worst, std::fabs(kb.angle(kb.radius(t)) - t));
  }
  for (int e = 1; e <= 15; ++e) {
    const double t = kb.theta_max() * (1 - std::pow(10.0, -e));
    worst = std::max(worst, std::fabs(kb.angle(kb.radius(t)) - t));
  }
  EXPECT_LT(worst, 1e-13);
  EXPECT_DOUBLE_EQ(kb.angle(kb.rd_max()), kb.theta_max());
  EXPECT_EQ(kb.angle(0.0), 0.0);
}

TEST(KannalaBrandt, WithoutCoefficientsIsTheEquidistantFisheye) {
  for (const char* fov : {"90", "180", "270", "360"}) {
    const Projection a = make(std::string("kannala-brandt:fov=") + fov, {801, 801});
    const Projection b = make(std::string("fisheye:fov=") + fov, {801, 801});
    double worst = 0;
    for (double y = 0.5; y < 801; y += 9.75)
      for (double x = 0.5; x < 801; x += 9.75) {
        Ray da = Ray::Zero(), db = Ray::Zero();  // (set only where to_ray succeeds)
        const bool ok = to_ray(a, x, y, da);
        ASSERT_EQ(ok, to_ray(b, x, y, db)) << fov << " at " << x << "," << y;
        if (ok) worst = std::max(worst, test::angle(da, db));
      }
    EXPECT_LT(worst, 1e-12) << fov;
  }
}

TEST(KannalaBrandt, ALawFoldingBackInsideTheFieldIsAnError) {
  // theta (1 - 0.1 theta^2) stops increasing at theta = 1/sqrt(0.3) = 104.6 deg.
  const std::string m = error_of("kannala-brandt:fov=220,k1=-0.1", {512, 512});
  EXPECT_NE(m.find("fold"), std::string::npos) << m;
  EXPECT_NE(m.find("104.6"), std::string::npos) << m;
  EXPECT_NE(m.find("give fov=209.2"), std::string::npos) << m;
  // Coefficients whose law overflows at the rim; fields past a model's domain (a double sphere's
  // here ends at 2 acos(-w2) = 251.2 degrees; a unified model's at xi = 0.5 at 2 acos(-0.5) = 240,
  // where R is infinite: open); a unified model at xi = 0 (a pinhole: R is infinite at 90
  // degrees) without a field takes a rectilinear lens's 160 degrees, and 180 is refused.
  EXPECT_THROW(make("kannala-brandt:fov=360,k4=1e305", {512, 512}), Error);
  const std::string past = error_of("double-sphere:xi=-0.18,alpha=0.59,fov=251.3", {512, 512});
  EXPECT_NE(past.find("expected fov <= 251.2"), std::string::npos) << past;
  EXPECT_NO_THROW(make("double-sphere:xi=-0.18,alpha=0.59,fov=251.2", {512, 512}));
  EXPECT_THROW(make("unified:xi=0.5,fov=240", {512, 512}), Error);
  EXPECT_NO_THROW(make("unified:xi=0.5,fov=239.9", {512, 512}));
  EXPECT_NEAR(std::get<CalibratedLens>(make("unified:xi=0", {512, 512})).theta_max(), deg2rad(80.0),
              1e-15);
  EXPECT_THROW(make("unified:xi=0,fov=180", {512, 512}), Error);
  EXPECT_NO_THROW(make("unified:xi=0,fov=120", {512, 512}));
  // The field it suggests is accepted, and its rim still round-trips.
  const Projection p = make("kannala-brandt:fov=209.2,k1=-0.1", {512, 512});
  const auto& kb = std::get<CalibratedLens>(p);
  EXPECT_NEAR(kb.angle(kb.radius(kb.theta_max() * 0.999)), kb.theta_max() * 0.999, 1e-9);
  // Default size: the image circle at the requested density (theta_d(pi/2) pixels per unit).
  const Size s = default_size(parse_spec("kannala-brandt:k1=0.01"), 100.0);
  const double rd = kPi / 2 * (1 + 0.01 * kPi * kPi / 4);
  EXPECT_EQ(s.width, std::llround(200 * rd));
}

TEST(BrownConrady, FoldsAreErrorsAndCoversIsSafe) {
  // r (1 - 0.3 r^2) stops increasing at r = 1/sqrt(0.9): 46.51 degrees off axis.
  const std::string m = error_of("brown-conrady:fov=120,k1=-0.3", {1920, 1080});
  EXPECT_NE(m.find("46.5"), std::string::npos) << m;
  EXPECT_NE(m.find("give fov=93.0"), std::string::npos) << m;
  // Without a fov the field ends at the fold, and every pixel inside it maps back.
  const Projection p = make("brown-conrady:k1=-0.3,fx=600", {1920, 1080});
  EXPECT_NEAR(std::get<CalibratedLens>(p).theta_max(), std::atan(1 / std::sqrt(0.9)), 1e-12);
  // Tangential terms that fold the image.
  EXPECT_THROW(make("brown-conrady:fov=120,p1=0.5", {1920, 1080}), Error);
  // covers(): where it says a rectangle is all valid, every point of it is (random rectangles,
  // some straddling the field's edge).
  const Projection q = make("brown-conrady:fov=100,fx=500,k1=-0.2,p1=0.01,p2=-0.01", {1920, 1080});
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ux(0, 1920), uy(0, 1080), side(1, 200);
  int covered = 0;
  for (int i = 0; i < 2000; ++i) {
    const double x0 = ux(rng), y0 = uy(rng), x1 = std::min(1920.0, x0 + side(rng)), y1 = std::min(1080.0, y0 + side(rng));
    if (!std::visit([&](const auto& c) { return c.covers(x0, y0, x1, y1); }, q)) continue;
    ++covered;
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 8; ++k)
        ASSERT_TRUE(contains(q, x0 + (x1 - x0) * j / 8, y0 + (y1 - y0) * k / 8)) << x0 << "," << y0;
  }
  EXPECT_GT(covered, 100);
}

TEST(PTLens, PixelsArePanoramaToolsRadii) {
  // Panorama Tools: r_src = (a r^3 + b r^2 + c r + d) r_dst, radii in units of half the shorter
  // side, r_dst the ideal pinhole's (focal length from hfov across the width).
  const double a = 0.01, b = -0.05, c = 0.02, d = 1 - a - b - c, W = 1920, H = 1080;
  const Projection p = make("ptlens:hfov=70,a=0.01,b=-0.05,c=0.02,cx=950,cy=530", {1920, 1080});
  const double f = 0.5 * W / std::tan(deg2rad(35.0)), half = 0.5 * std::min(W, H);
  double worst = 0;
  int n = 0;
  for (double t = 0.01; t < deg2rad(40.0); t += 0.013)
    for (double phi = 0; phi < 2 * kPi; phi += 0.37) {
      const Ray ray(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
      double x, y;
      if (!to_pixel(p, ray, x, y)) continue;
      const double u = f * std::tan(t) / half, r_src = (a * u * u * u + b * u * u + c * u + d) * u * half;
      worst = std::max(worst, std::hypot(x - (950.5 + r_src * std::cos(phi)), y - (530.5 + r_src * std::sin(phi))));
      ++n;
    }
  EXPECT_GT(n, 500);
  EXPECT_LT(worst, 1e-9);
  // A polynomial that folds inside a given field is refused; without a field it ends there.
  EXPECT_THROW(make("ptlens:hfov=100,a=-0.2,fov=170", {1920, 1080}), Error);
  EXPECT_THROW(make("ptlens:a=0.5,b=0.3,c=0.2", {1920, 1080}), Error);  // d = 0: R'(0) = 0
  const Projection q = make("ptlens:hfov=100,a=-0.2", {1920, 1080});
  double x, y;
  EXPECT_FALSE(to_pixel(q, Ray(std::sin(1.5), 0, std::cos(1.5)), x, y));
}

}  // namespace
}  // namespace panoproj
