#pragma once
// The fast engine: output tiles of kTile x kTile pixels over a thread pool. Per tile:
//   - common pairs (lib/src/simd/geometry.hpp): each vector of output pixels computes its source
//     positions in double SIMD registers and samples them at once (fused, no map);
//   - other pairs: a tile map (tile_map.hpp, cubic interpolation of exact nodes, within 1/256 px),
//     then the same SIMD sampling from the map.
// The SIMD kernels (simd_sampler.hpp) take every sample whose taps stay inside one cube face or
// the frame; the rest (seams, poles, face edges) get the reference sampler's edge rules (wrap,
// pole crossing, cube neighbours, clamp). The scalar engine samples everything with the reference.
// Tiles are fixed by the image size, not the thread count, so any number of threads gives the
// same bytes.
#include <Eigen/Core>
#include <functional>
#include <mutex>
#include <vector>

#include "panoproj/antialias.hpp"
#include "panoproj/edge_fill.hpp"
#include "panoproj/image.hpp"
#include "panoproj/interpolator.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/tile_map.hpp"

namespace panoproj {

struct SimdGeometry;  // internal (lib/src/simd/geometry.hpp)

enum class Engine {
  Simd,       // tiles; fused SIMD geometry for the common pairs (else interpolated coordinates);
              // SIMD sampling where no edge is touched (default)
  Scalar,     // the same tiles, interpolated coordinates, reference sampling everywhere
  Reference,  // exact per-pixel double geometry and sampling (resample.hpp)
};

Engine parse_engine(std::string_view name);  // throws panoproj::Error
const char* name_of(Engine e);

// Bytes a cached map takes per output pixel (double x, y and a validity byte).
inline constexpr int64_t kCachedMapBytesPerPixel = 2 * sizeof(double) + 1;

struct EngineStats {
  int64_t tiles = 0;
  int64_t fused_tiles = 0;   // geometry in registers, no map (simd engine, the common pairs)
  int64_t edge_samples = 0;  // samples the SIMD kernels left to the reference's edge rules
  int64_t interpolated_cells = 0, exact_cells = 0;  // tile_map.hpp cells of the other tiles
};

// One geometry (projections, rotation, kernel), applied to any number of images of the source's
// size. With cache_map, the tile maps of the tiles that are not fused (kCachedMapBytesPerPixel
// per output pixel at most) are built once, on the first run, and reused: batches and video
// frames pay for that geometry once. Fused tiles recompute theirs: in registers it costs less
// than reading a stored map. run() may be called from several threads at once. antialias
// (antialias.hpp; off by default here, auto in the command and the Python module) needs the
// simd or scalar engine; mip builds the source's levels on each run, as far as they are read.
class Converter {
 public:
  // edges: what pixels without a source, or on the field's edge, get (edge_fill.hpp; by default
  // 0, decided at pixel centres).
  Converter(Projection source, Projection target, const Eigen::Matrix3d& rotation, Interp interp,
            Engine engine, int threads, bool cache_map = false, Antialias antialias = {}, EdgeFill edges = {});

  // Throws panoproj::Error if src's size is not the source projection's. progress, if given,
  // is called from the calling thread with the fraction of tiles done.
  Image run(const Image& src, EngineStats* stats = nullptr,
            const std::function<void(double)>& progress = {}) const;
  // The same into out, reusing its buffer when it already has the output's size and layout
  // (video frames, batches: no new memory per frame).
  void run(const Image& src, Image& out, EngineStats* stats = nullptr,
           const std::function<void(double)>& progress = {}) const;

  // The source pixels [x0, x1) x [y0, y1) that run() reads (with the kernel's taps and the
  // edge rules: a seam or pole crossing widens it to the full width; cubemap sources and targets
  // showing the whole sphere (cubemap, full equirect, the world maps) read all). Read
  // only this part of a large source. With cache_map it builds and keeps the tile maps (run()
  // then reuses them); without, it maps tile by tile and keeps nothing.
  struct Region {
    int64_t x0, y0, x1, y1;
  };
  Region source_footprint() const;

  const Projection& source() const { return source_; }
  const Projection& target() const { return target_; }
  const Antialias& antialias() const { return antialias_; }

 private:
  Projection source_, target_;
  Antialias antialias_;
  EdgeFill edges_;
  std::vector<Projection> sub_targets_;  // [n]: the target at n times its size (sub-pixels)
  Eigen::Matrix3d rotation_;
  Interp interp_;
  Engine engine_;
  int threads_;
  bool cache_map_;
  mutable std::vector<TileMap> cache_;  // one per tile (empty for fused tiles), built on first use
  mutable std::once_flag cache_once_;   // so that threads sharing a Converter build it once
  void build_cache() const;
  TileRect tile(int64_t t) const;  // tiles in row-major order
  int64_t tile_count() const;
  // True (and g filled) where the tile's geometry (of target_, or of the given target) runs in
  // registers fused with the sampling.
  bool fused(const TileRect& rect, SimdGeometry& g) const { return fused(source_, target_, rect, g); }
  bool fused(const Projection& source, const Projection& target, const TileRect& rect, SimdGeometry& g) const;
  std::vector<Projection> lenses_;  // a dual-fisheye source's lenses alone (blended per tile), else empty
  const TileMap* cached(int64_t t) const;  // the kept map of a tile that has one, else null
};

// A one-off conversion (a Converter without a cache).
Image fast_remap(const Image& src, const Projection& src_proj, const Projection& dst_proj,
                 const Eigen::Matrix3d& rotation, Interp interp, Engine engine, int threads,
                 EngineStats* stats = nullptr);

// The SIMD target in use (e.g. "AVX2").
const char* simd_target();

}  // namespace panoproj
