// The Kannala-Brandt lens model (projections/kannala_brandt.hpp): its Newton inverse up to the
// image circle, its agreement with the equidistant fisheye when k = 0, and the error for a law
// that folds back inside the field. (Agreement with OpenCV's cv::fisheye: python/tests.)
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "panoproj/error.hpp"
#include "panoproj/projection.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

Projection make(const std::string& spec, Size size) { return make_projection(parse_spec(spec), size); }

TEST(KannalaBrandt, NewtonInverseHoldsUpToTheRim) {
  // Angles from the centre to the image circle, and just inside it (where a Newton step from
  // theta = r overshoots the most): undistort(distort(t)) = t.
  const Projection p = make("kannala-brandt:fov=250,k1=0.05,k2=-0.01,k3=0.0012,k4=-0.00005", {1000, 1000});
  const auto& kb = std::get<KannalaBrandt>(p);
  double worst = 0;
  for (int i = 0; i <= 1000; ++i) {
    const double t = kb.theta_max() * i / 1000.0;
    worst = std::max(worst, std::fabs(kb.undistort(kb.distort(t)) - t));
  }
  for (int e = 1; e <= 15; ++e) {
    const double t = kb.theta_max() * (1 - std::pow(10.0, -e));
    worst = std::max(worst, std::fabs(kb.undistort(kb.distort(t)) - t));
  }
  EXPECT_LT(worst, 1e-13);
  EXPECT_DOUBLE_EQ(kb.undistort(kb.rd_max()), kb.theta_max());
  EXPECT_EQ(kb.undistort(0.0), 0.0);
}

TEST(KannalaBrandt, WithoutCoefficientsIsTheEquidistantFisheye) {
  for (const char* fov : {"90", "180", "270", "360"}) {
    const Projection a = make(std::string("kannala-brandt:fov=") + fov, {801, 801});
    const Projection b = make(std::string("fisheye:fov=") + fov, {801, 801});
    double worst = 0;
    for (double y = 0.5; y < 801; y += 9.75)
      for (double x = 0.5; x < 801; x += 9.75) {
        Ray da, db;
        const bool ok = to_ray(a, x, y, da);
        ASSERT_EQ(ok, to_ray(b, x, y, db)) << fov << " at " << x << "," << y;
        if (ok) worst = std::max(worst, test::angle(da, db));
      }
    EXPECT_LT(worst, 1e-12) << fov;
  }
}

TEST(KannalaBrandt, ALawFoldingBackInsideTheFieldIsAnError) {
  // theta (1 - 0.1 theta^2) stops increasing at theta = 1/sqrt(0.3) = 104.6 deg.
  try {
    make("kannala-brandt:fov=220,k1=-0.1", {512, 512});
    FAIL();
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("fold"), std::string::npos) << m;
    EXPECT_NE(m.find("104.6"), std::string::npos) << m;
    EXPECT_NE(m.find("give fov=209.2"), std::string::npos) << m;
  }
  // Coefficients whose law overflows at the rim.
  EXPECT_THROW(make("kannala-brandt:fov=360,k4=1e305", {512, 512}), Error);
  // The field it suggests is accepted, and its rim still round-trips.
  const Projection p = make("kannala-brandt:fov=209.2,k1=-0.1", {512, 512});
  const auto& kb = std::get<KannalaBrandt>(p);
  EXPECT_NEAR(kb.undistort(kb.distort(kb.theta_max() * 0.999)), kb.theta_max() * 0.999, 1e-9);
  // Default size: the image circle at the requested density (theta_d(pi/2) pixels per unit).
  const Size s = default_size(parse_spec("kannala-brandt:k1=0.01"), 100.0);
  const double rd = kPi / 2 * (1 + 0.01 * kPi * kPi / 4);
  EXPECT_EQ(s.width, std::llround(200 * rd));
}

}  // namespace
}  // namespace panoproj
