#pragma once
// Interpolation kernels. Each declares its support (taps per axis); a sample at continuous
// position s (pixel centres at i + 0.5) reads taps first_tap(s) .. first_tap(s) + support - 1.
//   nearest   1 tap: the pixel containing s; pixels are copied untouched.
//   bilinear  2 taps, tent.
//   bicubic   4 taps, Keys cubic convolution with a = -0.5 (Catmull-Rom), Keys, "Cubic
//             convolution interpolation for digital image processing", IEEE TASSP 29(6), 1981.
//   lanczos3  6 taps, sinc(t) sinc(t/3), weights normalized to sum 1.
//   bicubic-dering, lanczos3-dering: the same, each channel clamped to the range of the 2x2 taps
//             around the sample (with alpha: premultiplied). Their negative lobes over- and
//             undershoot at sharp edges (dark rings around an HDR sun, negative values); the
//             clamp removes that and leaves samples inside the local range (most of a smooth
//             image) untouched.
// (Interp and its names: panoproj/options.hpp.) Internal.
#include <cstdint>

#include "panoproj/options.hpp"

namespace panoproj {

// The kernel of k (Bicubic for BicubicDering), and whether k clamps to the central 2x2 taps.
inline Interp kernel_of(Interp k) {
  return k == Interp::BicubicDering ? Interp::Bicubic : k == Interp::Lanczos3Dering ? Interp::Lanczos3 : k;
}
inline bool derings(Interp k) { return k != kernel_of(k); }

int support(Interp k);

// First tap index for a sample at s.
int64_t first_tap(Interp k, double s);
// Weights of the support() taps from first_tap(k, s); they sum to 1.
void tap_weights(Interp k, double s, double* w);

}  // namespace panoproj
