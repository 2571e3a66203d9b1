#pragma once
// Interpolation kernels. Each declares its support (taps per axis); a sample at continuous
// position s (pixel centres at i + 0.5) reads taps first_tap(s) .. first_tap(s) + support - 1.
//   nearest   1 tap: the pixel containing s; pixels are copied untouched.
//   bilinear  2 taps, tent.
//   bicubic   4 taps, Keys cubic convolution with a = -0.5 (Catmull-Rom), Keys, "Cubic
//             convolution interpolation for digital image processing", IEEE TASSP 29(6), 1981.
//   lanczos3  6 taps, sinc(t) sinc(t/3), weights normalized to sum 1.
#include <cstdint>
#include <string_view>

namespace panoproj {

enum class Interp { Nearest, Bilinear, Bicubic, Lanczos3 };

int support(Interp k);
const char* name_of(Interp k);
Interp parse_interp(std::string_view name);  // throws panoproj::Error

// First tap index for a sample at s.
int64_t first_tap(Interp k, double s);
// Weights of the support() taps from first_tap(k, s); they sum to 1.
void tap_weights(Interp k, double s, double* w);

}  // namespace panoproj
