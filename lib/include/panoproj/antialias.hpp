#pragma once
// Antialiasing where a conversion shrinks. An output pixel whose footprint in the source spans
// more than a source pixel averages over it instead of interpolating at its centre alone:
//   auto        per 64x64 tile, s = the geometric mean of its source extents over its size
//               along x and y (the mean step from one output pixel to the next, in source pixels;
//               where the tile crosses a seam, a pole or cube faces, the median of each pixel's
//               own footprint, as mip below); tiles with s <= 2 are
//               sampled as without antialiasing, bit for bit; the others average n x n
//               sub-pixels, n = ceil(s / 2) up to 4: sub-pixels about 2 source pixels apart,
//               which the kernels' own support (bilinear: 2 px) fills. Chosen by measurement
//               (panoproj accuracy, README): on 4096x2048 -> 512-px fisheye, bilinear 2x2
//               sub-pixels gain 9.6 dB over none at 3.7 times the time, mip levels 4.8 dB at 10.
//               Counts per axis (nx x ny from the steps along the output's x and y) were
//               measured and dropped: 1.3 times the time on equirect -> cube for +0.01 dB (an
//               equirect is oversampled along x near its poles, its content there already smooth
//               along x), and 0.2 dB less on the fisheye.
//   N (2..16)   N x N sub-pixels everywhere: the area average as N grows, at N^2 times the
//               sampling.
//   mip         mip levels (pyramid.hpp: level k is the source shrunk 2^k times by 2x2 box
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
//   off         one sample at the pixel centre.
#include <string>
#include <string_view>

namespace panoproj {

struct Antialias {
  enum class Mode { Off, Auto, Supersample, Mip };
  Mode mode = Mode::Off;
  int n = 1;  // sub-pixels per axis (Supersample)
  static constexpr int kMaxAuto = 4;  // auto's largest n
};

// "off", "auto", "mip" or a sub-pixel count 2..16; throws panoproj::Error naming the text.
Antialias parse_antialias(std::string_view text);
std::string name_of(const Antialias& a);

}  // namespace panoproj
