#include "panoproj/engine.hpp"

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "panoproj/error.hpp"
#include "panoproj/parallel.hpp"
#include "panoproj/resample.hpp"
#include "panoproj/source_edges.hpp"
#include "panoproj/tile_map.hpp"
#include "sampling/dual_blend.hpp"
#include "sampling/edge_pass.hpp"
#include "sampling/footprint_kernel.hpp"
#include "sampling/mip_sampler.hpp"
#include "sampling/pyramid.hpp"
#include "sampling/reference_sampler.hpp"
#include "simd/geometry.hpp"
#include "sampling/simd_sampler.hpp"
#include "sampling/subpixels.hpp"

namespace panoproj {

Engine parse_engine(std::string_view name) {
  for (Engine e : {Engine::Simd, Engine::Scalar, Engine::Reference})
    if (name == name_of(e)) return e;
  throw Error("engine '" + std::string(name) + "' is unknown (expected simd, scalar or reference)");
}

const char* name_of(Engine e) {
  switch (e) {
    case Engine::Simd: return "simd";
    case Engine::Scalar: return "scalar";
    case Engine::Reference: return "reference";
  }
  return "?";
}

const char* simd_target() { return simd_target_name(); }

namespace {

// The source as the SIMD kernels see it: the window held, and the cell taps must stay in (a cube
// face: cube layouts put faces on a grid of face-sized cells; else the whole frame).
SimdSource simd_source(const Image& src, const Projection& sp) {
  int64_t cw = 0, ch = 0;
  if (const auto* c = std::get_if<Cubemap>(&sp)) cw = ch = c->face_size();
  if (const auto* d = std::get_if<DualFisheye>(&sp)) cw = d->cell_width(), ch = d->cell_height();
  return {src.data(), static_cast<int64_t>(src.row_bytes()), src.channels(), src.alpha_channel(), src.type(),
          src.origin_x(), src.origin_y(), src.origin_x() + src.width(), src.origin_y() + src.height(), cw, ch};
}

// Widens box {x0, y0, x1, y1} to the valid positions of a tile map.
void widen_to(const TileMap& tm, std::array<double, 4>& b) {
  for (size_t i = 0; i < tm.ok.size(); ++i)
    if (tm.ok[i]) b = {std::min(b[0], tm.xs[i]), std::min(b[1], tm.ys[i]), std::max(b[2], tm.xs[i]), std::max(b[3], tm.ys[i])};
}

}  // namespace

Converter::Converter(Projection source, Projection target, const Eigen::Matrix3d& rotation,
                     Interp interp, Engine engine, int threads, bool cache_map, Antialias antialias, EdgeFill edges)
    : source_(std::move(source)), target_(std::move(target)), antialias_(antialias), edges_(edges),
      rotation_(rotation), interp_(interp), engine_(engine), threads_(threads), cache_map_(cache_map) {
  if (antialias_.mode != Antialias::Mode::Off && engine_ == Engine::Reference)
    throw Error("antialias " + name_of(antialias_) + " needs the simd or scalar engine (or --antialias off)");
  if (const auto* d = std::get_if<DualFisheye>(&source_); d && d->only() < 0) {
    // Each lens alone, blended (or cut) per tile; their maps are not kept (cache_map keeps those
    // of source_, which the lenses do not use).
    if (d->feather() > 0 && engine_ == Engine::Reference)
      throw Error("dual-fisheye: the feathered blend needs the simd or scalar engine (or feather=0)");
    if (d->feather() > 0 && antialias_.mode == Antialias::Mode::Mip)
      throw Error("dual-fisheye: antialias mip does not blend the lenses (use --antialias auto or supersample, or feather=0)");
    lenses_ = {d->only(0), d->only(1)};
    cache_map_ = false;
  }
  const int most = antialias_.mode == Antialias::Mode::Supersample ? antialias_.n
                  : antialias_.mode == Antialias::Mode::Auto      ? Antialias::kMaxAuto
                                                                  : 1;
  const Size s = size_of(target_);
  for (int n = 0; n <= most; ++n)
    sub_targets_.push_back(n < 2 ? target_ : rescaled(target_, {s.width * n, s.height * n}));
}

TileRect Converter::tile(int64_t t) const {
  const Size size = size_of(target_);
  const int64_t tiles_x = (size.width + kTile - 1) / kTile;
  const int64_t x0 = (t % tiles_x) * kTile, y0 = (t / tiles_x) * kTile;
  return {x0, y0, std::min(kTile, size.width - x0), std::min(kTile, size.height - y0)};
}

int64_t Converter::tile_count() const {
  const Size size = size_of(target_);
  return ((size.width + kTile - 1) / kTile) * ((size.height + kTile - 1) / kTile);
}

bool Converter::fused(const Projection& source, const Projection& target, const TileRect& rect, SimdGeometry& g) const {
  return engine_ == Engine::Simd && simd_geometry_for(source, target, rotation_, rect, g);
}


void Converter::build_cache() const {
  // Fused tiles recompute their geometry in registers faster than they could read a map: only the
  // others keep one (an empty TileMap marks a fused tile).
  std::vector<TileMap> maps(static_cast<size_t>(tile_count()));
  parallel_tasks(tile_count(), threads_, [&](int64_t t, int) {
    SimdGeometry g;
    const TileRect rect = tile(t);
    if (!fused(rect, g)) map_tile(source_, target_, rotation_, rect, maps[static_cast<size_t>(t)]);
  });
  cache_ = std::move(maps);
}

const TileMap* Converter::cached(int64_t t) const {
  if (!cache_map_) return nullptr;
  const TileMap& tm = cache_[static_cast<size_t>(t)];
  return tm.rect.w > 0 ? &tm : nullptr;
}

Converter::Region Converter::source_footprint() const {
  const Size frame = size_of(source_);
  const Region all{0, 0, frame.width, frame.height};
  // A cube source is read whole, a dual fisheye's too (its blend reads both lenses, beyond either
  // one's map); a target showing the whole sphere needs no mapping to know.
  if (std::holds_alternative<Cubemap>(source_) || std::holds_alternative<DualFisheye>(source_) || shows_whole_sphere(target_))
    return all;
  // Bounding box of the valid positions: over the kept maps, the fused tiles' vector geometry
  // (reduced in registers, nothing stored), or maps made one tile at a time.
  if (cache_map_) std::call_once(cache_once_, [this] { build_cache(); });
  const int64_t n_tiles = tile_count();
  const int n_workers = workers_for(n_tiles, threads_);
  std::vector<std::array<double, 4>> box(static_cast<size_t>(n_workers), {HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL});
  std::vector<double> spread(static_cast<size_t>(n_workers), 0.0);  // largest source px per output px
  std::vector<TileMap> local(static_cast<size_t>(n_workers));
  parallel_tasks(n_tiles, threads_, [&](int64_t t, int w) {
    std::array<double, 4> b{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};  // this tile's
    const TileRect rect = tile(t);
    const TileMap* tm = cached(t);
    SimdGeometry g;
    if (!tm && fused(rect, g)) {
      simd_tile_bounds(g, rect, b);
    } else {
      if (!tm) map_tile(source_, target_, rotation_, rect, local[static_cast<size_t>(w)]), tm = &local[static_cast<size_t>(w)];
      widen_to(*tm, b);
    }
    if (b[0] > b[2]) return;
    auto& all = box[static_cast<size_t>(w)];
    all = {std::min(all[0], b[0]), std::min(all[1], b[1]), std::max(all[2], b[2]), std::max(all[3], b[3])};
    // The tile's extent over its size bounds its mean step (antialiasing's reach below).
    const double s = std::max((b[2] - b[0]) / static_cast<double>(std::max<int64_t>(rect.w - 1, 1)),
                              (b[3] - b[1]) / static_cast<double>(std::max<int64_t>(rect.h - 1, 1)));
    spread[static_cast<size_t>(w)] = std::max(spread[static_cast<size_t>(w)], s);
  });
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (const auto& b : box) x0 = std::min(x0, b[0]), y0 = std::min(y0, b[1]), x1 = std::max(x1, b[2]), y1 = std::max(y1, b[3]);
  if (x0 > x1) return {0, 0, 0, 0};  // no pixel has a source
  const int n = support(interp_);
  // Taps (first_tap is monotonic), one pixel of margin for the 1/256 px map tolerance.
  Region r{first_tap(interp_, x0) - 1, first_tap(interp_, y0) - 1, first_tap(interp_, x1) + n + 1,
           first_tap(interp_, y1) + n + 1};
  if (antialias_.mode != Antialias::Mode::Off) {
    // rho: the largest step from one output pixel to the next, in source pixels. Mip level k
    // (2^k <= rho / 2) reaches its taps' n / 2 level pixels of 2^k source px, and one more for a
    // block cut by the window's edge (which averages only what it holds). Sub-pixels reach half
    // an output pixel further (rho / 2 source px), and auto's footprint kernel its own taps
    // (kFootprintTaps / 2 from the sample) where they reach further than interp_'s.
    const double rho = std::max(1.0, *std::max_element(spread.begin(), spread.end()));
    int64_t m = static_cast<int64_t>(std::ceil(rho / 2)) + 1;
    if (antialias_.mode == Antialias::Mode::Auto) m += std::max(0, kFootprintTaps / 2 - n / 2);
    if (antialias_.mode == Antialias::Mode::Mip) m = static_cast<int64_t>(std::exp2(std::ceil(std::log2(rho)))) * (n / 2 + 2);
    r = {r.x0 - m, r.y0 - m, r.x1 + m, r.y1 + m};
  }
  // Where taps leave the frame, the edge rules read elsewhere: wrap (full width), pole crossing
  // (full width, rows from the pole), clamp (the edge row or column, inside the clamp).
  if (r.x0 < 0 || r.x1 > frame.width) r.x0 = 0, r.x1 = frame.width;
  if (r.y0 < 0) r.y0 = 0, r.x0 = 0, r.x1 = frame.width;
  if (r.y1 > frame.height) r.y1 = frame.height, r.x0 = 0, r.x1 = frame.width;
  return r;
}

Image Converter::run(const Image& src, EngineStats* stats,
                     const std::function<void(double)>& progress) const {
  Image out;
  run(src, out, stats, progress);
  return out;
}

void Converter::run(const Image& src, Image& out, EngineStats* stats,
                    const std::function<void(double)>& progress) const {
  const Size expected = size_of(source_);
  if (src.frame_size() != expected)
    throw Error("image size " + std::to_string(src.frame_size().width) + "x" + std::to_string(src.frame_size().height) +
                " does not match the source projection's " + std::to_string(expected.width) + "x" +
                std::to_string(expected.height));
  if (engine_ == Engine::Reference) {
    out = remap(src, source_, target_, rotation_, {interp_, threads_});
    finish_edges(src, source_, target_, rotation_, interp_, edges_, threads_, out);
    if (progress) progress(1.0);
    return;
  }
  // Every pixel is written below (invalid ones as 0): a new buffer need not be filled.
  if (out.size() != size_of(target_) || out.channels() != src.channels() || out.type() != src.type() ||
      out.alpha_channel() != src.alpha_channel())
    out = Image(size_of(target_), src.channels(), src.type(), src.alpha_channel(), Image::Unfilled{});
  const SourceEdges edges(source_);
  const SimdSource simd_src = simd_source(src, source_);
  const bool use_simd = engine_ == Engine::Simd;
  const int64_t n_tiles = tile_count();
  const int n_workers = workers_for(n_tiles, threads_);
  if (cache_map_) std::call_once(cache_once_, [this] { build_cache(); });
  std::optional<Pyramid> pyramid;
  if (antialias_.mode == Antialias::Mode::Mip) pyramid.emplace(src, source_);
  struct Worker {
    TileMap map;
    SimdMisses misses;
    EngineStats stats;
    MipScratch mip;
    std::vector<unsigned char> sub;  // a tile's sub-pixel samples
    std::vector<float> weights;       // a dual fisheye's lens 0 weights over a tile
    std::vector<unsigned char> other;  // and its lens 1 samples there
    FootprintField field;              // the footprint kernel's widths over a tile
    std::vector<float> ex, ey;         // and over a row (the scalar engine)
  };
  std::vector<Worker> workers(static_cast<size_t>(n_workers));
  // The samples the SIMD kernels left in wk.misses (rect's pixel indices) by the edge rules
  // (with fp: the footprint kernel, its widths there).
  auto resolve_misses = [&](const Image& im, const SourceEdges& e, const TileRect& r, unsigned char* out_at,
                            int64_t stride, Worker& wk, const FootprintField* fp) {
    const uint8_t one = 1;
    const auto pb = static_cast<int64_t>(im.pixel_bytes());
    const SimdMisses& m = wk.misses;
    for (size_t q = 0; q < m.index.size(); ++q) {
      const int64_t i = m.index[q] % r.w, j = m.index[q] / r.w;
      unsigned char* o = out_at + j * stride + i * pb;
      if (!fp) {
        sample_reference(im, e, interp_, &m.xs[q], &m.ys[q], &one, 1, o);
        continue;
      }
      float ex, ey;
      fp->at(i, j, ex, ey);
      sample_footprint_reference(im, e, &m.xs[q], &m.ys[q], &ex, &ey, &one, 1, o);
    }
    wk.stats.edge_samples += static_cast<int64_t>(m.index.size());
  };
  // Samples positions map m of image im (edges e, SIMD view ss) into out: the SIMD kernels, and
  // the reference's edge rules for the samples they leave (seams, poles, face edges, the
  // window); the scalar engine samples all with the reference. fp: the footprint kernel and its
  // widths over the rect, else interp_.
  auto sample_map = [&](const Image& im, const SourceEdges& e, const SimdSource& ss, const TileMap& m,
                        unsigned char* out_at, int64_t stride, Worker& wk, const FootprintField* fp) {
    if (!use_simd) {
      wk.ex.resize(static_cast<size_t>(m.rect.w)), wk.ey.resize(static_cast<size_t>(m.rect.w));
      for (int64_t j = 0; j < m.rect.h; ++j) {
        const size_t k = static_cast<size_t>(j * m.rect.w);
        if (!fp) {
          sample_reference(im, e, interp_, m.xs.data() + k, m.ys.data() + k, m.ok.data() + k, m.rect.w, out_at + j * stride);
          continue;
        }
        for (int64_t i = 0; i < m.rect.w; ++i) fp->at(i, j, wk.ex[static_cast<size_t>(i)], wk.ey[static_cast<size_t>(i)]);
        sample_footprint_reference(im, e, m.xs.data() + k, m.ys.data() + k, wk.ex.data(), wk.ey.data(), m.ok.data() + k,
                                   m.rect.w, out_at + j * stride);
      }
      return;
    }
    wk.misses.clear();
    simd_sample(ss, interp_, m, out_at, stride, wk.misses, fp);
    resolve_misses(im, e, m.rect, out_at, stride, wk, fp);
  };
  // The tile rect of target t, seen through source projection sp, into out: fused where the SIMD
  // geometry takes it, else from its map (the kept one, or made now); fp as sample_map's.
  auto sample_from = [&](const Projection& sp, const Projection& t, const TileRect& rect, const TileMap* tm,
                         unsigned char* out_at, int64_t stride, Worker& wk, const FootprintField* fp) {
    SimdGeometry g;
    const bool in_registers = !tm && fused(sp, t, rect, g);
    if (!tm && !in_registers) map_tile(sp, t, rotation_, rect, wk.map), tm = &wk.map;
    if (tm) wk.stats.interpolated_cells += tm->interpolated_cells, wk.stats.exact_cells += tm->exact_cells;
    wk.stats.fused_tiles += in_registers;
    if (!in_registers) return sample_map(src, edges, simd_src, *tm, out_at, stride, wk, fp);
    wk.misses.clear();
    simd_convert(g, rect, simd_src, interp_, out_at, stride, wk.misses, fp);
    resolve_misses(src, edges, rect, out_at, stride, wk, fp);
  };
  // The same from source_; a dual fisheye's tiles from the lens that sees them all, or from both,
  // blended (dual_blend.hpp).
  const auto* dual = std::get_if<DualFisheye>(&source_);
  auto sample_rect = [&](const Projection& t, const TileRect& rect, const TileMap* tm, unsigned char* out_at,
                         int64_t stride, Worker& wk, const FootprintField* fp = nullptr) {
    if (lenses_.empty()) return sample_from(source_, t, rect, tm, out_at, stride, wk, fp);
    const int side = dual_weights(*dual, t, rotation_, rect, wk.weights);
    if (side >= 0) return sample_from(lenses_[static_cast<size_t>(side)], t, rect, nullptr, out_at, stride, wk, fp);
    const auto pb = static_cast<int64_t>(src.pixel_bytes());
    wk.other.resize(static_cast<size_t>(rect.w * rect.h * pb));
    sample_from(lenses_[0], t, rect, nullptr, out_at, stride, wk, fp);
    sample_from(lenses_[1], t, rect, nullptr, wk.other.data(), rect.w * pb, wk, fp);
    blend_lenses(wk.weights.data(), rect, src.type(), src.channels(), src.alpha_channel(), out_at, stride, wk.other.data(),
                 rect.w * pb);
  };
  // Where x wraps, footprints measure steps across the seam the short way.
  const double wrap = edges.wraps_x() ? static_cast<double>(size_of(source_).width) : 0.0;
  const bool cube_source = std::holds_alternative<Cubemap>(source_);
  // The tile's n x n sub-pixels in the n-times target (in parts of at most kTile x kTile, the
  // samplers' rect; with fp, the tile's footprint field, each through the footprint kernel),
  // then their means.
  auto subpixels = [&](int n, const TileRect& rect, unsigned char* corner, int64_t stride, Worker& wk,
                       const FootprintField* fp) {
    const TileRect sub{rect.x0 * n, rect.y0 * n, rect.w * n, rect.h * n};
    const auto pb = static_cast<int64_t>(src.pixel_bytes()), sub_stride = sub.w * pb;
    wk.sub.resize(static_cast<size_t>(sub_stride * sub.h));
    const Projection& sub_target = sub_targets_[static_cast<size_t>(n)];
    for (int64_t y = 0; y < sub.h; y += kTile)
      for (int64_t x = 0; x < sub.w; x += kTile) {
        const TileRect part{sub.x0 + x, sub.y0 + y, std::min(kTile, sub.w - x), std::min(kTile, sub.h - y)};
        const FootprintField part_fp = fp ? fp->for_rect(rect, part, n) : FootprintField{};
        sample_rect(sub_target, part, nullptr, wk.sub.data() + y * sub_stride + x * pb, sub_stride, wk, fp ? &part_fp : nullptr);
      }
    average_subpixels(src, wk.sub.data(), sub_stride, rect, n, corner, stride);
  };
  std::atomic<int64_t> done{0};
  int64_t last_percent = -1;
  parallel_tasks(n_tiles, threads_, [&](int64_t t, int w) {
    Worker& wk = workers[static_cast<size_t>(w)];
    const TileRect rect = tile(t);
    unsigned char* corner = out.pixel(rect.x0, rect.y0);
    const auto stride = static_cast<int64_t>(out.row_bytes());
    if (antialias_.mode == Antialias::Mode::Supersample) {
      subpixels(antialias_.n, rect, corner, stride, wk, nullptr);
    } else if (antialias_.mode == Antialias::Mode::Auto) {
      // The tile's footprint side: as without antialiasing up to 2 source pixels (or where it is
      // not known); else the footprint kernel, on n x n sub-pixels where the footprint is wider
      // than the kernel reaches (footprint_kernel.hpp).
      FootprintField& fp = wk.field;
      const FootprintSides s = footprint_field(source_, target_, rotation_, rect, wrap, fp);
      const int n = std::clamp(static_cast<int>(std::ceil(s.split / kFootprintReach - 1e-9)), 1, Antialias::kMaxAuto);
      if (s.side <= 2.0) sample_rect(target_, rect, cached(t), corner, stride, wk);
      else if (n == 1) sample_rect(target_, rect, cached(t), corner, stride, wk, &fp);
      else subpixels(n, rect, corner, stride, wk, &fp);
    } else if (pyramid) {
      const TileMap* tm = cached(t);
      SimdGeometry g;
      if (!tm) {
        if (fused(rect, g)) simd_map_tile(g, rect, wk.map, grid_suits(src.type()));  // the fused path's positions
        else map_tile(source_, target_, rotation_, rect, wk.map);
        tm = &wk.map;
      }
      sample_mip_tile(*pyramid, *tm, wrap,
                      [&](int k, const TileMap& m, unsigned char* o, int64_t st) {
                        // The level's rows the taps reach (the edge rules stay within them,
                        // but a cube's, which read neighbouring faces anywhere: all rows).
                        double y0 = HUGE_VAL, y1 = -HUGE_VAL;
                        for (size_t i = 0; i < m.ok.size(); ++i)
                          if (m.ok[i]) y0 = std::min(y0, m.ys[i]), y1 = std::max(y1, m.ys[i]);
                        const int reach = support(interp_) / 2 + 1;
                        if (cube_source) y0 = -HUGE_VAL, y1 = HUGE_VAL;
                        pyramid->build_rows(k, static_cast<int64_t>(std::max(-1e15, std::floor(y0))) - reach,
                                            static_cast<int64_t>(std::min(1e15, std::ceil(y1))) + reach + 1);
                        const Pyramid::Level& l = pyramid->level(k);
                        const Image& im = pyramid->image(k);
                        sample_map(im, l.edges, simd_source(im, l.projection), m, o, st, wk, nullptr);
                      },
                      corner, stride, wk.mip);
    } else {
      sample_rect(target_, rect, cached(t), corner, stride, wk);
    }
    const int64_t d = ++done;
    if (w == 0 && progress && d * 100 / n_tiles != last_percent) {
      last_percent = d * 100 / n_tiles;
      progress(static_cast<double>(d) / static_cast<double>(n_tiles));
    }
  });
  finish_edges(src, source_, target_, rotation_, interp_, edges_, threads_, out);
  if (progress) progress(1.0);
  if (stats) {
    *stats = {n_tiles, 0, 0, 0, 0};
    for (const Worker& wk : workers) {
      stats->fused_tiles += wk.stats.fused_tiles;
      stats->edge_samples += wk.stats.edge_samples;
      stats->interpolated_cells += wk.stats.interpolated_cells;
      stats->exact_cells += wk.stats.exact_cells;
    }
  }
}

Image fast_remap(const Image& src, const Projection& sp, const Projection& dp,
                 const Eigen::Matrix3d& rotation, Interp interp, Engine engine, int threads,
                 EngineStats* stats) {
  return Converter(sp, dp, rotation, interp, engine, threads).run(src, stats);
}

}  // namespace panoproj
