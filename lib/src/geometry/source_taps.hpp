#pragma once
// Where interpolation taps that fall outside a source's pixels read from, by source kind:
//   equirect  wraps in longitude (full 360); past a pole row it continues on the far side
//             (row -1-j, longitude + 180), when the frame reaches that pole;
//   cylindrical wraps in longitude (full 360);
//   cubemap   a tap past its face's edge is the neighbouring face's value where the ray through
//             the tap's centre on the extended face plane meets it, read bilinearly there, so
//             the kernel sees a continuous function across edges and corners (no seam);
//   dual fisheye clamps to the sample's lens half (never reading the other lens);
//   others    clamp to the frame. Whether a sample is valid at all is decided by to_pixel, so a
//             clamped tap only ever supports a sample whose centre is inside the field.
#include <cstdint>

#include "panoproj/projection.hpp"

namespace panoproj {

class SourceTaps {
 public:
  explicit SourceTaps(const Projection& source);

  // Whether x wraps around a full circle of longitude (equirect and cylindrical sources).
  bool wraps_x() const { return wrap_x_; }
  // Face under a sample position (cubemap sources), lens (dual fisheye), else 0.
  int face_at(double sx, double sy) const {
    return cube_ ? cube_->face_at(sx, sy) : dual_ ? dual_->lens_at(sx, sy) : 0;
  }
  // A source pixel and its share of one tap.
  struct Part {
    int64_t x, y;
    double w;
  };
  // The in-frame pixels that make up tap (ix, iy) of a sample on `face`: one pixel with weight 1,
  // or (cube taps past the face) up to four bilinear parts. Returns their count.
  int resolve(int64_t ix, int64_t iy, int face, Part* parts) const;

 private:
  enum class Mode { Clamp, Equirect, Cube, Cells };
  Mode mode_ = Mode::Clamp;
  int64_t w_ = 0, h_ = 0;
  bool wrap_x_ = false, north_ = false, south_ = false;
  const Cubemap* cube_ = nullptr;
  const DualFisheye* dual_ = nullptr;
};

}  // namespace panoproj
