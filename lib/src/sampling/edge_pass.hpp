#pragma once
// The finishing pass of EdgeFill (options.hpp) over a converted image. Internal (engine.cpp).
#include <Eigen/Core>

#include "panoproj/options.hpp"
#include "panoproj/image.hpp"
#include "sampling/interpolator.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

// out: src converted from `source` to `target` (rays through `rotation`, kernel `interp`).
// Per output tile it finds which pixels have a source (the SIMD geometry's or the tile mapper's
// validity, both exact, with a pixel of apron), skipping tiles the target covers whole from a
// source that sees every ray;
// edge pixels get their 4x4 sub-positions sampled with the reference sampler.
void finish_edges(const Image& src, const Projection& source, const Projection& target, const Eigen::Matrix3d& rotation,
                  Interp interp, const EdgeFill& fill, int threads, Image& out);

}  // namespace panoproj
