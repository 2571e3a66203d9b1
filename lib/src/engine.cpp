#include "panoproj/engine.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <array>
#include <string>
#include <vector>

#include "panoproj/error.hpp"
#include "panoproj/parallel.hpp"
#include "panoproj/resample.hpp"
#include "panoproj/source_edges.hpp"
#include "panoproj/tile_map.hpp"
#include "reference_sampler.hpp"
#include "simd_geometry.hpp"
#include "simd_sampler.hpp"

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
  return {src.data(), static_cast<int64_t>(src.row_bytes()), src.channels(), src.alpha_channel(), src.type(),
          src.origin_x(), src.origin_y(), src.origin_x() + src.width(), src.origin_y() + src.height(), cw, ch};
}

}  // namespace

Converter::Converter(Projection source, Projection target, const Eigen::Matrix3d& rotation,
                     Interp interp, Engine engine, int threads, bool cache_map)
    : source_(std::move(source)), target_(std::move(target)), rotation_(rotation), interp_(interp),
      engine_(engine), threads_(threads), cache_map_(cache_map) {}

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

bool Converter::fused(const TileRect& rect, SimdGeometry& g) const {
  return engine_ == Engine::Simd && simd_geometry_for(source_, target_, rotation_, rect, g);
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
  // A cube source is read whole; a target showing the whole sphere needs no mapping to know.
  if (std::holds_alternative<Cubemap>(source_) || shows_whole_sphere(target_)) return all;
  // Bounding box of the valid positions: over the kept maps, the fused tiles' vector geometry
  // (reduced in registers, nothing stored), or maps made one tile at a time.
  if (cache_map_) std::call_once(cache_once_, [this] { build_cache(); });
  const int64_t n_tiles = tile_count();
  const int n_workers = workers_for(n_tiles, threads_);
  std::vector<std::array<double, 4>> box(static_cast<size_t>(n_workers), {HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL});
  std::vector<TileMap> local(static_cast<size_t>(n_workers));
  parallel_tasks(n_tiles, threads_, [&](int64_t t, int w) {
    auto& b = box[static_cast<size_t>(w)];
    const TileRect rect = tile(t);
    const TileMap* tm = cached(t);
    SimdGeometry g;
    if (!tm && fused(rect, g)) return simd_tile_bounds(g, rect, b);
    if (!tm) map_tile(source_, target_, rotation_, rect, local[static_cast<size_t>(w)]), tm = &local[static_cast<size_t>(w)];
    for (size_t i = 0; i < tm->ok.size(); ++i) {
      if (!tm->ok[i]) continue;
      b[0] = std::min(b[0], tm->xs[i]), b[2] = std::max(b[2], tm->xs[i]);
      b[1] = std::min(b[1], tm->ys[i]), b[3] = std::max(b[3], tm->ys[i]);
    }
  });
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (const auto& b : box) x0 = std::min(x0, b[0]), y0 = std::min(y0, b[1]), x1 = std::max(x1, b[2]), y1 = std::max(y1, b[3]);
  if (x0 > x1) return {0, 0, 0, 0};  // no pixel has a source
  const int n = support(interp_);
  // Taps (first_tap is monotonic), one pixel of margin for the 1/256 px map tolerance.
  Region r{first_tap(interp_, x0) - 1, first_tap(interp_, y0) - 1, first_tap(interp_, x1) + n + 1,
           first_tap(interp_, y1) + n + 1};
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
  struct Worker {
    TileMap map;
    SimdMisses misses;
    EngineStats stats;
  };
  std::vector<Worker> workers(static_cast<size_t>(n_workers));
  std::atomic<int64_t> done{0};
  int64_t last_percent = -1;
  parallel_tasks(n_tiles, threads_, [&](int64_t t, int w) {
    Worker& wk = workers[static_cast<size_t>(w)];
    const TileRect rect = tile(t);
    SimdGeometry g;
    const TileMap* tm = cached(t);
    const bool in_registers = !tm && fused(rect, g);
    if (!tm && !in_registers) map_tile(source_, target_, rotation_, rect, wk.map), tm = &wk.map;
    if (tm) wk.stats.interpolated_cells += tm->interpolated_cells, wk.stats.exact_cells += tm->exact_cells;
    wk.stats.fused_tiles += in_registers;
    if (!use_simd) {
      for (int64_t j = 0; j < rect.h; ++j) {
        const size_t k = static_cast<size_t>(j * rect.w);
        sample_reference(src, edges, interp_, tm->xs.data() + k, tm->ys.data() + k, tm->ok.data() + k, rect.w,
                         out.pixel(rect.x0, rect.y0 + j));
      }
    } else {
      SimdMisses& m = wk.misses;
      m.clear();
      unsigned char* corner = out.pixel(rect.x0, rect.y0);
      const auto stride = static_cast<int64_t>(out.row_bytes());
      if (in_registers) {
        simd_convert(g, rect, simd_src, interp_, corner, stride, m);
      } else {
        simd_sample(simd_src, interp_, *tm, corner, stride, m);
      }
      // Samples whose taps cross a seam, pole, face edge or the window: the edge rules.
      const uint8_t one = 1;
      for (size_t q = 0; q < m.index.size(); ++q)
        sample_reference(src, edges, interp_, &m.xs[q], &m.ys[q], &one, 1,
                         out.pixel(rect.x0 + m.index[q] % rect.w, rect.y0 + m.index[q] / rect.w));
      wk.stats.edge_samples += static_cast<int64_t>(m.index.size());
    }
    const int64_t d = ++done;
    if (w == 0 && progress && d * 100 / n_tiles != last_percent) {
      last_percent = d * 100 / n_tiles;
      progress(static_cast<double>(d) / static_cast<double>(n_tiles));
    }
  });
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
