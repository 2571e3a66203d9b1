// The blended panorama (panorama.hpp).
#include "jobs/stitch/panorama.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "base/parallel.hpp"
#include "base/sample_io.hpp"
#include "jobs/stitch/blend_margins.hpp"
#include "jobs/stitch/pyramid.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/projections/lens_pair.hpp"

namespace panoproj {
namespace {

// A share every covering layer keeps, so that a pixel whose largest margin is another layer's
// masked part still gets the layers that cover it (at most this much of any other share).
constexpr float kLeastShare = 1e-7f;
// A band's pixels (its rows times the canvas's width), but the pyramids' reach.
constexpr int64_t kBandPixels = int64_t{1} << 24;

struct Item {
  const StitchLayer* layer;
  PixelRect extent;
  LayerMargin margin;
  PixelType work;
  int first = 0, last = -1;  // the bands it meets
  Image source;
};

PixelRect meet(const PixelRect& a, const PixelRect& b) {
  const PixelRect r{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1),
                    std::min(a.y1, b.y1)};
  return r.x1 > r.x0 && r.y1 > r.y0 ? r : PixelRect{};
}

int64_t align_down(int64_t v, int64_t a) {
  return v / a * a;
}

// The largest and second largest margins at each pixel of the window, and whose the largest is.
template <class T>
using Buffer = std::vector<T, PixelAllocator<T>>;  // (huge pages, unset on resize)
struct Leaders {
  Buffer<float> first, second;
  Buffer<int> owner;
};

// A layer's part: colours (gray replicated where the panorama is RGB) and alpha 0 or 1, as floats
// (out reshaped; uncovered pixels 0).
void load_part(const Image& part, int colour, Plane& out, int threads) {
  const int ch = part.channels(), alpha = ch - 1;
  const double unit = unit_of(part.type());
  const size_t bytes = bytes_of(part.type());
  out.reshape(part.width(), part.height(), colour + 1);
  with_sample_type(part.type(), [&](auto t) {
    using T = decltype(t);
    parallel_row_blocks(part.height(), threads, [&](int64_t y0, int64_t y1) {
      for (int64_t y = y0; y < y1; ++y) {
        const unsigned char* in = part.row(y);
        float* o = out.row(y);
        for (int64_t x = 0; x < part.width();
             ++x, in += bytes * static_cast<size_t>(ch), o += colour + 1) {
          const double a = load<T>(in + bytes * static_cast<size_t>(alpha)) / unit;
          if (!(a > 0)) {
            std::fill(o, o + colour + 1, 0.0f);
            continue;
          }
          for (int c = 0; c < colour; ++c)
            o[c] = static_cast<float>(load<T>(in + bytes * static_cast<size_t>(ch == 2 ? 0 : c)) /
                                      unit);
          o[colour] = 1.0f;
        }
      }
    });
  });
}

class BandBlender {
 public:
  BandBlender(const StitchPlan& plan, const Projection& pano, bool windows, int colour, int levels)
      : plan_(plan), pano_(pano), windows_(windows), colour_(colour), levels_(levels) {}

  // Blends the items meeting `window` (full canvas width): window-sized, colour + 1 channels,
  // valid until the next call.
  const Plane& run(std::vector<Item*>& items, const PixelRect& window) const {
    leaders(items, window);
    if (plan_.blend.multiband)
      multiband(items, window, out_);
    else
      feather(items, window);
    return out_;
  }

 private:
  const StitchPlan& plan_;
  const Projection& pano_;
  bool windows_;
  int colour_, levels_;

  // Buffers kept from band to band (their pages touched once).
  mutable Leaders lead_;
  mutable Plane out_;
  mutable Buffer<float> margins_;
  mutable std::vector<Plane> acc_, P_, G_;  // multiband's: the band's sums, a layer's pyramids
  mutable Plane up_, scratch_;
  mutable Buffer<uint8_t> covered_;

  int threads() const { return plan_.options.threads; }

  static void reset(Plane& p, int64_t w, int64_t h, int c) {
    p.width = w, p.height = h, p.channels = c;
    p.v.assign(static_cast<size_t>(w * h * c), 0.0f);
  }

  void leaders(const std::vector<Item*>& items, const PixelRect& window) const {
    const auto n = static_cast<size_t>(window.width() * window.height());
    Leaders& l = lead_;
    // (The second largest: the feather's; multiband's seams need only the largest's owner.)
    const bool second = !plan_.blend.multiband;
    l.first.assign(n, kNoMargin), l.owner.assign(n, -1);
    if (second) l.second.assign(n, kNoMargin);
    Buffer<float>& m = margins_;
    for (size_t k = 0; k < items.size(); ++k) {
      const PixelRect r = meet(items[k]->extent, window);
      if (r.width() == 0) continue;
      m.resize(static_cast<size_t>(r.width() * r.height()));
      items[k]->margin.over(pano_, r, m.data(), threads());
      parallel_row_blocks(r.height(), threads(), [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y)
          for (int64_t x = 0; x < r.width(); ++x) {
            const float v = m[static_cast<size_t>(y * r.width() + x)];
            const auto at =
                static_cast<size_t>((r.y0 + y - window.y0) * window.width() + r.x0 + x - window.x0);
            if (v > l.first[at]) {
              if (second) l.second[at] = l.first[at];
              l.first[at] = v, l.owner[at] = static_cast<int>(k);
            } else if (second && v > l.second[at]) {
              l.second[at] = v;
            }
          }
      });
    }
  }

  // Item k's part over `r` (canvas pixels, inside `window`), and with `margins` its margins there
  // (margins_).
  Image part(const Item& item, const PixelRect& r, bool margins) const {
    const PixelRect made = windows_ ? r : PixelRect{0, 0, plan_.canvas.width, plan_.canvas.height};
    Image image = render_window(plan_, *item.layer, item.source, made, item.extent, nullptr);
    if (!windows_) {  // (the canvas: the rectangle cut out)
      Image cut(r.size(), image.channels(), image.type(), image.alpha_channel());
      for (int64_t y = r.y0; y < r.y1; ++y)
        std::copy(image.pixel(r.x0, y), image.pixel(r.x0, y) + cut.row_bytes(), cut.row(y - r.y0));
      image = std::move(cut);
    }
    if (margins) {
      margins_.resize(static_cast<size_t>(r.width() * r.height()));
      item.margin.over(pano_, r, margins_.data(), threads());
    }
    return image;
  }

  void feather(const std::vector<Item*>& items, const PixelRect& window) const {
    Plane& acc = out_;
    reset(acc, window.width(), window.height(), colour_ + 1);
    const Leaders& lead = lead_;
    for (size_t k = 0; k < items.size(); ++k) {
      check_interrupt();
      const PixelRect r = meet(items[k]->extent, window);
      if (r.width() == 0) continue;
      const Image p = part(*items[k], r, true);
      const Buffer<float>& m = margins_;
      const int ch = p.channels();
      const auto unit = static_cast<float>(unit_of(p.type()));
      with_sample_type(p.type(), [&](auto t) {
        using T = decltype(t);
        parallel_row_blocks(r.height(), threads(), [&](int64_t y0, int64_t y1) {
          for (int64_t y = y0; y < y1; ++y) {
            const T* in = reinterpret_cast<const T*>(p.row(y));
            float* o = acc.row(r.y0 + y - window.y0) + (r.x0 - window.x0) * (colour_ + 1);
            const size_t lead_row = static_cast<size_t>((r.y0 + y - window.y0) * window.width());
            for (int64_t x = 0; x < r.width(); ++x, in += ch, o += colour_ + 1) {
              if (!(static_cast<float>(in[ch - 1]) > 0)) continue;
              const size_t at = lead_row + static_cast<size_t>(r.x0 - window.x0 + x);
              const float mine = m[static_cast<size_t>(y * r.width() + x)];
              const float other =
                  lead.owner[at] == static_cast<int>(k) ? lead.second[at] : lead.first[at];
              const float s =
                  std::max(static_cast<float>(lens_weight0(mine, other, plan_.blend.feather)),
                           kLeastShare) /
                  unit;
              for (int c = 0; c < colour_; ++c) o[c] += s * static_cast<float>(in[ch == 2 ? 0 : c]);
              o[colour_] += s * unit;
            }
          }
        });
      });
    }
    normalise(acc);
  }

  // colour /= weight where the weight is positive (the weight becomes 1), else all 0.
  void normalise(Plane& acc) const {
    parallel_row_blocks(acc.height, threads(), [&](int64_t y0, int64_t y1) {
      for (int64_t y = y0; y < y1; ++y) {
        float* o = acc.row(y);
        for (int64_t x = 0; x < acc.width; ++x, o += colour_ + 1) {
          const float w = o[colour_];
          if (w > 0) {
            for (int c = 0; c < colour_; ++c) o[c] /= w;
            o[colour_] = 1.0f;
          } else {
            std::fill(o, o + colour_ + 1, 0.0f);
          }
        }
      }
    });
  }

  void multiband(const std::vector<Item*>& items, const PixelRect& window, Plane& out) const {
    const int L = levels_;
    std::vector<Plane>& acc = acc_;
    acc.resize(static_cast<size_t>(L) + 1), P_.resize(acc.size()), G_.resize(acc.size());
    for (int64_t w = window.width(), h = window.height(), k = 0; k <= L;
         ++k, w = (w + 1) / 2, h = (h + 1) / 2) {
      acc[static_cast<size_t>(k)].reshape(w, h, colour_ + 1);
      std::fill(acc[static_cast<size_t>(k)].v.begin(), acc[static_cast<size_t>(k)].v.end(), 0.0f);
    }
    // The pyramids' buffers at the largest part's size, once (growing them part by part would
    // move and fault their pages again).
    int64_t most = 0;
    for (const Item* item : items) {
      const PixelRect r = pyramid_rect(*item, window);
      most = std::max(most, r.width() * r.height());
    }
    for (size_t l = 0; l <= static_cast<size_t>(L); ++l, most = (most >> 2) + most / 2 + 2) {
      const auto n = static_cast<size_t>(most * (colour_ + 1));
      P_[l].v.reserve(n), G_[l].v.reserve(static_cast<size_t>(most));
      if (l == 0) up_.v.reserve(n), scratch_.v.reserve(n);
    }
    for (size_t k = 0; k < items.size(); ++k) {
      check_interrupt();
      add_pyramid(*items[k], static_cast<int>(k), window);
    }
    collapse(out);
  }

  // The part of `window` item's pyramid spans: its extent and the pyramid's reach (its weights
  // reach 2^(L+1) - 2 pixels past its seam mask, REDUCE's 2 samples a level; past that it adds
  // nothing), on the window's level grid; empty where the item misses the window.
  PixelRect pyramid_rect(const Item& item, const PixelRect& window) const {
    const int64_t align = int64_t{1} << levels_, reach = 3 * align;
    const PixelRect e = meet(item.extent, window);
    if (e.width() == 0) return {};
    return {window.x0 + align_down(std::max<int64_t>(e.x0 - reach - window.x0, 0), align),
            window.y0 + align_down(std::max<int64_t>(e.y0 - reach - window.y0, 0), align),
            std::min(window.x1, e.x1 + reach), std::min(window.y1, e.y1 + reach)};
  }

  // Item k's Laplacian pyramid added to the band's (acc_), weighted by its seam mask's pyramid.
  void add_pyramid(const Item& item, int k, const PixelRect& window) const {
    const Leaders& lead = lead_;
    const int L = levels_;
    std::vector<Plane>& acc = acc_;
    const PixelRect r = pyramid_rect(item, window);
    if (r.width() == 0) return;
    std::vector<Plane>& P = P_;
    std::vector<Plane>& G = G_;
    load_part(part(item, r, false), colour_, P[0], threads());
    // Level 0: colours times alpha and alpha; the seam mask: alpha where its margin leads.
    G[0].reshape(r.width(), r.height(), 1);
    parallel_row_blocks(r.height(), threads(), [&](int64_t y0, int64_t y1) {
      for (int64_t y = y0; y < y1; ++y) {
        const float* q = P[0].row(y);
        float* s = G[0].row(y);
        const size_t lead_row = static_cast<size_t>((r.y0 + y - window.y0) * window.width());
        for (int64_t x = 0; x < r.width(); ++x, q += colour_ + 1) {
          const size_t at = lead_row + static_cast<size_t>(r.x0 - window.x0 + x);
          s[x] = !(q[colour_] > 0) ? 0.0f : lead.owner[at] == k ? 1.0f : kLeastShare;
        }
      }
    });
    for (size_t l = 1; l <= static_cast<size_t>(L); ++l) {
      reduce_into(P[l - 1], P[l], scratch_, threads());
      reduce_into(G[l - 1], G[l], scratch_, threads());
    }
    // From the top down, in one pass a level: its colours extended past the alpha (N_l = P_l /
    // alpha, else EXPAND(N_{l+1})), kept in P_l for the level below, and its Laplacian N_l -
    // EXPAND(N_{l+1}) (N_L at the top) added to the band's level weighted by G_l.
    for (int l = L; l >= 0; --l) {
      Plane& q = P[static_cast<size_t>(l)];
      if (l < L) {
        up_.reshape(q.width, q.height, colour_ + 1);
        expand_into(P[static_cast<size_t>(l) + 1], up_, scratch_, threads());
      }
      const Plane& up = up_;
      const Plane& w = G[static_cast<size_t>(l)];
      Plane& a = acc[static_cast<size_t>(l)];
      const int64_t ox = (r.x0 - window.x0) >> l, oy = (r.y0 - window.y0) >> l;
      const int64_t cw = std::min(q.width, a.width - ox), chh = std::min(q.height, a.height - oy);
      parallel_row_blocks(q.height, threads(), [&](int64_t y0, int64_t y1) {
        const int C = colour_ + 1;
        for (int64_t y = y0; y < y1; ++y) {
          float* n = q.row(y);
          const float* u = l < L ? up.row(y) : nullptr;
          const float* s = w.row(y);
          float* o = y < chh ? a.row(oy + y) + ox * C : nullptr;
          for (int64_t x = 0; x < q.width; ++x, n += C) {
            const float alpha = n[colour_];
            for (int c = 0; c < colour_; ++c)
              n[c] = alpha > 1e-6f ? n[c] / alpha : (u ? u[x * C + c] : 0.0f);
            n[colour_] = 0.0f;
            if (!o || x >= cw || !(s[x] > 0)) continue;
            float* at = o + x * C;
            for (int c = 0; c < colour_; ++c) at[c] += s[x] * (n[c] - (u ? u[x * C + c] : 0.0f));
            at[colour_] += s[x];
          }
        }
      });
    }
  }

  // Each level's weighted mean, then the pyramid collapsed into out; covered where level 0 has
  // weight.
  void collapse(Plane& out) const {
    std::vector<Plane>& acc = acc_;
    const int L = levels_;
    Plane& o = acc[0];
    covered_.resize(static_cast<size_t>(o.width * o.height));
    for (size_t i = 0; i < covered_.size(); ++i)
      covered_[i] = o.v[i * static_cast<size_t>(colour_ + 1) + static_cast<size_t>(colour_)] > 0;
    for (Plane& a : acc) normalise(a);
    for (int l = L - 1; l >= 0; --l)
      expand_add(acc[static_cast<size_t>(l) + 1], acc[static_cast<size_t>(l)], scratch_, threads());
    parallel_row_blocks(o.height, threads(), [&](int64_t y0, int64_t y1) {
      for (int64_t i = y0 * o.width; i < y1 * o.width; ++i) {
        float* px = o.v.data() + i * (colour_ + 1);
        if (!covered_[static_cast<size_t>(i)])
          std::fill(px, px + colour_ + 1, 0.0f);
        else
          px[colour_] = 1.0f;
      }
    });
    std::swap(out, o);
  }
};

// The layers with a pixel on the canvas; colour: 3 if one is RGB, else 1 (gray).
std::vector<Item> items_of(const StitchPlan& plan, int& colour) {
  std::vector<Item> items;
  for (const StitchLayer& l : plan.layers) {
    const PixelRect e = layer_extent(plan, l);
    if (e.width() == 0) continue;
    if (l.info.channels >= 3) colour = 3;
    items.push_back(
        {&l, e, LayerMargin(plan, l), layer_work_type(plan, l, l.info), 0, -1, Image()});
  }
  if (items.empty())
    throw Error(plan.project.path + ": no image has a pixel on the panorama's canvas");
  return items;
}

// Canvas rows [y0, y1) of `blended` (made over `window`) into out's samples.
void store_rows(const Plane& blended, const PixelRect& window, int64_t y0, int64_t y1, Image& out,
                int threads) {
  const int64_t W = out.width();
  const int colour = out.channels() - 1;
  const double unit = unit_of(out.type());
  const PixelType type = out.type();
  with_sample_type(type, [&](auto t) {
    using T = decltype(t);
    const bool integer = std::is_integral_v<T>;
    parallel_row_blocks(y1 - y0, threads, [&](int64_t j0, int64_t j1) {
      for (int64_t j = j0; j < j1; ++j) {
        const float* in = blended.row(y0 + j - window.y0);
        unsigned char* o = out.row(y0 + j);
        for (int64_t i = 0; i < W * (colour + 1); ++i) {
          // Multiband can overshoot: integers clamp to their range, floats to >= 0.
          const double v = std::max(0.0, static_cast<double>(in[i]));
          store<T>(o + static_cast<size_t>(i) * sizeof(T), (integer ? std::min(v, 1.0) : v) * unit);
        }
      }
    });
  });
}

}  // namespace

PixelType panorama_type(const StitchPlan& plan) {
  if (plan.depth) return *plan.depth;
  PixelType t = PixelType::U8;
  for (const StitchLayer& l : plan.layers) {
    const PixelType u = l.info.type;
    if (u == PixelType::F16 || u == PixelType::F32) return PixelType::F32;
    if (u == PixelType::U16) t = u;
  }
  return t;
}

int blend_levels(const StitchPlan& plan) {
  if (plan.blend.levels > 0) return plan.blend.levels;
  // The overlaps' width in canvas pixels (the two largest margins' sum), on a grid of at most
  // 256 x 256 positions: its median w gives L = floor(log2(w / 4)), so that the coarsest level's
  // kernel (about 2^(L+1) pixels each side) stays within half the overlap; 1 to kAutoBlendLevels,
  // and 2^L at most a quarter of the canvas's shorter side (the pyramids' reach, 4 x 2^L rows,
  // widens every band).
  const Projection pano = make_projection(*plan.pano, plan.canvas);
  std::vector<LayerMargin> margins;
  for (const StitchLayer& l : plan.layers) margins.emplace_back(plan, l);
  const int64_t step =
      std::max<int64_t>(1, (std::max(plan.canvas.width, plan.canvas.height) + 255) / 256);
  std::vector<double> widths;
  for (int64_t y = step / 2; y < plan.canvas.height; y += step)
    for (int64_t x = step / 2; x < plan.canvas.width; x += step) {
      Ray d;
      if (!to_ray(pano, static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, d)) continue;
      double a = kNoMargin, b = kNoMargin;
      for (const LayerMargin& m : margins) {
        const double v = m.at(d);
        if (v > a)
          b = a, a = v;
        else if (v > b)
          b = v;
      }
      if (b > 0) widths.push_back((a + b) * center_density(pano));
    }
  if (widths.empty()) return 1;
  std::nth_element(widths.begin(), widths.begin() + static_cast<std::ptrdiff_t>(widths.size() / 2),
                   widths.end());
  const double w = widths[widths.size() / 2];
  int levels = static_cast<int>(std::floor(std::log2(std::max(w / 4, 2.0))));
  const auto side = static_cast<double>(std::min(plan.canvas.width, plan.canvas.height));
  while (levels > 1 && std::ldexp(1.0, levels) > side / 4) --levels;
  return std::clamp(levels, 1, kAutoBlendLevels);
}

BlendedPanorama blend_panorama(const StitchPlan& plan, PixelType type,
                               const std::function<void(const Image&, const PixelRect&)>& band_done,
                               const std::function<void(double)>& progress) {
  const Projection pano = make_projection(*plan.pano, plan.canvas);
  const bool windows = has_window(pano);
  int colour = 1;
  std::vector<Item> items = items_of(plan, colour);
  const int levels = plan.blend.multiband ? blend_levels(plan) : 0;
  const int64_t align = int64_t{1} << levels, pad = plan.blend.multiband ? 4 * align : 0;
  const int64_t W = plan.canvas.width, H = plan.canvas.height;
  // Sources: each band's, from the first band an image meets to its last (found for bands of
  // `rows`).
  const uint64_t per_px = plan.blend.multiband ? (colour + 1) * 4 * 4 + 24 : (colour + 1) * 8 + 24;
  int64_t rows = H, bands = 1;
  const auto window_of = [&](int64_t b) {
    const int64_t y0 = b * rows, y1 = std::min(H, y0 + rows);
    return PixelRect{0, align_down(std::max<int64_t>(y0 - pad, 0), align), W,
                     std::min(H, y1 + pad)};
  };
  const auto place = [&] {
    bands = (H + rows - 1) / rows;
    uint64_t peak = 0;
    for (Item& it : items) {
      it.first = -1;
      for (int64_t b = 0; b < bands; ++b)
        if (meet(it.extent, window_of(b)).width() > 0) {
          if (it.first < 0) it.first = static_cast<int>(b);
          it.last = static_cast<int>(b);
        }
    }
    for (int64_t b = 0; b < bands; ++b) {
      uint64_t sources = 0;
      for (const Item& it : items)
        if (it.first <= b && b <= it.last)
          sources = add_bytes(sources, image_bytes(it.layer->size, 4, bytes_of(it.work)));
      peak = std::max(peak, sources);
    }
    return peak;
  };
  const uint64_t image = image_bytes(plan.canvas, colour + 1, bytes_of(type));
  uint64_t sources = place();
  if (windows) {
    // Bands of at most kBandPixels (multiband: at least 8 times the pyramids' reach past their
    // edges, which are made twice), and what the budget leaves for their buffers (at least twice
    // that reach), on the coarsest level's grid; the whole canvas where a band would cover most.
    const uint64_t budget = memory_budget(plan.options.memory_limit);
    const uint64_t left = budget > add_bytes(image, sources) ? budget - image - sources : 0;
    const int64_t fit =
        static_cast<int64_t>(left / per_px / static_cast<uint64_t>(W)) - 2 * pad - align;
    const int64_t wanted = std::max(kBandPixels / W, 8 * pad);
    rows = std::max<int64_t>({align_down(std::min(wanted, fit), align),
                              (std::max<int64_t>(2 * pad, 16) + align - 1) / align * align});
    if (rows + 2 * pad >= H && static_cast<int64_t>(left / per_px) >= W * H) rows = H;
    rows = std::min(rows, H);
    sources = place();
  }
  const int64_t win_px = W * std::min(H, rows + 2 * pad + align);
  require_memory("the panorama " + size_text(plan.canvas) + ", its images and a band's buffers",
                 add_bytes(add_bytes(image, sources), static_cast<uint64_t>(win_px) * per_px),
                 plan.options.memory_limit);
  BlendedPanorama result{Image(plan.canvas, colour + 1, type, colour), levels};
  Image& out = result.image;
  const BandBlender blender(plan, pano, windows, colour, levels);
  for (int64_t b = 0; b < bands; ++b) {
    check_interrupt();
    std::vector<Item*> active;
    for (Item& it : items) {
      if (it.first == b) it.source = layer_source(plan, *it.layer, it.work);
      if (it.first <= b && b <= it.last) active.push_back(&it);
    }
    const PixelRect window = window_of(b);
    const Plane& blended = blender.run(active, window);
    const int64_t y0 = b * rows, y1 = std::min(H, y0 + rows);
    store_rows(blended, window, y0, y1, out, plan.options.threads);
    if (band_done) band_done(out, {0, y0, W, y1});
    for (Item& it : items)
      if (it.last == b) it.source = Image();
    if (progress) progress(static_cast<double>(b + 1) / static_cast<double>(bands));
  }
  return result;
}

}  // namespace panoproj
