#include "engine/tile_strategies.hpp"

#include <algorithm>
#include <cmath>

#include "sampling/pyramid.hpp"
#include "sampling/subpixels.hpp"
#include "simd/geometry.hpp"

namespace panoproj {
namespace {

// The tile's n x n sub-pixels in the n-times target (in parts of at most kTile x kTile, the
// samplers' rect; with fp, the tile's footprint field, each through the footprint kernel), then
// their means.
void subpixels(const StrategyInputs& job, int n, const PixelRect& rect, unsigned char* corner,
               int64_t stride, TileScratch& wk, const FootprintField* fp) {
  const Image& src = job.sampling.image();
  const PixelRect sub{rect.x0 * n, rect.y0 * n, rect.x1 * n, rect.y1 * n};
  const auto pb = static_cast<int64_t>(src.pixel_bytes()), sub_stride = sub.width() * pb;
  wk.sub.resize(static_cast<size_t>(sub_stride * sub.height()));
  const Projection& sub_target = job.sub_targets[static_cast<size_t>(n)];
  for (int64_t y = 0; y < sub.height(); y += kTile)
    for (int64_t x = 0; x < sub.width(); x += kTile) {
      const PixelRect part{sub.x0 + x, sub.y0 + y, std::min(sub.x0 + x + kTile, sub.x1),
                           std::min(sub.y0 + y + kTile, sub.y1)};
      const FootprintField part_fp = fp ? fp->for_rect(rect, part, n) : FootprintField{};
      job.sampling.rect(sub_target, part, {}, wk.sub.data() + y * sub_stride + x * pb, sub_stride, wk,
                        fp ? &part_fp : nullptr);
    }
  average_subpixels(src, wk.sub.data(), sub_stride, rect, n, corner, stride);
}

// Widens b to the positions of the tile's n x n sub-pixels (its centres for n = 1).
void widen_to_subpixels(const StrategyInputs& job, int n, const PixelRect& rect, TileScratch& wk,
                        std::array<double, 4>& b) {
  job.sampling.widen_to_positions(job.sub_targets[static_cast<size_t>(n)],
                                  {rect.x0 * n, rect.y0 * n, rect.x1 * n, rect.y1 * n}, wk, b);
}

class Plain final : public TileStrategy {
 public:
  explicit Plain(const StrategyInputs& job) : job_(job) {}
  void tile(const PixelRect& rect, const KeptTile& kept, unsigned char* corner, int64_t stride,
            TileScratch& wk) const override {
    job_.sampling.rect(job_.target, rect, kept, corner, stride, wk);
  }
  bool widen_to_samples(const PixelRect& rect, TileScratch& wk,
                        std::array<double, 4>& b) const override {
    widen_to_subpixels(job_, 1, rect, wk, b);
    return true;
  }

 private:
  StrategyInputs job_;
};

class Supersample final : public TileStrategy {
 public:
  Supersample(const StrategyInputs& job, int n) : job_(job), n_(n) {}
  void tile(const PixelRect& rect, const KeptTile&, unsigned char* corner, int64_t stride,
            TileScratch& wk) const override {
    subpixels(job_, n_, rect, corner, stride, wk, nullptr);
  }
  bool widen_to_samples(const PixelRect& rect, TileScratch& wk,
                        std::array<double, 4>& b) const override {
    widen_to_subpixels(job_, n_, rect, wk, b);
    return true;
  }

 private:
  StrategyInputs job_;
  int n_;
};

// The tile's footprint side: as without antialiasing up to 2 source pixels (or where it is not
// known); else the footprint kernel, on n x n sub-pixels where the footprint is wider than the
// kernel reaches (footprint_kernel.hpp).
class Footprint final : public TileStrategy {
 public:
  explicit Footprint(const StrategyInputs& job) : job_(job) {}
  void tile(const PixelRect& rect, const KeptTile& kept, unsigned char* corner, int64_t stride,
            TileScratch& wk) const override {
    KeptFootprint* const k = kept.footprint;
    const bool known = k && k->ready();
    const int n = known ? k->n : sub_pixels(rect, wk);
    const FootprintField* field = known ? &k->field : &wk.field;
    if (!known && k && k->claim()) k->field = wk.field, k->n = n, k->publish();
    if (n == 0) job_.sampling.rect(job_.target, rect, kept, corner, stride, wk);
    else if (n == 1) job_.sampling.rect(job_.target, rect, kept, corner, stride, wk, field);
    else subpixels(job_, n, rect, corner, stride, wk, field);
  }
  bool widen_to_samples(const PixelRect& rect, TileScratch& wk,
                        std::array<double, 4>& b) const override {
    widen_to_subpixels(job_, std::max(1, sub_pixels(rect, wk)), rect, wk, b);
    return true;
  }

 private:
  // 0: plain samples; else the footprint kernel (wk.field) on n x n sub-pixels (1: the centres).
  // Measured once per tile (widen_to_samples, then tile()).
  int sub_pixels(const PixelRect& rect, TileScratch& wk) const {
    const int64_t id = rect.y0 * size_of(job_.target).width + rect.x0;
    if (wk.field_tile == id) return wk.field_n;
    const FootprintSides s = footprint_field(job_.source, job_.target, job_.rotation, rect, job_.wrap, wk.field);
    wk.field_tile = id;
    wk.field_n = s.side <= 2.0 ? 0
                               : std::clamp(static_cast<int>(std::ceil(s.split / kFootprintReach - 1e-9)), 1,
                                            Antialias::kMaxAuto);
    return wk.field_n;
  }

  StrategyInputs job_;
};

// Each tile's positions (kept, the fused path's, or mapped), then mip_sampler.hpp over the
// source's levels, each level's rows built as the taps reach them.
class Mip final : public TileStrategy {
 public:
  explicit Mip(const StrategyInputs& job) : job_(job), pyramid_(job.sampling.image(), job.source) {}
  void tile(const PixelRect& rect, const KeptTile& kept, unsigned char* corner, int64_t stride,
            TileScratch& wk) const override {
    const TileMap* tm =
        job_.sampling.lensed() ? nullptr : kept.map();  // (a lens's map is not the source's)
    SimdGeometry g;
    if (!tm) {
      if (job_.sampling.fused(job_.target, rect, g))
        simd_map_tile(g, rect, wk.map, grid_suits(job_.sampling.image().type()));  // the fused path's positions
      else
        job_.sampling.map_rect(job_.target, rect, wk.map);
      tm = &wk.map;
    }
    const bool cube_source = job_.sampling.taps().facts().cube != nullptr;
    const int reach = support(job_.sampling.interp()) / 2 + 1;
    sample_mip_tile(
        pyramid_, *tm, job_.wrap,
        [&](int k, const TileMap& m, unsigned char* o, int64_t st) {
          // The level's rows the taps reach (the tap rules stay within them, but a cube's, which
          // read neighbouring faces anywhere: all rows).
          double y0 = HUGE_VAL, y1 = -HUGE_VAL;
          for (size_t i = 0; i < m.ok.size(); ++i)
            if (m.ok[i]) y0 = std::min(y0, m.ys[i]), y1 = std::max(y1, m.ys[i]);
          if (cube_source) y0 = -HUGE_VAL, y1 = HUGE_VAL;
          pyramid_.build_rows(k, static_cast<int64_t>(std::max(-1e15, std::floor(y0))) - reach,
                              static_cast<int64_t>(std::min(1e15, std::ceil(y1))) + reach + 1);
          const Pyramid::Level& l = pyramid_.level(k);
          const Image& im = pyramid_.image(k);
          job_.sampling.map(im, l.taps, simd_source(im, l.taps), m, o, st, wk, nullptr);
        },
        corner, stride, wk.mip);
  }
  // (Its levels' rows reach beyond the taps' positions by the level's pixel size.)
  bool widen_to_samples(const PixelRect&, TileScratch&, std::array<double, 4>&) const override {
    return false;
  }

 private:
  StrategyInputs job_;
  Pyramid pyramid_;  // levels built as tiles read them (build_rows: const, thread-safe)
};

}  // namespace

std::unique_ptr<TileStrategy> tile_strategy(const Antialias& antialias, const StrategyInputs& job) {
  switch (antialias.mode) {
    case Antialias::Mode::Supersample: return std::make_unique<Supersample>(job, antialias.n);
    case Antialias::Mode::Auto: return std::make_unique<Footprint>(job);
    case Antialias::Mode::Mip: return std::make_unique<Mip>(job);
    case Antialias::Mode::Off: break;
  }
  return std::make_unique<Plain>(job);
}

}  // namespace panoproj
