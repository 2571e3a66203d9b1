#pragma once
// SIMD sampling of interior tiles (Google Highway, runtime dispatch). Internal to the engine.
// "Interior": every tap of every valid sample lies inside the source rectangle handed over, so
// the kernel has no edge logic; the engine sends other tiles to the reference sampler.
#include <cstdint>

#include "panoproj/image.hpp"
#include "panoproj/interpolator.hpp"

namespace panoproj {

struct SimdSource {
  const unsigned char* base;  // pixel (0, 0) of the positions' frame
  int64_t stride;             // bytes per row
  int channels, alpha;        // alpha channel or -1
  PixelType type;
};

// Largest vector width in floats over all compiled targets: position arrays must be padded to
// a multiple of it (with positions whose taps are also inside).
inline constexpr int kMaxSimdLanes = 16;

// Samples n positions (xs, ys relative to base, panoproj pixel convention) for bilinear, bicubic
// or lanczos3, writing interleaved pixels of src's type to out; samples with ok = 0 are 0.
// xs and ys are read (not written) up to n rounded up to kMaxSimdLanes; ok only up to n.
// Reads up to 3 bytes past the last pixel it touches (Image keeps that slack).
void simd_sample(const SimdSource& src, Interp interp, const float* xs, const float* ys,
                 const uint8_t* ok, int64_t n, unsigned char* out);

// Name of the SIMD target the dispatcher picks now (e.g. "AVX2").
const char* simd_target_name();

}  // namespace panoproj
