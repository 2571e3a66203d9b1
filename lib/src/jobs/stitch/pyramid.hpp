#pragma once
// Burt and Adelson's pyramids ("A multiresolution spline with application to image mosaics",
// ACM TOG 2(4), 1983) of float planes: REDUCE (the 5-tap binomial 1 4 6 4 1 / 16 in each
// direction, then every second sample) and EXPAND (the same kernel on the samples spread to twice
// the size, times 4), edges extended by their last sample. A level of w x h has ceil(w/2) x
// ceil(h/2) above it.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "panoproj/image.hpp"

namespace panoproj {

struct Plane {
  int64_t width = 0, height = 0;
  int channels = 0;
  std::vector<float, PixelAllocator<float>> v;  // interleaved, row-major (unset on resize)
  Plane() = default;
  // Zeros.
  Plane(int64_t w, int64_t h, int c)
      : width(w), height(h), channels(c), v(static_cast<size_t>(w * h * c), 0.0f) {}
  // w x h x c samples, unset (the buffer kept where it is large enough).
  void reshape(int64_t w, int64_t h, int c) {
    width = w, height = h, channels = c;
    v.resize(static_cast<size_t>(w * h * c));
  }
  float* row(int64_t y) { return v.data() + y * width * channels; }
  const float* row(int64_t y) const { return v.data() + y * width * channels; }
};

// The level above `fine`, into `coarse` (scratch: a buffer for the pass between).
void reduce_into(const Plane& fine, Plane& coarse, Plane& scratch, int threads);
Plane reduce(const Plane& fine, int threads);
// fine += EXPAND(coarse), EXPAND taken to fine's size (coarse: the level above it).
void expand_add(const Plane& coarse, Plane& fine, Plane& scratch, int threads);
// fine = EXPAND(coarse) at fine's size (fine's samples unread).
void expand_into(const Plane& coarse, Plane& fine, Plane& scratch, int threads);

}  // namespace panoproj
