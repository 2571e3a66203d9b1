#pragma once
// GoPro MAX: the camera's two video streams, each a strip of three equi-angular cube faces,
// held as one frame with the first stream's strip on top (the camera's 0:0, the front lens at
// its centre) and the second's below (0:5, the back lens at its centre).
//
// Each strip is W = 2 S + C wide and H high: outer faces S wide, the centre face C = H. The
// faces are YouTube's EAC (cubemap.hpp: l f r / d b u, the bottom row turned 3, 1, 3). The seam
// between the lenses (the great circle z = 0) runs down the middle of every outer face; each half
// of an outer face is one lens's, and reaches D/2 px past the middle into the other's side, so a
// band of D px around the seam is seen by both (its content repeats D px apart). A half's 90
// degrees of face span S - D px across (the centre face's C; at 5.6K, S - D = 1312 < 1344: the
// outer faces are squeezed across) and H down. So with s the EAC cell coordinate (+-1 at the
// face's edges, the tangent a = tan(pi/4 s)), in an outer face starting at x0:
//   the half by its outer edge   x = x0 + (S - D)/2 (1 + s),   x in [x0, x0 + S/2)
//   the half by the centre face  x = x0 + (S + D)/2 + (S - D)/2 s,   x in [x0 + S/2, x0 + S)
// (max2sphere's frame templates and the shared real frames agree: docs/gopro_max.md).
//
// Each lens is a partial Cubemap on the whole frame (its centre face, its halves of the outer
// faces). A ray's margin in lens k is how far inside that lens's part it lies, in the outer faces'
// EAC angle across the seam: theta = atan(z / max(|x|, |y|)) (front positive),
//   m0 = beta + theta,  m1 = beta - theta,  beta = pi/4 * D / (S - D)  (the band's half-width).
// As a source a ray is seen by the lens with the larger margin (the hard cut at the seam), or
// with a feather f > 0 both are blended by lens 0's weight (lens_pair.hpp; f = 2 beta, the
// default, ramps linearly across the whole band).
#include <array>
#include <cmath>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/cubemap.hpp"
#include "panoproj/projections/lens_pair.hpp"

namespace panoproj {

class GoProMax {
 public:
  // lenses: lens 0 (front) and lens 1 (back) on the whole frame, over the same grid; beta: the
  // band's half-width, feather: the ramp's width (both in EAC angle, radians).
  GoProMax(std::array<Cubemap, 2> lenses, double beta, double feather)
      : lenses_(lenses), beta_(beta), feather_(feather) {}

  // The lens whose cell holds pixel position (x, y) (every cell is one lens's).
  int lens_at(double x, double y) const { return lenses_[0].face_at(x, y) >= 0 ? 0 : 1; }

  // The EAC angle across the seam (front positive) and the margins of the header comment.
  static double seam_angle(const Ray& d) {
    return std::atan2(d.z(), std::max(std::fabs(d.x()), std::fabs(d.y())));
  }
  double margin(int k, const Ray& d) const {
    const double t = seam_angle(d);
    return k == 0 ? beta_ + t : beta_ - t;
  }
  double weight0(double m0, double m1) const { return lens_weight0(m0, m1, feather_); }

  bool to_ray(double x, double y, Ray& d) const {
    return in_frame(x, y, size()) && lenses_[lens_at(x, y)].to_ray(x, y, d);
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    if (!d.allFinite() || d.isZero()) return false;
    const int k = seam_angle(d) >= 0 ? 0 : 1;
    return lenses_[k].to_pixel(d, x, y) || lenses_[1 - k].to_pixel(d, x, y);
  }
  bool contains(double x, double y) const { return in_frame(x, y, size()); }
  // True only if every position in [x0, x1] x [y0, y1] has a ray: one cell of one lens.
  bool covers(double x0, double y0, double x1, double y1) const {
    const int k = lens_at(x0, y0);
    return k == lens_at(x1, y1) && lenses_[k].covers(x0, y0, x1, y1);
  }

  Size size() const { return lenses_[0].size(); }
  // Pixels per radian at the centre faces' centres (the outer faces are squeezed across).
  double center_density() const { return lenses_[0].x_axis().half[2] * 4 / kPi; }
  const Cubemap& lens(int k) const { return lenses_[k]; }
  double beta() const { return beta_; }
  double feather() const { return feather_; }

 private:
  std::array<Cubemap, 2> lenses_;
  double beta_, feather_;
};

}  // namespace panoproj
