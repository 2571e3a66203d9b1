#pragma once
// The conventions every projection shares. Tested in tests/conventions_test.cpp.
//
// Camera frame (OpenCV's, right-handed): +x right, +y down, +z forward.
// A ray is a unit Eigen::Vector3d in that frame.
// Longitude lambda = atan2(x, z): 0 straight ahead, positive to the right.
// Latitude  phi    = atan2(-y, hypot(x, z)): positive up (up is -y).
//   ray(lambda, phi) = (cos phi sin lambda, -sin phi, cos phi cos lambda).
// Pixel (i, j) covers [i, i+1) x [j, j+1); its centre is (i + 0.5, j + 0.5). Projections take and
// return continuous coordinates in that system, over the closed frame [0, W] x [0, H].
// (Calibration principal points cx, cy use OpenCV's integer centres: see kCvPixelShift.)
#include <Eigen/Core>
#include <cmath>
#include <numbers>

namespace panoproj {

using Ray = Eigen::Vector3d;

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr double kHalfPi = 0.5 * std::numbers::pi;
// OpenCV places pixel centres at integers; panoproj at i + 0.5. cx_panoproj = cx_opencv + 0.5.
inline constexpr double kCvPixelShift = 0.5;

inline constexpr double deg2rad(double d) { return d * (std::numbers::pi / 180.0); }
inline constexpr double rad2deg(double r) { return r * (180.0 / std::numbers::pi); }

inline Ray ray_from_lonlat(double lon, double lat) {
  const double c = std::cos(lat);
  return {c * std::sin(lon), -std::sin(lat), c * std::cos(lon)};
}
inline double longitude(const Ray& d) { return std::atan2(d.x(), d.z()); }
// atan2 form keeps full precision near the poles, where asin(-y) does not.
inline double latitude(const Ray& d) { return std::atan2(-d.y(), std::hypot(d.x(), d.z())); }

// Wraps an angle into [-pi, pi).
inline double wrap_pi(double a) {
  if (a >= -kPi && a < kPi) return a;
  a = std::fmod(a + kPi, kTwoPi);
  if (a < 0) a += kTwoPi;
  return a - kPi;
}

// Radial projections (fisheyes, calibrated lenses): the unit ray at angle t from the optical axis
// (+z) through image direction (u, v), r = |(u, v)| > 0; and a ray's angle off the axis with its
// direction (cu, cv) in the image (on the axis, where it is undefined, (1, 0): the front pole
// maps to the centre, the back pole to azimuth 0).
inline Ray radial_ray(double t, double u, double v, double r) {
  const double s = std::sin(t) / r;
  return Ray(s * u, s * v, std::cos(t));
}
inline double off_axis(const Ray& d, double& cu, double& cv) {
  const double s = std::hypot(d.x(), d.y());
  cu = s > 0.0 ? d.x() / s : 1.0;
  cv = s > 0.0 ? d.y() / s : 0.0;
  return std::atan2(s, d.z());
}

// sin(x)/x, exact to double precision near 0 (Taylor: 1 - x^2/6 + x^4/120).
inline double sinc(double x) {
  const double x2 = x * x;
  if (x2 < 1e-8) return 1.0 - x2 / 6.0 + x2 * x2 / 120.0;
  return std::sin(x) / x;
}

}  // namespace panoproj
