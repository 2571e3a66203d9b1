#pragma once
// Source-coordinate maps as a product, for other tools (cv::remap, GPU shaders, caches).
// A map is a 2-channel float32 image of the output's size: channel 0 = source x, 1 = source y.
// Coordinates come from the engine's tile mapper (within 1/256 px of the exact map, see
// tile_map.hpp); float32 then holds them to 2^-24 relative (0.002 px at 32768 px).
// Convention:
//   OpenCV   pixel centres at integers (cv::remap's): x_cv = x_panoproj - 0.5; pixels without a
//            source get -1, which cv::remap with BORDER_CONSTANT turns into the border value.
//   Panoproj pixel centres at i + 0.5; pixels without a source get NaN.
#include <Eigen/Core>

#include "panoproj/image.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

enum class MapConvention { OpenCV, Panoproj };

Image build_map(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation,
                MapConvention convention, int threads);

}  // namespace panoproj
