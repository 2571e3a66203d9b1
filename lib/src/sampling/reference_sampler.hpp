#pragma once
// The reference (double, per-tap tap rules) sampler of resample.cpp, for the engine's tiles
// that touch an edge and for its scalar mode. Internal.
#include <cstdint>

#include "panoproj/image.hpp"
#include "sampling/interpolator.hpp"
#include "geometry/source_taps.hpp"

namespace panoproj {

void sample_reference(const Image& src, const SourceTaps& taps, Interp interp, const double* xs,
                      const double* ys, const uint8_t* ok, int64_t n, unsigned char* out);

// The same with the footprint kernel (footprint_kernel.hpp), box widths ex, ey per sample.
void sample_footprint_reference(const Image& src, const SourceTaps& taps, const double* xs, const double* ys,
                                const float* ex, const float* ey, const uint8_t* ok, int64_t n, unsigned char* out);

}  // namespace panoproj
