// Pyramid steps (pyramid.hpp).
#include "jobs/stitch/pyramid.hpp"

#include <algorithm>

#include "base/parallel.hpp"

namespace panoproj {
namespace {

constexpr float k0 = 1.0f / 16, k1 = 4.0f / 16, k2 = 6.0f / 16;

int64_t clamp_index(int64_t i, int64_t n) {
  return std::clamp<int64_t>(i, 0, n - 1);
}

// One row's REDUCE along x: C channels (0: c at run time), the interior without clamps.
template <int C>
void reduce_row(const float* in, float* o, int64_t w, int64_t cw, int c) {
  const int n = C > 0 ? C : c;
  const auto tap = [&](int64_t j) {
    const float* a = in + clamp_index(2 * j - 2, w) * n;
    const float* b = in + clamp_index(2 * j - 1, w) * n;
    const float* m = in + 2 * j * n;
    const float* d = in + clamp_index(2 * j + 1, w) * n;
    const float* e = in + clamp_index(2 * j + 2, w) * n;
    for (int k = 0; k < n; ++k) o[j * n + k] = k0 * (a[k] + e[k]) + k1 * (b[k] + d[k]) + k2 * m[k];
  };
  const int64_t last = (w - 3) / 2;  // the last j whose taps lie inside
  for (int64_t j = 0; j < std::min<int64_t>(1, cw); ++j) tap(j);
  for (int64_t j = 1; j <= last && j < cw; ++j) {
    const float* m = in + 2 * j * n;
    for (int k = 0; k < n; ++k)
      o[j * n + k] = k0 * (m[k - 2 * n] + m[k + 2 * n]) + k1 * (m[k - n] + m[k + n]) + k2 * m[k];
  }
  for (int64_t j = std::max<int64_t>(last + 1, 1); j < cw; ++j) tap(j);
}

// One row's EXPAND along x into `o` (w samples of n channels).
template <int C>
void expand_row(const float* in, float* o, int64_t w, int64_t cw, int c) {
  const int n = C > 0 ? C : c;
  for (int64_t i = 0; i < w; ++i) {
    const int64_t j = i / 2;
    const float* m = in + clamp_index(j, cw) * n;
    const float* b = in + clamp_index(j + 1, cw) * n;
    if (i % 2 == 0) {
      const float* a = in + clamp_index(j - 1, cw) * n;
      for (int k = 0; k < n; ++k) o[i * n + k] = 0.125f * (a[k] + b[k]) + 0.75f * m[k];
    } else {
      for (int k = 0; k < n; ++k) o[i * n + k] = 0.5f * (m[k] + b[k]);
    }
  }
}

template <template <int> class Row, class... A>
void by_channels(int c, A... a) {
  switch (c) {
    case 1:
      return Row<1>::run(a..., c);
    case 2:
      return Row<2>::run(a..., c);
    case 4:
      return Row<4>::run(a..., c);
    default:
      return Row<0>::run(a..., c);
  }
}
template <int C>
struct ReduceRow {
  static void run(const float* in, float* o, int64_t w, int64_t cw, int c) {
    reduce_row<C>(in, o, w, cw, c);
  }
};
template <int C>
struct ExpandRow {
  static void run(const float* in, float* o, int64_t w, int64_t cw, int c) {
    expand_row<C>(in, o, w, cw, c);
  }
};

}  // namespace

Plane reduce(const Plane& fine, int threads) {
  Plane out, scratch;
  reduce_into(fine, out, scratch, threads);
  return out;
}

void reduce_into(const Plane& fine, Plane& out, Plane& across, int threads) {
  const int c = fine.channels;
  const int64_t w = fine.width, h = fine.height, cw = (w + 1) / 2, ch = (h + 1) / 2;
  // Rows first (every row of fine, every second column), then columns.
  across.reshape(cw, h, c), out.reshape(cw, ch, c);
  parallel_row_blocks(h, threads, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      by_channels<ReduceRow>(c, fine.row(y), across.row(y), w, cw);
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
}

namespace {

// fine = (add ? fine : 0) + EXPAND(coarse).
void expand_to(const Plane& coarse, Plane& fine, Plane& across, bool add, int threads) {
  const int c = fine.channels;
  const int64_t w = fine.width, h = fine.height, cw = coarse.width, chh = coarse.height;
  // Sample i of the fine level gathers the coarse samples j with i - 2j + 2 in 0..4, the
  // kernel's taps times 2 (each direction): (1 6 1) / 8 at even i, (4 4) / 8 at odd i.
  across.reshape(w, chh, c);
  parallel_row_blocks(chh, threads, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      by_channels<ExpandRow>(c, coarse.row(y), across.row(y), w, cw);
    }
  });
  parallel_row_blocks(h, threads, [&](int64_t y0, int64_t y1) {
    const int64_t n = w * c;
    for (int64_t y = y0; y < y1; ++y) {
      const int64_t j = y / 2;
      float* o = fine.row(y);
      const float* m = across.row(clamp_index(j, chh));
      // (fine's samples read only when added to: they may be unset)
      const float* a = across.row(clamp_index(y % 2 == 0 ? j - 1 : j, chh));
      const float* b = across.row(clamp_index(j + 1, chh));
      const float ka = y % 2 == 0 ? 0.125f : 0.0f, km = y % 2 == 0 ? 0.75f : 0.5f,
                  kb = y % 2 == 0 ? 0.125f : 0.5f;
      if (add)
        for (int64_t i = 0; i < n; ++i) o[i] += ka * a[i] + km * m[i] + kb * b[i];
      else
        for (int64_t i = 0; i < n; ++i) o[i] = ka * a[i] + km * m[i] + kb * b[i];
    }
  });
}

}  // namespace

void expand_add(const Plane& coarse, Plane& fine, Plane& scratch, int threads) {
  expand_to(coarse, fine, scratch, true, threads);
}

void expand_into(const Plane& coarse, Plane& fine, Plane& scratch, int threads) {
  expand_to(coarse, fine, scratch, false, threads);
}

}  // namespace panoproj
