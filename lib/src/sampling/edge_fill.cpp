// Fill colours and the finishing pass over field edges (EdgeFill in options.hpp, edge_pass.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "sampling/edge_pass.hpp"
#include "panoproj/error.hpp"
#include "base/parallel.hpp"
#include "geometry/source_taps.hpp"
#include "geometry/tile_map.hpp"
#include "sampling/reference_sampler.hpp"
#include "base/sample_io.hpp"
#include "simd/geometry.hpp"

namespace panoproj {

std::array<double, 4> parse_fill_colour(std::string_view text) {
  const std::string t(text);
  auto fail = [&]() -> std::array<double, 4> {
    throw Error("fill colour '" + t + "' is not R,G,B[,A] (unit range, e.g. 1,1,1 for white) or #rrggbb[aa]");
  };
  std::array<double, 4> c{0, 0, 0, 1};
  if (!t.empty() && t[0] == '#') {
    if (t.size() != 7 && t.size() != 9) return fail();
    for (size_t i = 0; 1 + 2 * i < t.size(); ++i) {
      const std::string byte = t.substr(1 + 2 * i, 2);
      char* end = nullptr;
      const long v = std::strtol(byte.c_str(), &end, 16);
      if (end != byte.c_str() + 2) return fail();
      c[i] = static_cast<double>(v) / 255.0;
    }
    return c;
  }
  size_t n = 0, at = 0;
  while (at <= t.size() && n < 4) {
    const size_t comma = std::min(t.find(',', at), t.size());
    const std::string part = t.substr(at, comma - at);
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(v)) return fail();
    c[n++] = v;
    at = comma + 1;
  }
  if ((n != 3 && n != 4) || at <= t.size()) return fail();
  return c;
}

namespace {

// The edge pass for samples of type T.
template <class T>
void finish_typed(const Image& src, const Projection& source, const Projection& target, const Eigen::Matrix3d& rotation,
                  Interp interp, const EdgeFill& fill, int threads, Image& out) {
  const Size size = out.size();
  const int nc = out.channels(), alpha = out.alpha_channel();
  const double unit = unit_of(out.type());
  const auto pb = static_cast<int64_t>(out.pixel_bytes());
  const std::array<double, 4> back = fill.colour.value_or(std::array<double, 4>{0, 0, 0, 0});
  const SourceTaps taps(source);
  const bool whole = shows_whole_sphere(source);
  const int64_t tiles_x = (size.width + kTile - 1) / kTile, tiles_y = (size.height + kTile - 1) / kTile;
  // The pixel at p: A (coverage x alpha, [0, 1]) of colour c (unit range, unpremultiplied) over
  // the background (Porter-Duff "over"; without alpha the background is opaque).
  auto put = [&](unsigned char* p, const double* c, double A) {
    if (alpha >= 0) {
      const double ao = A + (1 - A) * back[3];
      for (int ch = 0; ch < nc; ++ch) {
        if (ch == alpha) continue;
        const int bc = ch < alpha ? ch : ch - 1;  // background colour channel
        store<T>(p + ch * sizeof(T), ao > 0 ? (A * c[ch] + (1 - A) * back[3] * back[bc]) / ao * unit : 0.0);
      }
      store<T>(p + alpha * sizeof(T), ao * unit);
    } else {
      for (int ch = 0; ch < nc; ++ch) store<T>(p + ch * sizeof(T), (A * c[ch] + (1 - A) * back[ch]) * unit);
    }
  };
  // The fill colour as a pixel of the output's type.
  std::vector<unsigned char> background(static_cast<size_t>(pb));
  const double none[4] = {0, 0, 0, 0};
  put(background.data(), none, 0.0);
  parallel_tasks(tiles_x * tiles_y, threads, [&](int64_t t, int) {
    const int64_t x0 = (t % tiles_x) * kTile, y0 = (t / tiles_x) * kTile;
    const int64_t x1 = std::min(size.width, x0 + kTile), y1 = std::min(size.height, y0 + kTile);
    // With a one-pixel apron: an edge pixel's neighbours may lie in the next tile.
    const int64_t ax0 = std::max<int64_t>(0, x0 - 1), ay0 = std::max<int64_t>(0, y0 - 1);
    const PixelRect apron{ax0, ay0, std::min(size.width, x1 + 1), std::min(size.height, y1 + 1)};
    const bool composite = fill.colour && alpha >= 0;  // translucent pixels go over the colour too
    const bool frame_edge = x0 == 0 || y0 == 0 || x1 == size.width || y1 == size.height;
    const bool covered = std::visit(
        [&](const auto& q) {
          return q.covers(static_cast<double>(apron.x0) + 0.5, static_cast<double>(apron.y0) + 0.5,
                          static_cast<double>(apron.x0 + apron.width()) - 0.5,
                          static_cast<double>(apron.y0 + apron.height()) - 0.5);
        },
        target);
    if (whole && covered && !composite) return;
    // The validity in SIMD where the pair has it (the same as the exact map's), else mapped.
    TileMap tm;
    if (SimdGeometry g; simd_geometry_for(source, target, rotation, apron, g)) simd_map_tile(g, apron, tm);
    else map_tile(source, target, rotation, apron, tm);
    // Tiles wholly without a source (the fill, or nothing) or wholly with one (nothing, unless
    // translucent pixels go over the colour) need no pixel-by-pixel look.
    const auto n_ok = std::count(tm.ok.begin(), tm.ok.end(), uint8_t{1});
    if (n_ok == 0) {
      if (fill.colour)
        for (int64_t y = y0; y < y1; ++y)
          for (int64_t x = x0; x < x1; ++x) std::memcpy(out.pixel(x, y), background.data(), static_cast<size_t>(pb));
      return;
    }
    if (n_ok == static_cast<int64_t>(tm.ok.size()) && !composite && !(fill.soft && frame_edge)) return;
    // Whether each pixel's 3x3 neighbourhood (within the frame) is uniform: the validity's
    // minimum and maximum over 3 columns, then over 3 rows.
    const int64_t aw = apron.width(), ah = apron.height();
    std::vector<uint8_t> lo(tm.ok.size()), hi(tm.ok.size());
    for (int64_t r = 0; r < ah; ++r)
      for (int64_t i = 0; i < aw; ++i) {
        const uint8_t* row = tm.ok.data() + r * aw;
        const int64_t a = std::max<int64_t>(i - 1, 0), b = std::min(i + 1, aw - 1);
        lo[static_cast<size_t>(r * aw + i)] = std::min({row[a], row[i], row[b]});
        hi[static_cast<size_t>(r * aw + i)] = std::max({row[a], row[i], row[b]});
      }
    auto uniform = [&](int64_t x, int64_t y) {
      const int64_t r = y - ay0, i = x - ax0, a = std::max<int64_t>(r - 1, 0), b = std::min(r + 1, ah - 1);
      const auto at = [&](int64_t rr) { return static_cast<size_t>(rr * aw + i); };
      return std::min({lo[at(a)], lo[at(r)], lo[at(b)]}) == std::max({hi[at(a)], hi[at(r)], hi[at(b)]});
    };
    std::vector<unsigned char> subs(static_cast<size_t>(16 * pb));
    double xs[16], ys[16];
    uint8_t ok[16];
    double c[4] = {0, 0, 0, 0};
    // Whether the pixel corners (cx, cy) in [x0, x1] x [y0, y1] have a source, computed once each.
    std::vector<int8_t> corners(static_cast<size_t>((x1 - x0 + 1) * (y1 - y0 + 1)), -1);
    auto corner = [&](int64_t cx, int64_t cy) {
      int8_t& k = corners[static_cast<size_t>((cy - y0) * (x1 - x0 + 1) + (cx - x0))];
      double sx, sy;
      if (k < 0) k = source_pixel(source, target, rotation, static_cast<double>(cx), static_cast<double>(cy), sx, sy);
      return static_cast<int>(k);
    };
    for (int64_t y = y0; y < y1; ++y)
      for (int64_t x = x0; x < x1; ++x) {
        unsigned char* p = out.pixel(x, y);
        const int v = tm.ok[static_cast<size_t>((y - ay0) * aw + (x - ax0))];
        // A candidate: a neighbour's centre differs, or the frame's border (where the field may
        // end inside the pixel with no neighbour to show it). The field's edge crosses it where a
        // corner differs from the centre (a smooth edge entering and leaving by one side cuts a
        // sliver of 1 / (8 R) px, R its radius of curvature in px).
        bool edge = (fill.soft && (x == 0 || y == 0 || x == size.width - 1 || y == size.height - 1)) || !uniform(x, y);
        if (edge && fill.soft) {
          bool cut = false;
          for (int q = 0; q < 4 && !cut; ++q) cut = corner(x + q % 2, y + q / 2) != v;
          edge = cut;
        }
        if (!edge || !fill.soft) {
          if (v && composite) {  // a pixel of the source, over the colour where translucent
            const double A = load<T>(p + alpha * sizeof(T)) / unit;
            for (int ch = 0; ch < nc; ++ch) c[ch] = load<T>(p + ch * sizeof(T)) / unit;
            if (A < 1) put(p, c, A);
          } else if (!v && fill.colour) {
            std::memcpy(p, background.data(), static_cast<size_t>(pb));
          }
          continue;
        }
        // The 4x4 sub-positions: their sources, sampled as the converter would.
        for (int q = 0; q < 16; ++q)
          ok[q] = source_pixel(source, target, rotation, static_cast<double>(x) + (q % 4 + 0.5) / 4,
                               static_cast<double>(y) + (q / 4 + 0.5) / 4, xs[q], ys[q]);
        sample_reference(src, taps, interp, xs, ys, ok, 16, subs.data());
        double sum[4] = {0, 0, 0, 0}, sum_a = 0;
        int n = 0;
        for (int q = 0; q < 16; ++q) {
          if (!ok[q]) continue;
          ++n;
          const unsigned char* s = subs.data() + q * pb;
          const double a = alpha >= 0 ? load<T>(s + alpha * sizeof(T)) / unit : 1.0;
          sum_a += a;
          for (int ch = 0; ch < nc; ++ch) sum[ch] += ch == alpha ? a : a * load<T>(s + ch * sizeof(T)) / unit;
        }
        for (int ch = 0; ch < nc; ++ch) c[ch] = sum_a > 0 ? sum[ch] / sum_a : 0.0;
        put(p, c, sum_a / 16.0);  // coverage n / 16 times the mean alpha sum_a / n
      }
  });
}

}  // namespace

void finish_edges(const Image& src, const Projection& source, const Projection& target, const Eigen::Matrix3d& rotation,
                  Interp interp, const EdgeFill& fill, int threads, Image& out) {
  if (!fill.active()) return;
  with_sample_type(out.type(), [&](auto t) {
    finish_typed<decltype(t)>(src, source, target, rotation, interp, fill, threads, out);
  });
}

}  // namespace panoproj
