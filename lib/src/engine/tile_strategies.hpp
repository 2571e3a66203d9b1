#pragma once
// The Converter's per-tile strategies, one chosen per run from the antialiasing mode
// (options.hpp: Antialias): plain sampling; auto (per tile: plain, the footprint kernel, or the footprint
// kernel on n x n sub-pixels); n x n sub-pixels (supersample); mip levels. Each samples through
// TileSampling. Internal.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/tile_sampling.hpp"
#include "panoproj/options.hpp"

namespace panoproj {

// What the strategies share over a run.
struct StrategyInputs {
  const TileSampling& sampling;
  const Projection& source;
  const Projection& target;
  const std::vector<Projection>& sub_targets;  // [n]: the target at n times its size
  const Eigen::Matrix3d& rotation;
  double wrap;  // a turn's length in source pixels where x wraps (footprints measure across the
                // seam), else 0
};

class TileStrategy {
 public:
  virtual ~TileStrategy() = default;
  // Writes tile rect of the target at corner (rows of stride bytes); kept: what is kept of it.
  virtual void tile(const PixelRect& rect, const KeptTile& kept, unsigned char* corner,
                    int64_t stride, TileScratch& wk) const = 0;
  // Widens box {x0, y0, x1, y1} to the source positions tile() samples there (pixel centres or
  // sub-pixels; the kernels' taps reach around them); false where it cannot tell (mip).
  virtual bool widen_to_samples(const PixelRect& rect, TileScratch& wk,
                                std::array<double, 4>& b) const = 0;
};

// The strategy for antialias (mip builds the source's levels as its tiles read them).
std::unique_ptr<TileStrategy> tile_strategy(const Antialias& antialias, const StrategyInputs& job);

}  // namespace panoproj
