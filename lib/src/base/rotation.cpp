#include "panoproj/rotation.hpp"

#include <Eigen/Geometry>

#include "panoproj/conventions.hpp"

namespace panoproj {

Eigen::Matrix3d rotation_from_ypr(double yaw_deg, double pitch_deg, double roll_deg) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  // AngleAxis about +y by yaw maps +z to (sin, 0, cos); about +x by pitch maps +z to
  // (0, -sin, cos) (up is -y); about +z by roll maps +x to (cos, sin, 0). See rotation.hpp.
  return (AngleAxisd(deg2rad(yaw_deg), Vector3d::UnitY()) *
          AngleAxisd(deg2rad(pitch_deg), Vector3d::UnitX()) *
          AngleAxisd(deg2rad(roll_deg), Vector3d::UnitZ()))
      .toRotationMatrix();
}

}  // namespace panoproj
