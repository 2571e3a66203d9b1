#pragma once
// Dual fisheye: the two back-to-back lenses of a 360 camera, recorded side by side (lens 0 left,
// lens 1 right) or top/bottom (lens 0 on top), each image circle inside its own half.
//
// Each lens is a Fisheye (fisheye.hpp) on the whole frame, its centre in its half, turned by its
// own rotation R_k (rotation.hpp's yaw, pitch, roll): camera ray = R_k * lens ray, so the lens
// looks along axis_k = R_k * z (the default second lens, yaw 180, looks back).
//
// A ray's margin in lens k is how far inside its image circle it lies: m_k = psi_max_k -
// angle(ray, axis_k). As a source, a ray is seen by the lens with the larger margin (the hard
// cut); with a feather f > 0, the converter (engine.cpp) blends both lenses by lens 0's weight
// (lens_pair.hpp) over a ramp f wide (in angle). For back-to-back lenses the overlap's width
// m0 + m1 is the same everywhere; f = the overlap (the default) gives w0 = m0 / (m0 + m1).
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross
#include <algorithm>
#include <array>
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/fisheye.hpp"
#include "panoproj/projections/lens_pair.hpp"

namespace panoproj {

class DualFisheye {
 public:
  // lenses: on the whole frame of `size`, each image circle inside its half; rotations: R_k;
  // feather: the ramp's width (radians), 0 for the hard cut.
  DualFisheye(Size size, bool top_bottom, std::array<Fisheye, 2> lenses, std::array<Eigen::Matrix3d, 2> rotations,
              double feather)
      : size_(size), top_bottom_(top_bottom), lenses_(lenses), rot_(rotations), feather_(feather) {
    for (int k = 0; k < 2; ++k) axis_[k] = rot_[k].col(2);
  }

  // The half holding pixel position (x, y): lens 0 left (top), lens 1 right (bottom).
  int lens_at(double x, double y) const {
    return (top_bottom_ ? y : x) < static_cast<double>(half()) ? 0 : 1;
  }
  // Where the halves meet: W/2 (side by side) or H/2 (top/bottom), in pixels.
  int64_t half() const { return top_bottom_ ? size_.height / 2 : size_.width / 2; }

  // How far inside lens k's image circle ray d lies (radians; negative outside).
  double margin(int k, const Ray& d) const {
    return lenses_[k].psi_max() - std::atan2(axis_[k].cross(d).norm(), axis_[k].dot(d));
  }
  // Lens 0's share of ray d, from the margins (see the header comment).
  double weight0(double m0, double m1) const { return lens_weight0(m0, m1, feather_); }

  bool to_ray(double x, double y, Ray& d) const {
    if (!in_frame(x, y, size_)) return false;
    const int k = lens_at(x, y);
    Ray l;
    if (!lenses_[k].to_ray(x, y, l)) return false;
    d = rot_[k] * l;
    return true;
  }

  bool to_pixel(const Ray& d, double& x, double& y) const {
    const int k = margin(0, d) >= margin(1, d) ? 0 : 1;
    return lens_pixel(k, d, x, y) || lens_pixel(1 - k, d, x, y);
  }

  bool contains(double x, double y) const {
    return in_frame(x, y, size_) && lenses_[lens_at(x, y)].contains(x, y);
  }
  // True only if every position in [x0, x1] x [y0, y1] has a ray: one half, its lens covers it.
  bool covers(double x0, double y0, double x1, double y1) const {
    const int k = lens_at(x0, y0);
    return k == lens_at(x1, y1) && lenses_[k].covers(x0, y0, x1, y1);
  }

  Size size() const { return size_; }
  double center_density() const { return lenses_[0].center_density(); }
  bool top_bottom() const { return top_bottom_; }
  const Fisheye& lens(int k) const { return lenses_[k]; }
  const Eigen::Matrix3d& rotation(int k) const { return rot_[k]; }
  double feather() const { return feather_; }
  // The cells that interpolation taps stay in (a lens's half).
  int64_t cell_width() const { return top_bottom_ ? size_.width : half(); }
  int64_t cell_height() const { return top_bottom_ ? half() : size_.height; }

 private:
  // Lens k's pixel of camera ray d, inside its closed half.
  bool lens_pixel(int k, const Ray& d, double& x, double& y) const {
    if (!lenses_[k].to_pixel(rot_[k].transpose() * d, x, y)) return false;
    const double c = top_bottom_ ? y : x, h = static_cast<double>(half());
    const double slack = kEdgeSlack * static_cast<double>(top_bottom_ ? size_.height : size_.width);
    return k == 0 ? c <= h + slack : c >= h - slack;
  }

  Size size_;
  bool top_bottom_;
  std::array<Fisheye, 2> lenses_;
  std::array<Eigen::Matrix3d, 2> rot_;
  std::array<Ray, 2> axis_;
  double feather_;
};

}  // namespace panoproj
