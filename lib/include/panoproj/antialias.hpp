#pragma once
// Antialiasing where a conversion shrinks. An output pixel whose footprint in the source spans
// more than a source pixel averages over it instead of interpolating at its centre alone:
//   auto        per 64x64 tile, s = the median over 3 x 3 points (corners, edge middles, centre)
//               of the footprint's side: the geometric mean of the map's steps to the next pixel
//               along x and along y, in source pixels (each the shorter of the steps before and
//               after it, so that a seam or face edge does not count). Tiles with s <= 2 are
//               sampled as without antialiasing, bit for bit. The others take the footprint
//               kernel (footprint_kernel.hpp): each pixel the mean of the source pixels under its
//               footprint, weighted by their overlap with a box of the footprint's widths along
//               x and y (up to 5 source pixels, 6 taps), whatever the interpolator; where the
//               footprint is wider than that (s > 5, with x steps on an equirect counted at
//               cos(latitude): its rows near the poles hold far more samples than detail), n x n
//               sub-pixels, n = ceil(s / 5) up to 4, each through the kernel. Chosen by
//               measurement (panoproj accuracy, README), chart scene, 4096x2048 -> 512-px
//               fisheye: +12.6 dB over none at about twice its time. Tried before: n x n bilinear
//               sub-pixels, n = ceil(s / 2) (+10.9 dB at 5.2 times); 4-tap kernels (two
//               tents at +-a, 2x2 sub-pixels without their geometry; the box cut to 4 taps),
//               1.7 and 2.3 dB lower at about 0.7 times the time; splitting near equirect poles as
//               elsewhere, 0.8 dB lower at 1.5 times.
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
