#pragma once
// The feathered blend of a two-lens source (a dual fisheye, dual_fisheye.hpp; a GoPro MAX,
// gopro_max.hpp) over one output tile, for the converter (engine.cpp), which samples each lens
// alone (LensSource) and blends them here. Internal.
#include <Eigen/Core>
#include <vector>

#include "panoproj/image.hpp"
#include "panoproj/projection.hpp"
#include "geometry/tile_map.hpp"

namespace panoproj {

// Lens 0's weight w0 at the pixels of target tile `rect` (rays through `rotation`, as the
// converter's). The lens margins are computed exactly at nodes every kDualNodeStep pixels (and the
// last row and column) and interpolated bilinearly between them: the margins are smooth on the
// sphere away from the lens axes, and weights within 1e-3 of the exact ones (dual_fisheye_test).
// Returns 0 or 1 when that lens alone gives every pixel of the tile (w untouched: the margins at
// the nodes clear the ramp by more than the nodes' spacing can hide), -1 when w (rect.w x rect.h,
// row-major) holds the weights. A tile with a node without a ray gets exact weights per pixel.
inline constexpr int kDualNodeStep = 8;
// (Pair: DualFisheye or GoProMax, their margin, weight0 and feather.)
template <class Pair>
int dual_weights(const Pair& d, const Projection& target, const Eigen::Matrix3d& rotation,
                 const PixelRect& rect, std::vector<float>& w);

// a = w a + (1 - w) b over the rect's pixels (rows of a_stride and b_stride bytes); with an alpha
// channel, the colours blend weighted by their alphas (premultiplied).
void blend_lenses(const float* w, const PixelRect& rect, PixelType type, int channels, int alpha,
                  unsigned char* a, int64_t a_stride, const unsigned char* b, int64_t b_stride);

}  // namespace panoproj
