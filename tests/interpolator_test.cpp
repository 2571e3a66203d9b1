// Kernel weights: taps around the sample, partition of unity, reproduction of polynomials,
// interpolation at pixel centres.
#include "sampling/interpolator.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

const Interp kAll[] = {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3};

// Value at s of the kernel applied to samples f(i + 0.5) at the pixel centres.
double interpolate(Interp k, double s, double (*f)(double)) {
  double w[6];
  tap_weights(k, s, w);
  const int64_t b = first_tap(k, s);
  double v = 0;
  for (int i = 0; i < support(k); ++i) v += w[i] * f(static_cast<double>(b + i) + 0.5);
  return v;
}

TEST(Interpolator, SupportAndTapsAroundTheSample) {
  EXPECT_EQ(support(Interp::Nearest), 1);
  EXPECT_EQ(support(Interp::Bilinear), 2);
  EXPECT_EQ(support(Interp::Bicubic), 4);
  EXPECT_EQ(support(Interp::Lanczos3), 6);
  EXPECT_EQ(first_tap(Interp::Nearest, 3.99), 3);   // the pixel containing s
  EXPECT_EQ(first_tap(Interp::Bilinear, 3.6), 3);   // centres 3.5 and 4.5
  EXPECT_EQ(first_tap(Interp::Bilinear, 3.4), 2);   // centres 2.5 and 3.5
  EXPECT_EQ(first_tap(Interp::Bicubic, 3.6), 2);
  EXPECT_EQ(first_tap(Interp::Lanczos3, 3.6), 1);
  EXPECT_EQ(first_tap(Interp::Bilinear, -0.2), -1);  // centres -0.5 and 0.5
}

TEST(Interpolator, PartitionOfUnityAndPixelCentres) {
  for (Interp k : kAll)
    for (double s = -3.0; s < 5.0; s += 0.0371) {
      double w[6], sum = 0;
      tap_weights(k, s, w);
      for (int i = 0; i < support(k); ++i) sum += w[i];
      EXPECT_NEAR(sum, 1.0, 1e-14) << name_of(k) << " at " << s;
    }
  // At a pixel centre every kernel returns that pixel's value.
  auto f = [](double x) { return std::sin(3 * x) + x * x; };
  for (Interp k : kAll)
    for (double c = -2.5; c < 4; c += 1.0) EXPECT_NEAR(interpolate(k, c, f), f(c), 1e-12) << name_of(k);
}

TEST(Interpolator, ReproducesPolynomials) {
  auto linear = [](double x) { return 2.0 - 0.75 * x; };
  auto quadratic = [](double x) { return 0.3 * x * x - x + 1; };
  for (double s = 0.0; s < 3.0; s += 0.0917) {
    EXPECT_NEAR(interpolate(Interp::Bilinear, s, linear), linear(s), 1e-13);
    EXPECT_NEAR(interpolate(Interp::Bicubic, s, linear), linear(s), 1e-13);
    // Keys a = -0.5 is the third-order member: exact for quadratics too.
    EXPECT_NEAR(interpolate(Interp::Bicubic, s, quadratic), quadratic(s), 1e-13);
    // Normalized Lanczos-3 is not linear-exact: it ripples by up to ~2% of the slope (0.75 here).
    EXPECT_NEAR(interpolate(Interp::Lanczos3, s, linear), linear(s), 0.025 * 0.75);
  }
}

TEST(Interpolator, Names) {
  for (Interp k : kAll) EXPECT_EQ(parse_interp(name_of(k)), k);
  EXPECT_THROW(parse_interp("cubic"), Error);
}

}  // namespace
}  // namespace panoproj
