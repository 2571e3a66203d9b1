#pragma once
// SIMD sampling (Google Highway, runtime dispatch). Internal to the engine. In chunks of a few
// rows: phase 1 turns positions into first taps (int32 byte offsets) and float fractions and
// prefetches the taps; phase 2 gathers and blends (float; uint8 without alpha in 16-bit fixed
// point).
// A sample whose taps all lie inside its cell (one cube face, else the frame) and inside the
// window of the source held in memory is computed here; any other valid sample (a seam, a pole,
// a face edge, a window edge) is listed in SimdMisses for the reference sampler's tap rules.
// Three entry points: positions from a map; fused with the vector geometry (no map at all); or
// the taps a fused run kept (planned_taps.hpp), phase 2 alone.
#include <cstdint>
#include <vector>

#include "panoproj/image.hpp"
#include "sampling/interpolator.hpp"
#include "geometry/tile_map.hpp"
#include "sampling/footprint_kernel.hpp"
#include "simd/geometry.hpp"

namespace panoproj {

struct PlannedTaps;  // planned_taps.hpp

struct SimdSource {
  const unsigned char* base;  // frame pixel (x0, y0): the first pixel held
  int64_t stride;             // bytes per row
  int channels, alpha;        // alpha channel or -1
  PixelType type;
  int64_t x0, y0, x1, y1;     // the frame pixels [x0, x1) x [y0, y1) held in memory
  int64_t cell_w, cell_h;     // taps must stay in one aligned cell of this size; 0: the frame
  const CubeAxis* cells_x = nullptr;  // uneven cells (FFmpeg's EAC frame) instead: taps stay in
  const CubeAxis* cells_y = nullptr;  // the sample's cell of these edges
  bool dering = false;        // clamp to the central 2x2 taps (set from the Interp by the kernels)
  const FootprintField* footprint = nullptr;  // the footprint kernel's widths (set by the entry points)
};

// Output pixels the kernels left (written as 0) for the reference sampler: pixel index in the
// rect (row-major) and source position.
struct SimdMisses {
  std::vector<int64_t> index;
  std::vector<double> xs, ys;
  void clear() { index.clear(), xs.clear(), ys.clear(); }
};

// Samples the positions of a tile map (panoproj pixel convention, frame coordinates) with any
// kernel, or with footprint, the footprint kernel (footprint_kernel.hpp) and its widths over
// the rect; samples with ok = 0 are 0. Writes interleaved pixels of src's type: the rect's row j
// at out + j * out_stride. Reads nothing past the window's last pixel (the last row's final taps
// go to misses), so the source may be a view of someone else's exact-sized buffer. The rect may be
// at most kTile pixels wide (a chunk of blocks holds a row of that; wider throws).
void simd_sample(const SimdSource& src, Interp interp, const TileMap& tm, unsigned char* out, int64_t out_stride,
                 SimdMisses& misses, const FootprintField* footprint = nullptr);

// Whether a source of type t takes positions interpolated on the grid (SimdGeometry::grid):
// uint8, where their error (within kFloatTolerance per axis) moves a sample by < 0.25 LSB even at
// 160 LSB per px; wider types would resolve it and keep per-pixel geometry.
inline bool grid_suits(PixelType t) { return t == PixelType::U8; }

// The same for the output pixels of rect in g's target, the positions from the vector geometry
// (g must be valid for rect; on its grid where grid_suits(src.type)): no map is stored.
// record: also keep the rect's planned taps and misses there (only where keeps_taps()).
void simd_convert(const SimdGeometry& g, const PixelRect& rect, const SimdSource& src,
                  Interp interp, unsigned char* out, int64_t out_stride, SimdMisses& misses,
                  const FootprintField* footprint = nullptr, PlannedTaps* record = nullptr);

// Whether the samples of src can be kept as planned taps (planned_taps.hpp): a window under 2 GB
// (int32 offsets from its first pixel).
bool keeps_taps(const SimdSource& src);
// Whether in their compact form: uint8 without alpha, bilinear, not the footprint kernel, on a
// SIMD target (the fixed-point kernel).
bool keeps_compact_taps(const SimdSource& src, Interp interp, const FootprintField* footprint);

// The rect's pixels from taps recorded by simd_convert on a source of src's layout with interp
// and footprint (the field over the rect again; the misses, taps.misses, are left to the caller,
// as simd_convert's).
void simd_replay(const PlannedTaps& taps, const PixelRect& rect, const SimdSource& src,
                 Interp interp, const FootprintField* footprint, unsigned char* out,
                 int64_t out_stride);

// Name of the SIMD target the dispatcher picks now (e.g. "AVX2").
const char* simd_target_name();

// How the gray kernels fetch their taps on x86: -1 as timed once on this CPU, 0 by loads, 1 by
// gathers (the same bytes; tests run both).
int simd_gray_fetch();
void set_simd_gray_fetch(int fetch);

}  // namespace panoproj
