#include "panoproj/engine.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <thread>
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

struct Footprint {
  int64_t x0, y0, x1, y1;  // taps span [x0, x1) x [y0, y1)
};

// Taps of all valid samples of a tile, if they lie in one rectangle the SIMD kernel may read
// without edge rules (the frame, or the samples' single cube face) and 32-bit offsets reach.
bool interior_footprint(const TileMap& tm, const Image& src, const Projection& sp, Interp interp,
                        Footprint& fp) {
  const int k = support(interp);
  Footprint lim{src.origin_x(), src.origin_y(), src.origin_x() + src.width(), src.origin_y() + src.height()};
  const auto* cube = std::get_if<Cubemap>(&sp);
  int face = -2;
  fp = {std::numeric_limits<int64_t>::max(), std::numeric_limits<int64_t>::max(),
        std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::min()};
  bool any = false;
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (size_t i = 0; i < tm.ok.size(); ++i) {
    if (!tm.ok[i]) continue;
    any = true;
    if (cube) {
      const int f = cube->face_at(tm.xs[i], tm.ys[i]);
      if (face == -2) {
        face = f;
        const auto o = cube->face_origin(f);
        lim = {std::max(lim.x0, o[0]), std::max(lim.y0, o[1]), std::min(lim.x1, o[0] + cube->face_size()),
               std::min(lim.y1, o[1] + cube->face_size())};
      } else if (f != face) {
        return false;
      }
    }
    x0 = std::min(x0, tm.xs[i]), x1 = std::max(x1, tm.xs[i]);
    y0 = std::min(y0, tm.ys[i]), y1 = std::max(y1, tm.ys[i]);
  }
  // Taps are monotonic in the position: the extremes bound them all.
  if (any) fp = {first_tap(interp, x0), first_tap(interp, y0), first_tap(interp, x1) + k,
                 first_tap(interp, y1) + k};
  if (!any) return false;
  if (fp.x0 < lim.x0 || fp.y0 < lim.y0 || fp.x1 > lim.x1 || fp.y1 > lim.y1) return false;
  const double span = static_cast<double>(fp.y1 - fp.y0) * static_cast<double>(src.row_bytes()) +
                      static_cast<double>(fp.x1 - fp.x0) * static_cast<double>(src.pixel_bytes());
  return span < 2e9;  // int32 byte offsets
}

}  // namespace

Converter::Converter(Projection source, Projection target, const Eigen::Matrix3d& rotation,
                     Interp interp, Engine engine, int threads, bool cache_map)
    : source_(std::move(source)), target_(std::move(target)), rotation_(rotation), interp_(interp),
      engine_(engine), threads_(threads), cache_map_(cache_map) {}

void Converter::map(const TileRect& rect, TileMap& out) const {
  SimdGeometry g;
  if (engine_ == Engine::Simd && simd_geometry_for(source_, target_, rotation_, rect, g)) {
    simd_map_tile(g, rect, out);
  } else {
    map_tile(source_, target_, rotation_, rect, out);
  }
}

void Converter::build_cache() const {
  const Size size = size_of(target_);
  const int64_t tiles_x = (size.width + kTile - 1) / kTile, tiles_y = (size.height + kTile - 1) / kTile;
  const int64_t n_tiles = tiles_x * tiles_y;
  std::vector<TileMap> maps(static_cast<size_t>(n_tiles));
  std::atomic<int64_t> next{0};
  auto build = [&] {
    for (int64_t t; (t = next.fetch_add(1)) < n_tiles;) {
      const TileRect rect{(t % tiles_x) * kTile, (t / tiles_x) * kTile,
                          std::min(kTile, size.width - (t % tiles_x) * kTile),
                          std::min(kTile, size.height - (t / tiles_x) * kTile)};
      map(rect, maps[static_cast<size_t>(t)]);
    }
  };
  const int n_threads = static_cast<int>(std::min<int64_t>(resolve_threads(threads_), n_tiles));
  std::vector<std::thread> pool;
  for (int i = 1; i < n_threads; ++i) pool.emplace_back(build);
  build();
  for (auto& th : pool) th.join();
  cache_ = std::move(maps);
}

Converter::Region Converter::source_footprint() const {
  const Size frame = size_of(source_);
  const Region all{0, 0, frame.width, frame.height};
  if (std::holds_alternative<Cubemap>(source_)) return all;
  // Bounding box of the valid positions: from the kept tile maps, or (without a cache) from tile
  // maps made one at a time and dropped, so memory stays at one tile per thread.
  std::mutex m;
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  auto extend = [&](const TileMap& tm) {
    double a = HUGE_VAL, b = HUGE_VAL, c = -HUGE_VAL, d = -HUGE_VAL;
    for (size_t i = 0; i < tm.ok.size(); ++i) {
      if (!tm.ok[i]) continue;
      a = std::min(a, tm.xs[i]), c = std::max(c, tm.xs[i]);
      b = std::min(b, tm.ys[i]), d = std::max(d, tm.ys[i]);
    }
    const std::lock_guard<std::mutex> lock(m);
    x0 = std::min(x0, a), x1 = std::max(x1, c), y0 = std::min(y0, b), y1 = std::max(y1, d);
  };
  if (cache_map_) {
    if (cache_.empty()) build_cache();
    for (const TileMap& tm : cache_) extend(tm);
  } else {
    const Size size = size_of(target_);
    const int64_t tiles_x = (size.width + kTile - 1) / kTile, tiles_y = (size.height + kTile - 1) / kTile;
    std::atomic<int64_t> next{0};
    auto scan = [&] {
      TileMap tm;
      for (int64_t t; (t = next.fetch_add(1)) < tiles_x * tiles_y;) {
        map({(t % tiles_x) * kTile, (t / tiles_x) * kTile, std::min(kTile, size.width - (t % tiles_x) * kTile),
             std::min(kTile, size.height - (t / tiles_x) * kTile)},
            tm);
        extend(tm);
      }
    };
    const int n_threads = static_cast<int>(std::min<int64_t>(resolve_threads(threads_), tiles_x * tiles_y));
    std::vector<std::thread> pool;
    for (int i = 1; i < n_threads; ++i) pool.emplace_back(scan);
    scan();
    for (auto& th : pool) th.join();
  }
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
  const Size expected = size_of(source_);
  if (src.frame_size() != expected)
    throw Error("image size " + std::to_string(src.frame_size().width) + "x" + std::to_string(src.frame_size().height) +
                " does not match the source projection's " + std::to_string(expected.width) + "x" +
                std::to_string(expected.height));
  if (engine_ == Engine::Reference) {
    Image out = remap(src, source_, target_, rotation_, {interp_, threads_});
    if (progress) progress(1.0);
    return out;
  }
  const Size size = size_of(target_);
  Image out(size, src.channels(), src.type(), src.alpha_channel());
  const SourceEdges edges(source_);
  const int64_t tiles_x = (size.width + kTile - 1) / kTile, tiles_y = (size.height + kTile - 1) / kTile;
  const int64_t n_tiles = tiles_x * tiles_y;
  const bool use_simd = engine_ == Engine::Simd && interp_ != Interp::Nearest;
  auto rect_of = [&](int64_t t) {
    return TileRect{(t % tiles_x) * kTile, (t / tiles_x) * kTile,
                    std::min(kTile, size.width - (t % tiles_x) * kTile),
                    std::min(kTile, size.height - (t / tiles_x) * kTile)};
  };
  const int n_threads = static_cast<int>(std::min<int64_t>(resolve_threads(threads_), n_tiles));
  if (cache_map_ && cache_.empty()) build_cache();
  std::atomic<int64_t> next{0}, done{0}, simd_tiles{0}, interp_cells{0}, exact_cells{0};
  auto worker = [&](bool reports) {
    TileMap local;
    std::vector<float> fx(kTile + kMaxSimdLanes), fy(kTile + kMaxSimdLanes);
    int64_t last_percent = -1;
    for (int64_t t; (t = next.fetch_add(1)) < n_tiles;) {
      const TileRect rect = rect_of(t);
      const TileMap* tile_map = &local;
      if (cache_map_) {
        tile_map = &cache_[static_cast<size_t>(t)];
      } else {
        map(rect, local);
      }
      const TileMap& tm = *tile_map;
      interp_cells += tm.interpolated_cells;
      exact_cells += tm.exact_cells;
      Footprint fp;
      if (use_simd && interior_footprint(tm, src, source_, interp_, fp)) {
        ++simd_tiles;
        // Positions relative to the footprint's corner, in float; invalid and padding lanes get
        // a valid sample's position so that their taps stay inside too.
        size_t first = 0;
        while (!tm.ok[first]) ++first;
        const float safe_x = static_cast<float>(tm.xs[first] - static_cast<double>(fp.x0));
        const float safe_y = static_cast<float>(tm.ys[first] - static_cast<double>(fp.y0));
        const SimdSource s{src.at(fp.x0, fp.y0), static_cast<int64_t>(src.row_bytes()),
                           src.channels(), src.alpha_channel(), src.type()};
        const double ox = static_cast<double>(fp.x0), oy = static_cast<double>(fp.y0);
        std::fill(fx.begin() + rect.w, fx.end(), safe_x);
        std::fill(fy.begin() + rect.w, fy.end(), safe_y);
        for (int64_t j = 0; j < rect.h; ++j) {
          const double* xs = tm.xs.data() + j * rect.w;
          const double* ys = tm.ys.data() + j * rect.w;
          const uint8_t* ok = tm.ok.data() + j * rect.w;
          for (int64_t i = 0; i < rect.w; ++i) {
            fx[i] = ok[i] ? static_cast<float>(xs[i] - ox) : safe_x;
            fy[i] = ok[i] ? static_cast<float>(ys[i] - oy) : safe_y;
          }
          simd_sample(s, interp_, fx.data(), fy.data(), ok, rect.w, out.pixel(rect.x0, rect.y0 + j));
        }
      } else {
        for (int64_t j = 0; j < rect.h; ++j) {
          const size_t k = static_cast<size_t>(j * rect.w);
          sample_reference(src, edges, interp_, tm.xs.data() + k, tm.ys.data() + k, tm.ok.data() + k,
                           rect.w, out.pixel(rect.x0, rect.y0 + j));
        }
      }
      const int64_t d = ++done;
      if (reports && progress && d * 100 / n_tiles != last_percent) {
        last_percent = d * 100 / n_tiles;
        progress(static_cast<double>(d) / static_cast<double>(n_tiles));
      }
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < n_threads; ++i) pool.emplace_back(worker, false);
  worker(true);
  for (auto& th : pool) th.join();
  if (progress) progress(1.0);
  if (stats) *stats = {n_tiles, simd_tiles.load(), interp_cells.load(), exact_cells.load()};
  return out;
}

Image fast_remap(const Image& src, const Projection& sp, const Projection& dp,
                 const Eigen::Matrix3d& rotation, Interp interp, Engine engine, int threads,
                 EngineStats* stats) {
  return Converter(sp, dp, rotation, interp, engine, threads).run(src, stats);
}

}  // namespace panoproj
