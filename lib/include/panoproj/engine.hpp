#pragma once
// The fast engine: output tiles of kTile x kTile pixels over a thread pool. Per tile:
//   1. source coordinates from tile_map.hpp (cubic interpolation of exact nodes, <= 1/256 px);
//   2. if every tap lies inside the source (one face for cubemaps) and SIMD is on: Highway
//      kernels (float, runtime-dispatched target); otherwise the reference sampler, with its
//      edge rules (wrap, poles, cube neighbours, clamp).
// Tiles are fixed by the image size, not the thread count, so any number of threads gives the
// same bytes.
#include <Eigen/Core>

#include "panoproj/image.hpp"
#include "panoproj/interpolator.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/tile_map.hpp"

namespace panoproj {

enum class Engine {
  Simd,       // tiles, interpolated coordinates, SIMD sampling where no edge is touched (default)
  Scalar,     // the same tiles and coordinates, reference sampling everywhere
  Reference,  // exact per-pixel double geometry and sampling (resample.hpp)
};

Engine parse_engine(std::string_view name);  // throws panoproj::Error
const char* name_of(Engine e);

struct EngineStats {
  int64_t tiles = 0, simd_tiles = 0, interpolated_cells = 0, exact_cells = 0;
};

Image fast_remap(const Image& src, const Projection& src_proj, const Projection& dst_proj,
                 const Eigen::Matrix3d& rotation, Interp interp, Engine engine, int threads,
                 EngineStats* stats = nullptr);

// The SIMD target in use (e.g. "AVX2").
const char* simd_target();

}  // namespace panoproj
