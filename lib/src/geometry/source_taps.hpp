#pragma once
// Where interpolation taps that fall outside a source's image read from (the source's
// SamplingFacts, declared by its module):
//   wrapping  [x0, x1) holds a turn of longitude: a tap past one side reads the other; past a
//             pole line (equirect, Miller and the cylindrical equal-area map to 90 degrees) it
//             continues on the far side (row mirrored, half a turn away). Positions that land
//             between pixel centres (a fractional box or half turn) read linearly between them;
//   cubemap   a tap past its face's edge is the neighbouring face's value where the ray through
//             the tap's centre on the extended face plane meets it, read bilinearly there, so
//             the kernel sees a continuous function across edges and corners (no seam);
//   dual fisheye clamps to the sample's lens half (never reading the other lens);
//   GoPro MAX  a tap past its cell reads on as a cube's, within the sample's lens (clamped into
//             the cell where that lens does not see the tap's ray);
//   others    clamp into the box. Whether a sample is valid at all is decided by to_pixel, so a
//             clamped tap only ever supports a sample whose centre is inside the field.
#include <cstdint>

#include "geometry/sampling_facts.hpp"

namespace panoproj {

class SourceTaps {
 public:
  explicit SourceTaps(const Projection& source);

  // The source's facts (its module's, read once).
  const SamplingFacts& facts() const { return facts_; }
  // The length of a turn in pixels where x wraps (so that steps across the seam can be taken the
  // short way), else 0.
  double wrap_period() const { return facts_.wraps_x ? facts_.x1 - facts_.x0 : 0.0; }
  // The pixels that hold the image: columns [col0, col1), rows [row0, row1) (centres in the box).
  int64_t col0() const { return col0_; }
  int64_t col1() const { return col1_; }
  int64_t row0() const { return row0_; }
  int64_t row1() const { return row1_; }
  // Face under a sample position (cubemap sources), lens (dual fisheye), lens and face (GoPro
  // MAX: 8 lens + face), else 0.
  int face_at(double sx, double sy) const {
    if (facts_.max) {
      const int k = facts_.max->lens_at(sx, sy);
      return 8 * k + facts_.max->lens(k).face_at(sx, sy);
    }
    return facts_.cube   ? facts_.cube->face_at(sx, sy)
           : facts_.dual ? facts_.dual->lens_at(sx, sy)
                         : 0;
  }
  // A source pixel and its share of one tap.
  struct Part {
    int64_t x, y;
    double w;
  };
  // The pixels that make up tap (ix, iy) of a sample on `face`: one pixel with weight 1, or up
  // to four bilinear parts (cube taps past the face; wrapped taps between pixel centres).
  // Returns their count.
  int resolve(int64_t ix, int64_t iy, int face, Part* parts) const;

 private:
  int wrapped(int64_t ix, int64_t iy, Part* parts) const;
  int cube_neighbour(const Cubemap& cube, int64_t ix, int64_t iy, int face, Part* parts) const;

  SamplingFacts facts_;
  int64_t col0_ = 0, col1_ = 0, row0_ = 0, row1_ = 0;
};

}  // namespace panoproj
