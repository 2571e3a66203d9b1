#pragma once
// The reference remap: for every output pixel, pixel -> ray -> R * ray -> source pixel -> sample.
// Scalar and exact (geometry in double, accumulation in double); the fast engine is checked
// against it. Threads take whole rows; each pixel's value does not depend on the split, so the
// result is identical for any thread count.
#include <Eigen/Core>

#include "panoproj/image.hpp"
#include "sampling/interpolator.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

struct RemapOptions {
  Interp interp = Interp::Bicubic;
  int threads = 0;  // 0: all cores
};

// src may be a window of the source frame (image.hpp) holding every pixel the taps reach.
// Output: dst's size, src's channels, type and alpha. Pixels with no source (outside the
// source's field or the target's frame) are 0, which is transparent when there is alpha.
// Alpha is interpolated premultiplied; nearest copies pixels untouched.
Image remap(const Image& src, const Projection& src_proj, const Projection& dst_proj,
            const Eigen::Matrix3d& rotation, const RemapOptions& options);

}  // namespace panoproj
