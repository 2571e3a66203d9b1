#include "mip_sampler.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <cmath>

#include "sample_io.hpp"

namespace panoproj {
namespace {

constexpr float kNone = HUGE_VALF;

// Squared steps between horizontal (h[j w + i]: pixels i, i + 1) and vertical (v[j w + i]: rows
// j, j + 1) neighbours; kNone where either has no position. x steps wrap on a full circle.
void steps(const TileMap& tm, double wrap, float* h, float* v) {
  const int64_t w = tm.rect.w, n = w * tm.rect.h;
  auto step = [&](int64_t a, int64_t b) {
    double dx = tm.xs[b] - tm.xs[a];
    const double dy = tm.ys[b] - tm.ys[a];
    if (wrap > 0) dx += dx > 0.5 * wrap ? -wrap : (dx < -0.5 * wrap ? wrap : 0.0);
    return tm.ok[a] && tm.ok[b] ? static_cast<float>(dx * dx + dy * dy) : kNone;
  };
  for (int64_t k = 0; k < n; ++k) {
    h[k] = k % w + 1 < w ? step(k, k + 1) : kNone;
    v[k] = k + w < n ? step(k, k + w) : kNone;
  }
}

}  // namespace

void sample_mip_tile(const Pyramid& pyramid, const TileMap& tm, double wrap_width, const LevelSampler& sample,
                     unsigned char* out, int64_t out_stride, MipScratch& s) {
  const TileRect& rect = tm.rect;
  const int64_t w = rect.w, n = rect.w * rect.h;
  const Image& src = pyramid.image(0);
  const int nc = src.channels(), alpha = src.alpha_channel();
  const auto pb = static_cast<int64_t>(src.pixel_bytes());
  const int deepest = pyramid.levels() - 1;
  // Per pixel: over each axis the smaller step to a neighbour (a seam or face edge lies on one
  // side only); the footprint's side is the geometric mean of the two (the square root of its
  // area), and r, half of it, the level scale (see antialias.hpp).
  s.rho.resize(static_cast<size_t>(3 * n));
  float* h = s.rho.data() + n;
  float* v = h + n;
  steps(tm, wrap_width, h, v);
  auto finite = [](float a) { return a == kNone ? 0.0f : a; };
  // Levels and weights: 2^j <= r < 2^(j+1) blends levels j and j + 1 linearly in r (f = r / 2^j
  // - 1, read off r's exponent and mantissa); r <= 1 is level 0 alone; from the deepest level on,
  // that level alone.
  s.level.resize(static_cast<size_t>(n));
  float* f = s.rho.data();
  int top = 0;  // the deepest level in use
  for (int64_t k = 0; k < n; ++k) {
    const int64_t i = k % w;
    const float sx = std::min(h[k], i > 0 ? h[k - 1] : kNone), sy = std::min(v[k], k >= w ? v[k - w] : kNone);
    const float r = 0.5f * std::sqrt(std::sqrt(std::max(finite(sx), 1e-12f) * std::max(finite(sy), 1e-12f)));
    const auto bits = std::bit_cast<uint32_t>(r);
    const int j = r > 1.0f ? static_cast<int>(bits >> 23) - 127 : 0;
    const bool last = j >= deepest;
    s.level[k] = static_cast<int8_t>(last ? deepest : j);
    f[k] = r > 1.0f && !last ? std::bit_cast<float>((bits & 0x7fffffu) | 0x3f800000u) - 1.0f : 0.0f;
    if (tm.ok[k]) top = std::max(top, s.level[k] + (f[k] > 0.0f));
  }
  TileMap& lm = s.level_map;
  lm.rect = rect;
  lm.xs.resize(static_cast<size_t>(n)), lm.ys.resize(static_cast<size_t>(n)), lm.ok.resize(static_cast<size_t>(n));
  // Level 0 straight into the tile (pixels with r <= 1 are then done, as without antialiasing).
  for (int64_t k = 0; k < n; ++k) lm.ok[k] = tm.ok[k] && s.level[k] == 0;
  std::copy(tm.xs.begin(), tm.xs.end(), lm.xs.begin());
  std::copy(tm.ys.begin(), tm.ys.end(), lm.ys.begin());
  sample(0, lm, out, out_stride);
  if (top == 0) return;
  // The others: weighted sums per channel, colour premultiplied by alpha where there is one.
  s.acc.assign(static_cast<size_t>(n * nc), 0.0f);
  s.samples.resize(static_cast<size_t>(n * pb));
  with_sample_type(src.type(), [&](auto tag) {
    using T = decltype(tag);
    const double unit = unit_of(src.type());
    auto add = [&](int64_t k, const unsigned char* p, float wt) {
      float* a = s.acc.data() + k * nc;
      if (alpha < 0) {
        for (int c = 0; c < nc; ++c) a[c] += wt * static_cast<float>(load<T>(p + c * sizeof(T)));
        return;
      }
      const double cover = load<T>(p + alpha * sizeof(T)) / unit;
      for (int c = 0; c < nc; ++c)
        a[c] += wt * static_cast<float>(c == alpha ? cover * unit : load<T>(p + c * sizeof(T)) * cover);
    };
    for (int64_t k = 0; k < n; ++k)
      if (tm.ok[k] && s.level[k] == 0 && f[k] > 0.0f) add(k, out + (k / w) * out_stride + (k % w) * pb, 1.0f - f[k]);
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
      for (int64_t k = 0; k < n; ++k)
        if (lm.ok[k]) add(k, s.samples.data() + k * pb, s.level[k] == level ? 1.0f - f[k] : f[k]);
    }
    for (int64_t k = 0; k < n; ++k) {
      if (!tm.ok[k] || (s.level[k] == 0 && f[k] == 0.0f)) continue;
      const float* a = s.acc.data() + k * nc;
      unsigned char* p = out + (k / w) * out_stride + (k % w) * pb;
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
  });
}

}  // namespace panoproj
