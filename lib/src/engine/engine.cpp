#include "panoproj/convert.hpp"

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "base/parallel.hpp"
#include "base/row_feed.hpp"
#include "engine/tile_sampling.hpp"
#include "engine/tile_strategies.hpp"
#include "geometry/tile_map.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "photometry/source_correction.hpp"
#include "sampling/edge_pass.hpp"
#include "sampling/footprint_kernel.hpp"
#include "sampling/resample.hpp"
#include "simd/geometry.hpp"

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

// How much further than interp's taps auto's footprint kernel reaches (kFootprintTaps / 2 from
// the sample).
int footprint_reach_beyond(Interp interp) { return std::max(0, kFootprintTaps / 2 - support(interp) / 2); }

}  // namespace

// The Converter's state: the projections, options and kept maps (convert.hpp's promises are kept
// here), and the tiles.
struct Converter::Impl {
  Impl(Projection source, Projection target, const Siting& siting, const Eigen::Matrix3d& rotation,
       Interp interp, Engine engine, int threads, Keep keep, Antialias antialias, EdgeFill edges,
       Stereo stereo);
  PixelRect source_footprint() const;
  using Reader = std::function<void(const RowsArrived&)>;
  using Finished = std::function<void(const PixelRect&)>;
  void run(const Image& src, Image& out, EngineStats* stats, const std::function<void(double)>& progress,
           const Reader* read, const Finished& finished = {}) const;
  // run() past the source's correction.
  void run_source(const Image& src, Image& out, EngineStats* stats,
                  const std::function<void(double)>& progress, const Reader* read,
                  const Finished& finished) const;
  // One eye's frame (or a mono conversion's).
  void run_frame(const Image& src, Image& out, EngineStats* stats, const std::function<void(double)>& progress,
                 const Reader* read, const Finished& finished) const;
  // Each target eye from its source eye (or the mono source), on copies or views of the halves.
  void run_stereo(const Image& src, Image& out, EngineStats* stats, const std::function<void(double)>& progress,
                  const Reader* read) const;

  Projection source_, target_;
  Siting siting_;
  Stereo stereo_;
  Antialias antialias_;
  EdgeFill edges_;
  std::vector<Projection> sub_targets_;  // [n]: the target at n times its size (sub-pixels)
  Eigen::Matrix3d rotation_;
  Interp interp_;
  Engine engine_;
  int threads_;
  Keep keep_;
  std::vector<LensSource>
      lenses_;  // a two-lens source's lenses alone (blended per tile), else empty
  std::shared_ptr<const SourceCorrection> correction_;  // applied to each source first, or null
  mutable std::vector<TileMap> cache_;  // one per tile (empty for fused tiles), built on first use
  mutable std::unique_ptr<PlannedTaps[]> planned_;  // one per tile (Keep::MapsAndTaps), with cache_
  mutable std::once_flag cache_once_;   // so that threads sharing a Converter build it once
  mutable std::mutex layout_mutex_;
  mutable std::optional<SimdSource> planned_layout_;  // the source layout planned_ holds taps for
  mutable std::unique_ptr<std::atomic<int64_t>[]> rows_kept_;  // rows_read per tile (-1: not yet), with cache_
  mutable std::unique_ptr<KeptFootprint[]> footprints_;  // one per tile (auto antialiasing), with cache_
  mutable std::unique_ptr<KeptBlend[]> blends_;  // one per tile (a two-lens source), with cache_

  void build_cache() const;
  // planned_ where src's taps may be kept (keeps_taps) and src has the layout of the first
  // such source run, else null.
  PlannedTaps* planned_for(const Image& src, const SourceTaps& taps) const;
  PixelRect tile(int64_t t) const;  // tiles in row-major order
  int64_t tile_count() const;
  // True (and g filled) where the tile's geometry runs in registers fused with the sampling.
  bool fused(const PixelRect& rect, SimdGeometry& g) const;
  // The same from source projection sp (the source, or a lens) through rotation r.
  bool fused(const Projection& sp, const Eigen::Matrix3d& r, const PixelRect& rect,
             SimdGeometry& g) const;
  int parts() const;  // what a tile keeps per: the source, or a two-lens source's lenses
  // The kept map of a tile's part k that has one, else null.
  const TileMap* cached(int64_t t, int k = 0) const;
  // What tile t keeps, its taps in planned (null: none).
  KeptTile kept(int64_t t, PlannedTaps* planned) const;
  // Whether run_reading can start tiles before the whole source is in.
  bool streams() const;
  // Tiles in the order their source rows come in: by the source row of their centre.
  std::vector<int64_t> tiles_by_source_row() const;
  // The frame rows [0, k) tile t reads through strategy s (0 if it has no source); kept per tile
  // with the maps (it runs the tile's geometry).
  int64_t rows_read(const TileStrategy& s, int64_t t, TileScratch& wk) const;
};

Converter::Converter(const ConversionGeometry& g, const ConvertOptions& o, Keep keep)
    : impl_(std::make_unique<Impl>(g.source, g.target, g.siting, g.rotation, o.interp, o.engine,
                                   o.threads, keep, antialias_of(o), o.edges, g.stereo)) {
  impl_->correction_ = g.correction;
}
Converter::~Converter() = default;
Converter::Converter(Converter&&) noexcept = default;
Converter& Converter::operator=(Converter&&) noexcept = default;
const Projection& Converter::source() const { return impl_->source_; }
const Projection& Converter::target() const { return impl_->target_; }
const Antialias& Converter::antialias() const { return impl_->antialias_; }
const Stereo& Converter::stereo() const { return impl_->stereo_; }
Size Converter::source_frame() const { return stereo_frame(size_of(impl_->source_), impl_->stereo_.source); }
Size Converter::target_frame() const { return stereo_frame(size_of(impl_->target_), impl_->stereo_.target); }
PixelRect Converter::source_footprint() const {
  return impl_->source_footprint();
}
void Converter::run(const Image& src, Image& out, EngineStats* stats,
                    const std::function<void(double)>& progress,
                    const std::function<void(const PixelRect&)>& finished) const {
  impl_->run(src, out, stats, progress, nullptr, finished);
}
void Converter::run_reading(const Image& src, Image& out,
                            const std::function<void(const RowsArrived&)>& read, EngineStats* stats,
                            const std::function<void(double)>& progress,
                            const std::function<void(const PixelRect&)>& finished) const {
  impl_->run(src, out, stats, progress, &read, finished);
}

Converter::Impl::Impl(Projection source, Projection target, const Siting& siting,
                      const Eigen::Matrix3d& rotation, Interp interp, Engine engine, int threads,
                      Keep keep, Antialias antialias, EdgeFill edges, Stereo stereo)
    : source_(std::move(source)),
      target_(std::move(target)),
      siting_(siting),
      stereo_(stereo),
      antialias_(antialias),
      edges_(edges),
      rotation_(rotation),
      interp_(interp),
      engine_(engine),
      threads_(threads),
      keep_(keep) {
  if (antialias_.mode != Antialias::Mode::Off && engine_ == Engine::Reference)
    throw Error("antialias " + name_of(antialias_) + " needs the simd or scalar engine (or --antialias off)");
  if (siting_.any() && (engine_ == Engine::Reference || edges_.active()))
    throw Error("sited planes (video chroma) need the simd or scalar engine and no edge fill");
  if (const SamplingFacts f = sampling_facts(source_); f.lensed()) {
    // Each lens alone, blended (or cut) per tile; Keep keeps each lens's maps or taps (not
    // source_'s, which the lenses do not use).
    const std::string name = f.max ? "gopro-max" : "dual-fisheye";
    if (f.lens_feather() > 0 && engine_ == Engine::Reference)
      throw Error(name + ": the feathered blend needs the simd or scalar engine (or feather=0)");
    if (f.lens_feather() > 0 && antialias_.mode == Antialias::Mode::Mip)
      throw Error(name +
                  ": antialias mip does not blend the lenses (use --antialias auto or supersample, "
                  "or feather=0)");
    lenses_ = lens_sources(f, rotation_);
  }
  const int most = antialias_.mode == Antialias::Mode::Supersample ? antialias_.n
                  : antialias_.mode == Antialias::Mode::Auto      ? Antialias::kMaxAuto
                                                                  : 1;
  const Size s = size_of(target_);
  for (int n = 0; n <= most; ++n)
    sub_targets_.push_back(n < 2 ? target_ : rescaled(target_, {s.width * n, s.height * n}));
}

PixelRect Converter::Impl::tile(int64_t t) const {
  const Size size = size_of(target_);
  const int64_t tiles_x = (size.width + kTile - 1) / kTile;
  const int64_t x0 = (t % tiles_x) * kTile, y0 = (t / tiles_x) * kTile;
  return {x0, y0, std::min(x0 + kTile, size.width), std::min(y0 + kTile, size.height)};
}

int64_t Converter::Impl::tile_count() const {
  const Size size = size_of(target_);
  return ((size.width + kTile - 1) / kTile) * ((size.height + kTile - 1) / kTile);
}

bool Converter::Impl::fused(const PixelRect& rect, SimdGeometry& g) const {
  return fused(source_, rotation_, rect, g);
}

bool Converter::Impl::fused(const Projection& sp, const Eigen::Matrix3d& r, const PixelRect& rect,
                            SimdGeometry& g) const {
  return engine_ == Engine::Simd && simd_geometry_for(sp, target_, r, rect, g, siting_) &&
         exact_for(interp_, g);
}

int Converter::Impl::parts() const {
  return lenses_.empty() ? 1 : 2;
}

int kept_bytes_per_pixel(const ConversionGeometry& g) {
  // (A two-lens source's: a map or taps per lens, and lens 0's weight.)
  return sampling_facts(g.source).lensed() ? 2 * static_cast<int>(kCachedMapBytesPerPixel) + 4
                                           : static_cast<int>(kCachedMapBytesPerPixel);
}

void Converter::Impl::build_cache() const {
  // Fused tiles recompute their geometry in registers faster than they could read a map: only the
  // others keep one (an empty TileMap marks a fused tile). A dual fisheye's tiles keep one per
  // lens (parts(): tile t's part k at t * parts() + k).
  const auto n = static_cast<size_t>(tile_count() * parts());
  std::vector<TileMap> maps(n);
  parallel_tasks(tile_count(), threads_, [&](int64_t t, int) {
    SimdGeometry g;
    const PixelRect rect = tile(t);
    for (int k = 0; k < parts(); ++k) {
      const Projection& sp = lenses_.empty() ? source_ : lenses_[static_cast<size_t>(k)].lens;
      const Eigen::Matrix3d& r =
          lenses_.empty() ? rotation_ : lenses_[static_cast<size_t>(k)].rotation;
      if (!fused(sp, r, rect, g))
        map_tile(sp, target_, r, rect, maps[static_cast<size_t>(t * parts() + k)],
                 interp_ == Interp::Nearest, siting_);
    }
  });
  cache_ = std::move(maps);
  static_assert(PlannedTaps::kBytesPerPixel <= kCachedMapBytesPerPixel);  // a tile keeps its map or its taps
  if (keep_ == Keep::MapsAndTaps && engine_ == Engine::Simd)
    planned_ = std::make_unique<PlannedTaps[]>(n);
  rows_kept_ = std::make_unique<std::atomic<int64_t>[]>(static_cast<size_t>(tile_count()));
  for (int64_t t = 0; t < tile_count(); ++t) rows_kept_[static_cast<size_t>(t)].store(-1, std::memory_order_relaxed);
  if (antialias_.mode == Antialias::Mode::Auto) footprints_ = std::make_unique<KeptFootprint[]>(static_cast<size_t>(tile_count()));
  if (!lenses_.empty()) blends_ = std::make_unique<KeptBlend[]>(static_cast<size_t>(tile_count()));
}

PlannedTaps* Converter::Impl::planned_for(const Image& src, const SourceTaps& taps) const {
  if (!planned_) return nullptr;
  const SimdSource s = simd_source(src, taps);
  if (!keeps_taps(s)) return nullptr;
  const std::lock_guard<std::mutex> lock(layout_mutex_);
  if (!planned_layout_) planned_layout_ = s;
  return same_layout(*planned_layout_, s) ? planned_.get() : nullptr;
}

const TileMap* Converter::Impl::cached(int64_t t, int k) const {
  if (keep_ == Keep::Nothing) return nullptr;
  const TileMap& tm = cache_[static_cast<size_t>(t * parts() + k)];
  return tm.rect.width() > 0 ? &tm : nullptr;
}

KeptTile Converter::Impl::kept(int64_t t, PlannedTaps* planned) const {
  KeptTile k;
  k.footprint = footprints_ ? &footprints_[t] : nullptr;
  k.blend = blends_ ? &blends_[t] : nullptr;
  for (int p = 0; p < parts(); ++p) {
    k.maps[p] = cached(t, p);
    k.taps[p] = planned ? &planned[t * parts() + p] : nullptr;
  }
  return k;
}

PixelRect Converter::Impl::source_footprint() const {
  const Size frame = size_of(source_);
  const PixelRect all{0, 0, frame.width, frame.height};
  if (stereo_.any()) {  // both eyes' frame, read whole
    const Size both = stereo_frame(frame, stereo_.source);
    return {0, 0, both.width, both.height};
  }
  // A cube source is read whole, a dual fisheye's too (its blend reads both lenses, beyond either
  // one's map); a target showing the whole sphere needs no mapping to know.
  if (sampling_facts(source_).has_cells() || shows_whole_sphere(target_)) return all;
  // Bounding box of the valid positions: over the kept maps, the fused tiles' vector geometry
  // (reduced in registers, nothing stored), or maps made one tile at a time.
  if (keep_ != Keep::Nothing) std::call_once(cache_once_, [this] { build_cache(); });
  const int64_t n_tiles = tile_count();
  const int n_workers = workers_for(n_tiles, threads_);
  std::vector<std::array<double, 4>> box(static_cast<size_t>(n_workers), {HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL});
  std::vector<double> spread(static_cast<size_t>(n_workers), 0.0);  // largest source px per output px
  std::vector<TileMap> local(static_cast<size_t>(n_workers));
  parallel_tasks(n_tiles, threads_, [&](int64_t t, int w) {
    std::array<double, 4> b{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};  // this tile's
    const PixelRect rect = tile(t);
    widen_to_positions(source_, rotation_, target_, rect, cached(t), engine_ == Engine::Simd,
                       local[static_cast<size_t>(w)], b, siting_);
    if (b[0] > b[2]) return;
    auto& all = box[static_cast<size_t>(w)];
    all = {std::min(all[0], b[0]), std::min(all[1], b[1]), std::max(all[2], b[2]), std::max(all[3], b[3])};
    // The tile's extent over its size bounds its mean step (antialiasing's reach below).
    const double s =
        std::max((b[2] - b[0]) / static_cast<double>(std::max<int64_t>(rect.width() - 1, 1)),
                 (b[3] - b[1]) / static_cast<double>(std::max<int64_t>(rect.height() - 1, 1)));
    spread[static_cast<size_t>(w)] = std::max(spread[static_cast<size_t>(w)], s);
  });
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (const auto& b : box) x0 = std::min(x0, b[0]), y0 = std::min(y0, b[1]), x1 = std::max(x1, b[2]), y1 = std::max(y1, b[3]);
  if (x0 > x1) return {0, 0, 0, 0};  // no pixel has a source
  const int n = support(interp_);
  // Taps (first_tap is monotonic), one pixel of margin for the 1/256 px map tolerance.
  PixelRect r{first_tap(interp_, x0) - 1, first_tap(interp_, y0) - 1,
              first_tap(interp_, x1) + n + 1, first_tap(interp_, y1) + n + 1};
  if (antialias_.mode != Antialias::Mode::Off) {
    // rho: the largest step from one output pixel to the next, in source pixels. Mip level k
    // (2^k <= rho / 2) reaches its taps' n / 2 level pixels of 2^k source px, and one more for a
    // block cut by the window's edge (which averages only what it holds). Sub-pixels reach half
    // an output pixel further (rho / 2 source px), and auto's footprint kernel its own taps
    // (kFootprintTaps / 2 from the sample) where they reach further than interp_'s.
    const double rho = std::max(1.0, *std::max_element(spread.begin(), spread.end()));
    int64_t m = static_cast<int64_t>(std::ceil(rho / 2)) + 1;
    if (antialias_.mode == Antialias::Mode::Auto) m += footprint_reach_beyond(interp_);
    if (antialias_.mode == Antialias::Mode::Mip) m = static_cast<int64_t>(std::exp2(std::ceil(std::log2(rho)))) * (n / 2 + 2);
    r = {r.x0 - m, r.y0 - m, r.x1 + m, r.y1 + m};
  }
  // Where taps leave the image's pixels, the tap rules read elsewhere: wrap (full width), pole
  // crossing (full width, rows from the pole), clamp (the edge row or column, inside the clamp).
  const SourceTaps taps(source_);
  if (r.x0 < taps.col0() || r.x1 > taps.col1()) r.x0 = 0, r.x1 = frame.width;
  if (r.y0 < taps.row0()) r.y0 = 0, r.x0 = 0, r.x1 = frame.width;
  if (r.y1 > taps.row1()) r.y1 = frame.height, r.x0 = 0, r.x1 = frame.width;
  return r;
}

bool Converter::Impl::streams() const {
  // Mip builds levels over the rows its tiles reach; a cube or dual fisheye's taps cross into
  // other faces or lenses (source_footprint reads them whole).
  return engine_ != Engine::Reference && antialias_.mode != Antialias::Mode::Mip &&
         !sampling_facts(source_).has_cells();
}

std::vector<int64_t> Converter::Impl::tiles_by_source_row() const {
  const int64_t n = tile_count();
  std::vector<double> row(static_cast<size_t>(n), 0.0);  // no source at the centre: first
  for (int64_t t = 0; t < n; ++t) {
    const PixelRect r = tile(t);
    double x = 0, y = 0;
    if (source_pixel(source_, target_, rotation_,
                     static_cast<double>(r.x0) + 0.5 * static_cast<double>(r.width()),
                     static_cast<double>(r.y0) + 0.5 * static_cast<double>(r.height()), x, y))
      row[static_cast<size_t>(t)] = y;
  }
  std::vector<int64_t> order(static_cast<size_t>(n));
  for (int64_t t = 0; t < n; ++t) order[static_cast<size_t>(t)] = t;
  std::stable_sort(order.begin(), order.end(),
                   [&](int64_t a, int64_t b) { return row[static_cast<size_t>(a)] < row[static_cast<size_t>(b)]; });
  return order;
}

int64_t Converter::Impl::rows_read(const TileStrategy& s, int64_t t, TileScratch& wk) const {
  // (Kept: every run has the same strategy, the Converter's antialiasing.)
  std::atomic<int64_t>* kept = rows_kept_ ? &rows_kept_[static_cast<size_t>(t)] : nullptr;
  if (kept && kept->load(std::memory_order_relaxed) >= 0) return kept->load(std::memory_order_relaxed);
  const int64_t all = size_of(source_).height;
  std::array<double, 4> b{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  int64_t k = all;  // where the strategy cannot tell
  if (s.widen_to_samples(tile(t), wk, b)) {
    // None (no sample), else the taps below the lowest sample (one row more for the 1/256 px map
    // tolerance) and the footprint kernel's reach beyond them.
    k = b[1] > b[3] ? 0 : first_tap(interp_, b[3]) + support(interp_) + 1;
    if (k > 0 && antialias_.mode == Antialias::Mode::Auto) k += footprint_reach_beyond(interp_);
    k = std::min(k, all);
  }
  if (kept) kept->store(k, std::memory_order_relaxed);
  return k;
}

Image Converter::run(const Image& src, EngineStats* stats,
                     const std::function<void(double)>& progress) const {
  Image out;
  run(src, out, stats, progress);
  return out;
}

void Converter::Impl::run(const Image& src, Image& out, EngineStats* stats,
                          const std::function<void(double)>& progress, const Reader* read,
                          const Finished& finished) const {
  if (correction_ && !correction_->identity(src.type())) {
    // The whole window first, corrected into a copy (the correction is per source pixel).
    if (read) (*read)([](int64_t) {});
    Image corrected;
    correction_->apply(src, corrected, threads_);
    return run_source(corrected, out, stats, progress, nullptr, finished);
  }
  run_source(src, out, stats, progress, read, finished);
}

void Converter::Impl::run_source(const Image& src, Image& out, EngineStats* stats,
                                 const std::function<void(double)>& progress, const Reader* read,
                                 const Finished& finished) const {
  if (stereo_.any()) return run_stereo(src, out, stats, progress, read);
  run_frame(src, out, stats, progress, read, finished);
}

namespace {

// Eye e of a stereo frame (whole in memory): a view of its rows (tb), or a copy of its half (sbs).
Image eye_of(const Image& frame, Size eye, StereoLayout layout, int e) {
  const auto o = stereo_origin(eye, layout, e);
  if (layout == StereoLayout::TopBottom)
    return Image::view(const_cast<unsigned char*>(frame.row(o[1])), eye, frame.channels(), frame.type(),
                       frame.alpha_channel());
  Image copy(eye, frame.channels(), frame.type(), frame.alpha_channel(), Image::Unfilled{});
  for (int64_t y = 0; y < eye.height; ++y) std::memcpy(copy.row(y), frame.pixel(o[0], y), copy.row_bytes());
  return copy;
}

}  // namespace

void Converter::Impl::run_stereo(const Image& src, Image& out, EngineStats* stats,
                                 const std::function<void(double)>& progress, const Reader* read) const {
  const Size se = size_of(source_), te = size_of(target_);
  const Size sf = stereo_frame(se, stereo_.source), tf = stereo_frame(te, stereo_.target);
  if (src.frame_size() != sf)
    throw Error("image size " + size_text(src.frame_size()) + " does not match the source's " + size_text(sf) +
                (stereo_.source == StereoLayout::Mono ? "" : " (two eyes of " + size_text(se) + ")"));
  if (read) (*read)([](int64_t) {});  // each eye reads its own half: the whole frame first
  if (src.size() != sf) throw InternalError("a stereo source is read whole");
  if (out.size() != tf || out.channels() != src.channels() || out.type() != src.type() ||
      out.alpha_channel() != src.alpha_channel())
    out = Image(tf, src.channels(), src.type(), src.alpha_channel(), Image::Unfilled{});
  const int eyes = stereo_.target == StereoLayout::Mono ? 1 : 2;
  EngineStats sum;
  for (int e = 0; e < eyes; ++e) {
    const int from = stereo_.target == StereoLayout::Mono ? stereo_.eye : e;
    Image half;
    if (stereo_.source != StereoLayout::Mono) half = eye_of(src, se, stereo_.source, from);
    const Image& in = stereo_.source == StereoLayout::Mono ? src : half;
    // A tb or mono target's eye is a view of out's rows (unless an engine hands back its own
    // image); an sbs eye is made apart and copied in.
    const auto o = stereo_origin(te, stereo_.target, e);
    unsigned char* at = stereo_.target != StereoLayout::SideBySide ? out.pixel(o[0], o[1]) : nullptr;
    Image eye = at ? Image::view(at, te, out.channels(), out.type(), out.alpha_channel()) : Image();
    EngineStats one;
    run_frame(in, eye, &one, progress ? [&](double f) { progress((e + f) / eyes); } : std::function<void(double)>{},
              nullptr, {});
    if (eye.data() != at)
      for (int64_t y = 0; y < te.height; ++y) std::memcpy(out.pixel(o[0], o[1] + y), eye.row(y), eye.row_bytes());
    sum += one;
  }
  if (stats) *stats = sum;
}

void Converter::Impl::run_frame(const Image& src, Image& out, EngineStats* stats,
                                const std::function<void(double)>& progress, const Reader* read,
                                const Finished& finished) const {
  const Size expected = size_of(source_);
  if (src.frame_size() != expected)
    throw Error("image size " + std::to_string(src.frame_size().width) + "x" + std::to_string(src.frame_size().height) +
                " does not match the source projection's " + std::to_string(expected.width) + "x" +
                std::to_string(expected.height));
  if (read && engine_ == Engine::Reference) (*read)({}), read = nullptr;
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
  const int64_t n_tiles = tile_count();
  if (keep_ != Keep::Nothing) std::call_once(cache_once_, [this] { build_cache(); });
  const TileSampling sampling(src, source_, lenses_, rotation_, interp_, engine_ == Engine::Simd,
                              siting_, size_of(target_));
  PlannedTaps* const planned = planned_for(src, sampling.taps());
  // Where x wraps, footprints measure steps across the seam the short way.
  const double wrap = sampling.taps().wrap_period();
  const auto strategy = tile_strategy(antialias_, {sampling, source_, target_, sub_targets_, rotation_, wrap});
  // While src is read (task 0), tiles go in the order their rows come in, each once they are.
  const int64_t first = read ? 1 : 0;
  const bool stream = read && streams();
  const std::vector<int64_t> order = stream ? tiles_by_source_row() : std::vector<int64_t>{};
  RowFeed feed;
  const int64_t all_rows = src.origin_y() + src.height();
  std::vector<TileScratch> workers(static_cast<size_t>(workers_for(n_tiles + first, threads_)));
  std::atomic<int64_t> done{0};
  int64_t last_percent = -1;
  parallel_tasks(n_tiles + first, threads_, [&](int64_t task, int w) {
    if (task < first) {
      try {
        (*read)(stream ? RowsArrived([&](int64_t k) { feed.arrived(src.origin_y() + k); }) : RowsArrived{});
      } catch (...) {
        feed.close();  // the tiles waiting stop; the error ends the run
        throw;
      }
      feed.arrived(all_rows);
      return;
    }
    const int64_t t = stream ? order[static_cast<size_t>(task - first)] : task - first;
    const PixelRect rect = tile(t);
    // (A tile waits for the rows its positions reach; they come in the order taken.)
    if (read && !feed.has(all_rows) &&
        !feed.wait(stream ? std::min(all_rows, rows_read(*strategy, t, workers[static_cast<size_t>(w)])) : all_rows))
      return;  // the read failed: its error ends the run
    strategy->tile(rect, kept(t, planned), out.pixel(rect.x0, rect.y0),
                   static_cast<int64_t>(out.row_bytes()), workers[static_cast<size_t>(w)]);
    if (finished && !edges_.active())
      finished({rect.x0, rect.y0, rect.x0 + rect.width(), rect.y0 + rect.height()});
    const int64_t d = ++done;
    if (w == 0 && progress && d * 100 / n_tiles != last_percent) {
      last_percent = d * 100 / n_tiles;
      progress(static_cast<double>(d) / static_cast<double>(n_tiles));
    }
  });
  finish_edges(src, source_, target_, rotation_, interp_, edges_, threads_, out);
  if (progress) progress(1.0);
  if (stats) {
    *stats = {};
    for (const TileScratch& wk : workers) *stats += wk.stats;  // (workers count no tiles)
    stats->tiles = n_tiles;
  }
}

}  // namespace panoproj
