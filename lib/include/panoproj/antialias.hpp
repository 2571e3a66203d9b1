#pragma once
// Antialiasing where a conversion shrinks. An output pixel whose footprint in the source spans
// rho > 1 source pixels averages over it instead of interpolating at its centre alone:
//   auto        mip levels (pyramid.hpp: level k is the source shrunk 2^k times by 2x2 box
//               means). rho, the side of a pixel's footprint in source pixels, is the geometric
//               mean of the map's steps to the next pixel along x and along y (each the smaller
//               of the forward and backward step, so that a seam or face edge between
//               neighbours does not count); the pixel samples with the chosen kernel the two
//               levels around r = rho / 2, 2^k <= r < 2^(k+1), blended linearly in r. Bilinear at
//               level log2(rho / 2) spans rho source pixels: for a uniform shrink by 2^(k+1) it is
//               exactly the area average. (rho instead of rho / 2, as textures on GPUs, blurred
//               the chart scene 3 dB below no antialiasing; the larger step instead of the mean
//               lost 1.5 dB where equirect sources stretch near the poles: tests/antialias_test.)
//               Pixels with r <= 1 (rho <= 2) are sampled as without antialiasing, bit for bit.
//   N (2..16)   N x N samples per output pixel at the centres of its N x N sub-pixels, averaged:
//               the area average the accuracy tests use as truth, at N^2 times the sampling cost.
//   off         one sample at the pixel centre.
// Measured error and time for each: `panoproj accuracy`.
#include <string>
#include <string_view>

namespace panoproj {

struct Antialias {
  enum class Mode { Off, Auto, Supersample };
  Mode mode = Mode::Off;
  int n = 1;  // sub-pixels per axis (Supersample)
};

// "off", "auto" or a sub-pixel count 2..16; throws panoproj::Error naming the text.
Antialias parse_antialias(std::string_view text);
std::string name_of(const Antialias& a);

}  // namespace panoproj
