#include "sampling/mip_sampler.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

#include "sampling/map_steps.hpp"
#include "base/sample_io.hpp"

namespace panoproj {

void sample_mip_tile(const Pyramid& pyramid, const TileMap& tm, double wrap_width, const LevelSampler& sample,
                     unsigned char* out, int64_t out_stride, MipScratch& s) {
  const PixelRect& rect = tm.rect;
  const int64_t w = rect.width(), n = rect.width() * rect.height();
  const Image& src = pyramid.image(0);
  const int nc = src.channels(), alpha = src.alpha_channel();
  const auto pb = static_cast<int64_t>(src.pixel_bytes());
  const int deepest = pyramid.levels() - 1;
  // Per pixel: over each axis the smaller step to a neighbour (a seam or face edge lies on one
  // side only); the footprint's side is the geometric mean of the two (the square root of its
  // area), and r, half of it, the level scale (see Antialias, options.hpp).
  s.rho.resize(static_cast<size_t>(n));
  // Levels and weights: 2^j <= r < 2^(j+1) blends levels j and j + 1 linearly in r (f = r / 2^j
  // - 1, read off r's exponent and mantissa); r <= 1 is level 0 alone; from the deepest level on,
  // that level alone.
  s.level.resize(static_cast<size_t>(n));
  float* f = s.rho.data();
  int top = 0;           // the deepest level in use
  bool level0 = false;  // some pixel uses level 0
  for (int64_t j = 0; j < rect.height(); ++j)
    for (int64_t i = 0; i < w; ++i) {
      const int64_t k = j * w + i;
      float ux, uy, vx, vy;
      const float q = pixel_steps(tm, i, j, static_cast<float>(wrap_width), ux, uy, vx, vy)
                          ? (ux * ux + uy * uy) * (vx * vx + vy * vy)  // (2 r)^4
                          : 0.0f;
      s.level[k] = 0, f[k] = 0.0f;
      if (!(q > 16.0f)) {  // r <= 1, most pixels of most conversions: no roots
        level0 |= tm.ok[k] != 0;
        continue;
      }
      const float r = 0.5f * std::sqrt(std::sqrt(q));
      const auto bits = std::bit_cast<uint32_t>(r);
      const int lo = static_cast<int>(bits >> 23) - 127;
      if (lo >= deepest) {
        s.level[k] = static_cast<int8_t>(deepest);
      } else {
        s.level[k] = static_cast<int8_t>(lo);
        f[k] = std::bit_cast<float>((bits & 0x7fffffu) | 0x3f800000u) - 1.0f;
      }
      if (tm.ok[k]) top = std::max(top, s.level[k] + (f[k] > 0.0f)), level0 |= s.level[k] == 0;
    }
  TileMap& lm = s.level_map;
  lm.rect = rect;
  lm.xs.resize(static_cast<size_t>(n)), lm.ys.resize(static_cast<size_t>(n)), lm.ok.resize(static_cast<size_t>(n));
  // Level 0 straight into the tile (pixels with r <= 1 are then done, as without antialiasing;
  // the sampler writes 0 where no level-0 sample is taken); without level 0, zeros.
  if (level0) {
    for (int64_t k = 0; k < n; ++k) lm.ok[k] = tm.ok[k] && s.level[k] == 0;
    std::copy(tm.xs.begin(), tm.xs.end(), lm.xs.begin());
    std::copy(tm.ys.begin(), tm.ys.end(), lm.ys.begin());
    sample(0, lm, out, out_stride);
  } else {
    for (int64_t j = 0; j < rect.height(); ++j)
      std::memset(out + j * out_stride, 0, static_cast<size_t>(w * pb));
  }
  if (top == 0) return;
  // The others: weighted sums per channel, colour premultiplied by alpha where there is one.
  s.acc.assign(static_cast<size_t>(n * nc), 0.0f);
  s.samples.resize(static_cast<size_t>(n * pb));
  with_sample_type(src.type(), [&](auto tag) {
    using T = decltype(tag);
    const double unit = unit_of(src.type());
    // Adds weight wt (per pixel of the rows, 0: none) times the samples of rows [0, h) of `from`.
    auto add = [&](const unsigned char* from, int64_t stride, auto&& weight) {
      for (int64_t j = 0; j < rect.height(); ++j) {
        const unsigned char* p = from + j * stride;
        float* a = s.acc.data() + j * w * nc;
        for (int64_t i = 0; i < w; ++i, p += pb, a += nc) {
          const float wt = weight(j * w + i);
          if (wt == 0.0f) continue;
          if (alpha < 0) {
            for (int c = 0; c < nc; ++c)
              a[c] += wt * static_cast<float>(load<T>(p + c * sizeof(T)));
            continue;
          }
          const double cover = load<T>(p + alpha * sizeof(T)) / unit;
          for (int c = 0; c < nc; ++c)
            a[c] += wt * static_cast<float>(c == alpha ? cover * unit : load<T>(p + c * sizeof(T)) * cover);
        }
      }
    };
    if (level0)
      add(out, out_stride, [&](int64_t k) { return tm.ok[k] && s.level[k] == 0 ? 1.0f - f[k] : 0.0f; });
    for (int level = 1; level <= top; ++level) {
      const double scale = std::ldexp(1.0, -level);
      bool any = false;
      for (int64_t k = 0; k < n; ++k) {
        lm.ok[k] = tm.ok[k] && (s.level[k] == level || (s.level[k] == level - 1 && f[k] > 0.0f));
        lm.xs[k] = tm.xs[k] * scale, lm.ys[k] = tm.ys[k] * scale;
        any |= lm.ok[k] != 0;
      }
      if (!any) continue;
      sample(level, lm, s.samples.data(), w * pb);
      add(s.samples.data(), w * pb, [&](int64_t k) {
        return lm.ok[k] ? (s.level[k] == level ? 1.0f - f[k] : f[k]) : 0.0f;
      });
    }
    for (int64_t j = 0; j < rect.height(); ++j) {
      unsigned char* p = out + j * out_stride;
      const float* a = s.acc.data() + j * w * nc;
      for (int64_t i = 0; i < w; ++i, p += pb, a += nc) {
        const int64_t k = j * w + i;
        if (!tm.ok[k] || (s.level[k] == 0 && f[k] == 0.0f)) continue;
        if constexpr (std::is_integral_v<T>) {
          if (alpha < 0) {  // rounded and clamped in float
            constexpr float kMax = static_cast<float>(std::numeric_limits<T>::max());
            for (int c = 0; c < nc; ++c) {
              const T t = static_cast<T>(std::min(std::max(a[c] + 0.5f, 0.0f), kMax));
              std::memcpy(p + c * sizeof(T), &t, sizeof(T));
            }
            continue;
          }
        }
        const double cover = alpha >= 0 ? a[alpha] / unit : 1.0;
        for (int c = 0; c < nc; ++c) {
          const double value = c == alpha || alpha < 0 ? a[c] : (cover > 1e-12 ? a[c] / cover : 0.0);
          store<T>(p + c * sizeof(T), value);
        }
      }
    }
  });
}

}  // namespace panoproj
