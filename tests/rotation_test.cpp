// The view rotation's conventions (rotation.hpp) and the frame's (conventions.hpp).
#include "panoproj/rotation.hpp"

#include <gtest/gtest.h>

#include "panoproj/conventions.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

void expect_ray(const Ray& a, const Ray& b) { EXPECT_LT(test::angle(a, b), 1e-12) << a.transpose() << " vs " << b.transpose(); }

TEST(Conventions, FrameLongitudeLatitude) {
  expect_ray(ray_from_lonlat(0, 0), Ray(0, 0, 1));             // ahead is +z
  expect_ray(ray_from_lonlat(kHalfPi, 0), Ray(1, 0, 0));       // longitude +90 is right, +x
  expect_ray(ray_from_lonlat(0, kHalfPi), Ray(0, -1, 0));      // latitude +90 is up, -y
  for (double lon : {-3.0, -1.0, 0.0, 2.5})
    for (double lat : {-1.5, 0.0, 0.7}) {
      EXPECT_NEAR(longitude(ray_from_lonlat(lon, lat)), lon, 1e-15);
      EXPECT_NEAR(latitude(ray_from_lonlat(lon, lat)), lat, 1e-15);
    }
  EXPECT_EQ(wrap_pi(kPi), -kPi);
  EXPECT_NEAR(wrap_pi(3 * kPi + 0.5), -kPi + 0.5, 1e-12);
  EXPECT_NEAR(sinc(1e-5), std::sin(1e-5) / 1e-5, 2.3e-16);
  EXPECT_EQ(sinc(0), 1.0);
}

TEST(Rotation, YawPitchRollSigns) {
  // R maps output rays to source rays; the output's centre looks along R * +z.
  expect_ray(rotation_from_ypr(90, 0, 0) * Ray(0, 0, 1), Ray(1, 0, 0));   // yaw right
  expect_ray(rotation_from_ypr(0, 90, 0) * Ray(0, 0, 1), Ray(0, -1, 0));  // pitch up
  expect_ray(rotation_from_ypr(0, 0, 90) * Ray(1, 0, 0), Ray(0, 1, 0));   // roll: right axis goes down
  expect_ray(rotation_from_ypr(0, 0, 90) * Ray(0, 0, 1), Ray(0, 0, 1));   // roll keeps the axis
}

TEST(Rotation, OrderIsRollThenPitchThenYaw) {
  // Yaw 90 after pitch 30: the centre looks 30 degrees up, toward longitude +90.
  const Ray c = rotation_from_ypr(90, 30, 0) * Ray(0, 0, 1);
  EXPECT_NEAR(longitude(c), kHalfPi, 1e-12);
  EXPECT_NEAR(latitude(c), deg2rad(30), 1e-12);
  // Roll does not move the centre; the output's right axis, rolled 90, points down then.
  const Eigen::Matrix3d r = rotation_from_ypr(40, 20, 90);
  expect_ray(r * Ray(0, 0, 1), rotation_from_ypr(40, 20, 0) * Ray(0, 0, 1));
  expect_ray(r * Ray(1, 0, 0), rotation_from_ypr(40, 20, 0) * Ray(0, 1, 0));
  EXPECT_NEAR((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-15);
  EXPECT_NEAR(r.determinant(), 1, 1e-15);
}

}  // namespace
}  // namespace panoproj
