#include "sampling/pyramid.hpp"

#include <algorithm>
#include <type_traits>

#include "base/sample_io.hpp"

namespace panoproj {
namespace {

// Integer samples of NC channels without alpha, the common case, in one pass over the pairs;
// (a + b + c + d + 2) / 4 rounds to nearest. All of the n_pairs column pairs are held.
template <class T, int NC>
void shrink_row_interior(const T* __restrict r0, const T* __restrict r1, T* __restrict out, int64_t n_pairs) {
  for (int64_t x = 0; x < n_pairs; ++x, r0 += 2 * NC, r1 += 2 * NC, out += NC)
    for (int c = 0; c < NC; ++c)
      out[c] = static_cast<T>((uint32_t{r0[c]} + r0[NC + c] + r1[c] + r1[NC + c] + 2) >> 2);
}

// Rows [y0, y1) of `to` (a level's window) from `from` (the level before): each pixel the mean of
// the 2x2 block of frame pixels under it, clamped to the pixels `from` holds; with alpha, the
// colour's mean weighted by alpha.
template <class T>
void shrink_rows(const Image& from, Image& to, int64_t y0, int64_t y1) {
  const int nc = from.channels(), alpha = from.alpha_channel();
  const double unit = unit_of(from.type());
  const int64_t fx0 = from.origin_x(), fx1 = fx0 + from.width() - 1;
  const int64_t fy0 = from.origin_y(), fy1 = fy0 + from.height() - 1;
  const auto pb = static_cast<int64_t>(from.pixel_bytes());
  // The columns of `to` whose both source columns are held: [i0, i1).
  const int64_t i0 = std::clamp((fx0 + 1) / 2 - to.origin_x(), int64_t{0}, to.width());
  const int64_t i1 = std::clamp((fx1 + 1) / 2 - to.origin_x(), i0, to.width());
  for (int64_t y = y0; y < y1; ++y) {
    const int64_t Y = to.origin_y() + y;
    const unsigned char* r0 = from.at(fx0, std::clamp(2 * Y, fy0, fy1));
    const unsigned char* r1 = from.at(fx0, std::clamp(2 * Y + 1, fy0, fy1));
    unsigned char* out = to.row(y);
    int64_t x = 0;
    for (; x < to.width(); ++x) {
      if constexpr (std::is_integral_v<T>) {
        if (alpha < 0 && x == i0 && i1 > i0) {
          const int64_t at = (2 * (to.origin_x() + x) - fx0) * pb;
          auto run = [&](auto nc_tag) {
            constexpr int N = decltype(nc_tag)::value;
            shrink_row_interior<T, N>(reinterpret_cast<const T*>(r0 + at), reinterpret_cast<const T*>(r1 + at),
                                      reinterpret_cast<T*>(out + x * pb), i1 - i0);
          };
          switch (nc) {
            case 1: run(std::integral_constant<int, 1>{}); break;
            case 2: run(std::integral_constant<int, 2>{}); break;
            case 3: run(std::integral_constant<int, 3>{}); break;
            default: run(std::integral_constant<int, 4>{}); break;
          }
          x = i1 - 1;
          continue;
        }
      }
      const int64_t X = to.origin_x() + x;
      const int64_t a = (std::clamp(2 * X, fx0, fx1) - fx0) * pb, b = (std::clamp(2 * X + 1, fx0, fx1) - fx0) * pb;
      if (alpha >= 0) {  // colour premultiplied by alpha, so that transparent pixels add none
        const unsigned char* p[4] = {r0 + a, r0 + b, r1 + a, r1 + b};
        double cover = 0, sum[4] = {};
        for (const unsigned char* q : p) {
          const double w = load<T>(q + alpha * sizeof(T)) / unit;
          cover += w;
          for (int c = 0; c < nc; ++c) sum[c] += c == alpha ? 0.0 : w * load<T>(q + c * sizeof(T));
        }
        for (int c = 0; c < nc; ++c)
          store<T>(out + x * pb + c * sizeof(T), c == alpha ? 0.25 * cover * unit : (cover > 0 ? sum[c] / cover : 0.0));
        continue;
      }
      for (int c = 0; c < nc; ++c) {
        const size_t o = static_cast<size_t>(c) * sizeof(T);
        const double m = 0.25 * (load<T>(r0 + a + o) + load<T>(r0 + b + o) + load<T>(r1 + a + o) + load<T>(r1 + b + o));
        // Integers: the same rounding as the interior, (sum + 2) / 4.
        store<T>(out + x * pb + o, std::is_integral_v<T> ? std::floor(m + 0.5) : m);
      }
    }
  }
}

}  // namespace

int deepest_level(const Projection& p) {
  Size s = size_of(p);
  int64_t face = 0;
  const SamplingFacts f = sampling_facts(p);
  if (const Cubemap* c = f.cube) face = c->uniform() ? c->face_size() : 1;  // uneven cells: level 0
  if (f.max) face = 1;
  int k = 0;
  while (s.width % 2 == 0 && s.height % 2 == 0 && s.width >= 2 && s.height >= 2 && (face == 0 || face % 2 == 0)) {
    s = {s.width / 2, s.height / 2};
    face /= 2;
    ++k;
  }
  return k;
}

Pyramid::Pyramid(const Image& src, const Projection& p) : src_(src) {
  const int n = deepest_level(p) + 1;
  Size s = size_of(p);
  const Image* from = &src;
  for (int k = 0; k < n; ++k, s = {s.width / 2, s.height / 2}) {
    Projection q = k == 0 ? p : rescaled(p, s);
    auto l = std::make_unique<Level>(Level{q, SourceTaps(q), Image(), nullptr});
    l->taps = SourceTaps(l->projection);  // it keeps a pointer into the projection: its final place
    if (k > 0) {
      const int64_t x0 = from->origin_x() / 2, y0 = from->origin_y() / 2;
      const int64_t x1 = (from->origin_x() + from->width() + 1) / 2, y1 = (from->origin_y() + from->height() + 1) / 2;
      l->image = Image({x1 - x0, y1 - y0}, from->channels(), from->type(), from->alpha_channel(), Image::Unfilled{});
      l->image.set_window(x0, y0, s);
      l->bands = std::make_unique<std::once_flag[]>(static_cast<size_t>((y1 - y0 + kBand - 1) / kBand));
    }
    levels_.push_back(std::move(l));
    if (k > 0) from = &levels_.back()->image;
  }
}

void Pyramid::build_rows(int k, int64_t y0, int64_t y1) const {
  if (k == 0) return;
  const Level& l = level(k);
  Image& to = const_cast<Image&>(l.image);  // rows are written once, under their band's flag
  const int64_t oy = to.origin_y();
  const int64_t b0 = std::max<int64_t>(0, y0 - oy) / kBand, b1 = (std::min(y1 - oy, to.height()) + kBand - 1) / kBand;
  for (int64_t b = b0; b < b1; ++b)
    std::call_once(l.bands[static_cast<size_t>(b)], [&] {
      const int64_t r0 = b * kBand, r1 = std::min(to.height(), r0 + kBand);
      build_rows(k - 1, 2 * (oy + r0), 2 * (oy + r1));
      with_sample_type(to.type(), [&](auto t) { shrink_rows<decltype(t)>(image(k - 1), to, r0, r1); });
    });
}

}  // namespace panoproj
