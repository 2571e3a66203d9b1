// Pyramid steps (pyramid.hpp).
#include "jobs/stitch/pyramid.hpp"

#include <algorithm>

#include "base/parallel.hpp"

namespace panoproj {
namespace {

constexpr float k0 = 1.0f / 16, k1 = 4.0f / 16, k2 = 6.0f / 16;

int64_t clamp_index(int64_t i, int64_t n) { return std::clamp<int64_t>(i, 0, n - 1); }

}  // namespace

Plane reduce(const Plane& fine, int threads) {
  const int c = fine.channels;
  const int64_t w = fine.width, h = fine.height, cw = (w + 1) / 2, ch = (h + 1) / 2;
  // Rows first (every row of fine, every second column), then columns.
  Plane across(cw, h, c), out(cw, ch, c);
  parallel_row_blocks(h, threads, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      const float* in = fine.row(y);
      float* o = across.row(y);
      for (int64_t j = 0; j < cw; ++j) {
        const float* a = in + clamp_index(2 * j - 2, w) * c;
        const float* b = in + clamp_index(2 * j - 1, w) * c;
        const float* m = in + 2 * j * c;
        const float* d = in + clamp_index(2 * j + 1, w) * c;
        const float* e = in + clamp_index(2 * j + 2, w) * c;
        for (int k = 0; k < c; ++k)
          o[j * c + k] = k0 * (a[k] + e[k]) + k1 * (b[k] + d[k]) + k2 * m[k];
      }
    }
  });
  parallel_row_blocks(ch, threads, [&](int64_t j0, int64_t j1) {
    const int64_t n = cw * c;
    for (int64_t j = j0; j < j1; ++j) {
      const float* a = across.row(clamp_index(2 * j - 2, h));
      const float* b = across.row(clamp_index(2 * j - 1, h));
      const float* m = across.row(2 * j);
      const float* d = across.row(clamp_index(2 * j + 1, h));
      const float* e = across.row(clamp_index(2 * j + 2, h));
      float* o = out.row(j);
      for (int64_t i = 0; i < n; ++i) o[i] = k0 * (a[i] + e[i]) + k1 * (b[i] + d[i]) + k2 * m[i];
    }
  });
  return out;
}

void expand_add(const Plane& coarse, Plane& fine, float sign, int threads) {
  const int c = fine.channels;
  const int64_t w = fine.width, h = fine.height, cw = coarse.width, chh = coarse.height;
  // Sample i of the fine level gathers the coarse samples j with i - 2j + 2 in 0..4, the
  // kernel's taps times 2 (each direction): (1 6 1) / 8 at even i, (4 4) / 8 at odd i.
  Plane across(w, chh, c);
  parallel_row_blocks(chh, threads, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      const float* in = coarse.row(y);
      float* o = across.row(y);
      for (int64_t i = 0; i < w; ++i) {
        const int64_t j = i / 2;
        const float* m = in + clamp_index(j, cw) * c;
        if (i % 2 == 0) {
          const float* a = in + clamp_index(j - 1, cw) * c;
          const float* b = in + clamp_index(j + 1, cw) * c;
          for (int k = 0; k < c; ++k) o[i * c + k] = 0.125f * (a[k] + b[k]) + 0.75f * m[k];
        } else {
          const float* b = in + clamp_index(j + 1, cw) * c;
          for (int k = 0; k < c; ++k) o[i * c + k] = 0.5f * (m[k] + b[k]);
        }
      }
    }
  });
  parallel_row_blocks(h, threads, [&](int64_t y0, int64_t y1) {
    const int64_t n = w * c;
    for (int64_t y = y0; y < y1; ++y) {
      const int64_t j = y / 2;
      float* o = fine.row(y);
      const float* m = across.row(clamp_index(j, chh));
      if (y % 2 == 0) {
        const float* a = across.row(clamp_index(j - 1, chh));
        const float* b = across.row(clamp_index(j + 1, chh));
        for (int64_t i = 0; i < n; ++i) o[i] += sign * (0.125f * (a[i] + b[i]) + 0.75f * m[i]);
      } else {
        const float* b = across.row(clamp_index(j + 1, chh));
        for (int64_t i = 0; i < n; ++i) o[i] += sign * 0.5f * (m[i] + b[i]);
      }
    }
  });
}

}  // namespace panoproj
