#pragma once
// Burt and Adelson's pyramids ("A multiresolution spline with application to image mosaics",
// ACM TOG 2(4), 1983) of float planes: REDUCE (the 5-tap binomial 1 4 6 4 1 / 16 in each
// direction, then every second sample) and EXPAND (the same kernel on the samples spread to twice
// the size, times 4), edges extended by their last sample. A level of w x h has ceil(w/2) x
// ceil(h/2) above it.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace panoproj {

struct Plane {
  int64_t width = 0, height = 0;
  int channels = 0;
  std::vector<float> v;  // interleaved, row-major
  Plane() = default;
  Plane(int64_t w, int64_t h, int c)
      : width(w), height(h), channels(c), v(static_cast<size_t>(w * h * c), 0.0f) {}
  float* row(int64_t y) { return v.data() + y * width * channels; }
  const float* row(int64_t y) const { return v.data() + y * width * channels; }
};

// The level above `fine`.
Plane reduce(const Plane& fine, int threads);
// fine += sign * EXPAND(coarse), EXPAND taken to fine's size (coarse: the level above it).
void expand_add(const Plane& coarse, Plane& fine, float sign, int threads);

}  // namespace panoproj
