#pragma once
// View rotation. R maps output rays to source rays: src_ray = R * dst_ray.
//   R = Ry(yaw) * Rx(pitch) * Rz(roll)   (roll first, about the view axis; then pitch; then yaw)
//   Ry(a) = [c 0 s; 0 1 0; -s 0 c]   positive yaw turns the view right: +z -> (sin a, 0, cos a)
//   Rx(a) = [1 0 0; 0 c -s; 0 s c]   positive pitch looks up:          +z -> (0, -sin a, cos a)
//   Rz(a) = [c -s 0; s c 0; 0 0 1]   positive roll turns the view clockwise (the camera's right
//                                     axis goes down): +x -> (cos a, sin a, 0), so the picture
//                                     appears turned counter-clockwise.
// Angles in degrees; tested in tests/rotation_test.cpp.
#include <Eigen/Core>

namespace panoproj {

Eigen::Matrix3d rotation_from_ypr(double yaw_deg, double pitch_deg, double roll_deg);

}  // namespace panoproj
