#pragma once
// A fused tile's planned taps, kept for a Converter's later runs (Keep::MapsAndTaps, convert.hpp):
// what phase 1 of the SIMD sampler gives phase 2, per output pixel, so a later run on a source of
// the same layout only gathers and blends: its bytes are those of the run that planned them.
// Two forms: compact for uint8 bilinear without alpha (the fixed-point weights, 8 bytes a pixel),
// else the fractions (12 bytes; the footprint kernel's widths are made again from the tile's
// field, as phase 1 makes them). Recorded by the first run that samples the tile (kept_once.hpp).
// Internal.
#include <cstdint>
#include <vector>

#include "base/kept_once.hpp"
#include "sampling/simd_sampler.hpp"

namespace panoproj {

struct PlannedTaps : KeptOnce {  // claim() to record, publish() or decline() (too many misses)
  // Bytes a kept tile may hold per output pixel: 12 for its taps, at most 3 for its misses (24
  // bytes each; a tile with more than kMostMisses of its pixels missed is not kept).
  static constexpr int kBytesPerPixel = 15;
  static constexpr double kMostMisses = 1.0 / 8;
  static constexpr int64_t kPad = 16;  // the widest vector's lanes (AVX-512: 16 floats)

  std::vector<int32_t> off;  // byte offset of each pixel's first tap from the window's first
                             // pixel, -1 where the SIMD kernel does not sample it (row-major in the
                             // tile, then kPad of -1 so a vector's reads stay inside)
  bool compact = false;           // weights, else tx and ty
  std::vector<uint32_t> weights;  // compact: round(t 65535) along x | along y << 16, the same layout
  std::vector<float> tx, ty;      // else: the fractions phase 1 gives, the same layout
  SimdMisses misses;              // the samples left to the reference's tap rules

  // Sizes the arrays for a rect of n pixels, in the form compact says.
  void allocate(int64_t n, bool compact_form) {
    const auto all = static_cast<size_t>(n + kPad);
    compact = compact_form;
    off.assign(all, -1);
    if (compact) weights.assign(all, 0);
    else tx.assign(all, 0.0f), ty.assign(all, 0.0f);
  }
  void release() { off = {}, weights = {}, tx = {}, ty = {}; }
};

// Whether taps planned on source a hold for source b: the same window of the frame, row stride
// and pixels (offsets count from the window's first pixel; base pointers may differ).
inline bool same_layout(const SimdSource& a, const SimdSource& b) {
  return a.stride == b.stride && a.channels == b.channels && a.alpha == b.alpha && a.type == b.type && a.x0 == b.x0 &&
         a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1 && a.cell_w == b.cell_w && a.cell_h == b.cell_h &&
         a.cells_x == b.cells_x && a.cells_y == b.cells_y;
}

}  // namespace panoproj
