#pragma once
// The blended panorama (stitch with an image file as output): the plan's layers, made band by
// band of the canvas, blended by weights from their geometry alone (blend_margins.hpp), so that
// every frame of a template puts its seams in the same place:
// - feather: layer i's share s_i = lens_weight0(m_i, max_{j != i} m_j, feather) (lens_pair.hpp,
//   the dual fisheye's ramp; the whole overlap by default: s_i = m_i / (m_i + m_j) for two), over
//   the sum of the shares of the layers that cover the pixel;
// - multiband: Burt and Adelson's spline (pyramid.hpp): each layer's Laplacian pyramid (the
//   layer's colours, extended past its alpha by normalized convolution) blended at each level by
//   the Gaussian pyramid of its seam mask (the pixels where its margin is the largest), the
//   weights normalised at each level; levels from the overlaps' width unless given.
// Bands keep the canvas-sized buffers to the output image: each band's accumulators, the layers'
// parts in it, and the images it needs (each read once, at the first band it meets, dropped
// after the last).
#include <functional>

#include "jobs/stitch/stitch.hpp"

namespace panoproj {

struct BlendedPanorama {
  Image image;     // the canvas: colour (gray or RGB, as the layers) and alpha (covered: full)
  int levels = 0;  // multiband's
};

// The panorama's samples: the plan's depth, else the deepest layer's (float above 16 bits).
PixelType panorama_type(const StitchPlan& plan);

// band_done(image, rows): rows of the canvas final (in order). progress: the fraction done.
BlendedPanorama blend_panorama(const StitchPlan& plan, PixelType type,
                               const std::function<void(const Image&, const PixelRect&)>& band_done,
                               const std::function<void(double)>& progress);

inline constexpr int kMaxBlendLevels = 12;  // given
inline constexpr int kAutoBlendLevels = 8;  // estimated
// The levels multiband uses on the plan's canvas (its estimate, or plan.blend.levels).
int blend_levels(const StitchPlan& plan);

}  // namespace panoproj
