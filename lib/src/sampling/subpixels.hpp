#pragma once
// Antialias's N x N supersampling: the means of each output pixel's sub-pixel samples. Internal.
#include <cstdint>

#include "panoproj/image.hpp"
#include "geometry/tile_map.hpp"

namespace panoproj {

// sub: the n x n-times rect's samples (rows of sub_stride bytes) in src's pixel layout; writes the
// rect's pixels into out (rows of out_stride bytes). Colour is averaged premultiplied by alpha.
void average_subpixels(const Image& src, const unsigned char* sub, int64_t sub_stride,
                       const PixelRect& rect, int n, unsigned char* out, int64_t out_stride);

}  // namespace panoproj
