#pragma once
// How the Converter samples one rect of a target from the source (the tiles' strategies,
// tile_strategies.hpp, call it): the geometry fused in registers where the SIMD pair takes it,
// else from the rect's map (the kept one, or made now); the SIMD kernels with the reference's
// tap rules (SourceTaps) for the samples they leave (seams, poles, face edges, the window), or
// the reference for all (the scalar engine); a dual fisheye's rects from the lens that sees
// them all, or from both, blended (dual_blend.hpp). Internal.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "panoproj/convert.hpp"
#include "panoproj/image.hpp"
#include "base/kept_once.hpp"
#include "geometry/source_taps.hpp"
#include "geometry/tile_map.hpp"
#include "sampling/footprint_kernel.hpp"
#include "sampling/mip_sampler.hpp"
#include "sampling/planned_taps.hpp"
#include "sampling/simd_sampler.hpp"

namespace panoproj {

// Auto antialiasing's measure of a tile (tile_strategies.cpp: its sub-pixels per axis and the
// footprint kernel's widths), which the geometry alone sets.
struct KeptFootprint : KeptOnce {
  FootprintField field;
  int n = 0;
};

// A dual fisheye's blend over a tile (dual_weights, dual_blend.hpp), which the geometry alone sets:
// the lens that sees every pixel (0 or 1), or -1 and lens 0's weights.
struct KeptBlend : KeptOnce {
  int side = -1;
  std::vector<float> weights;
};

// What a Converter keeps of one tile for its later runs (Keep, convert.hpp): its map (a tile not
// fused), or the taps it plans (a fused one, where they fit the source: planned_taps.hpp), one
// each per lens of a dual-fisheye source (else [0]), and then its blend; with auto antialiasing
// its footprint measure.
struct KeptTile {
  const TileMap* maps[2] = {nullptr, nullptr};
  PlannedTaps* taps[2] = {nullptr, nullptr};
  KeptFootprint* footprint = nullptr;
  KeptBlend* blend = nullptr;
  const TileMap* map() const { return maps[0]; }
  // Part k alone (a lens's).
  KeptTile part(int k) const {
    return {{maps[k], nullptr}, {taps[k], nullptr}, footprint, nullptr};
  }
};

// One worker thread's buffers and counts.
struct TileScratch {
  TileMap map;
  SimdMisses misses;
  EngineStats stats;
  MipScratch mip;
  std::vector<unsigned char> sub;    // a tile's sub-pixel samples
  std::vector<float> weights;        // a dual fisheye's lens 0 weights over a rect
  std::vector<unsigned char> other;  // and its lens 1 samples there
  FootprintField field;              // the footprint kernel's widths over a tile
  int64_t field_tile = -1;           // the tile (its corner's index) field and field_n are of
  int field_n = 0;                   // auto's sub-pixels per axis there (tile_strategies.cpp)
  std::vector<float> ex, ey;         // and over a row (the scalar engine)
};

// The source as the SIMD kernels see it: the window held, and the cell taps must stay in (a cube
// face: cube layouts put faces on a grid of face-sized cells; else the whole frame).
// Nearest takes exact positions near pixel edges (float lanes recomputed in double there, no
// grid; tile maps likewise): it copies the pixels the reference engine picks. Returns true.
inline bool exact_for(Interp interp, SimdGeometry& g) {
  if (interp == Interp::Nearest) g.grid = false, g.edge_exact = true;
  return true;
}

// src as the SIMD sampler reads it: the pixels held that are the image's (taps.col0() .. row1():
// taps beyond are misses, for the tap rules), and its cells.
SimdSource simd_source(const Image& src, const SourceTaps& taps);

// One lens of a two-lens source alone (SamplingFacts::lensed): a dual fisheye's fisheye on the
// whole frame (its circle inside its half) and the rotation to it, R_k^T times the conversion's
// (lens ray = R_k^T camera ray); a GoPro MAX's partial cube and the conversion's. Its taps stay in
// its cells by the source's tap rules.
struct LensSource {
  Projection lens;
  Eigen::Matrix3d rotation;
};
std::vector<LensSource> lens_sources(const SamplingFacts& f, const Eigen::Matrix3d& rotation);

// Widens box {x0, y0, x1, y1} to the valid source positions of rect of target t, from source sp
// through rotation r: those of its kept map tm if given, else the fused geometry's (simd, nothing
// stored), else those of a map made in scratch.
void widen_to_positions(const Projection& sp, const Eigen::Matrix3d& r, const Projection& t,
                        const PixelRect& rect, const TileMap* tm, bool simd, TileMap& scratch,
                        std::array<double, 4>& b, const Siting& siting = {});

class TileSampling {
 public:
  // lenses: a dual-fisheye source's lenses alone (blended per rect), else empty. simd: the simd
  // engine (fused geometry, SIMD kernels), else the scalar one. siting: the planes' (a target's
  // sub-pixel frames, n times `target`'s size, get it scaled).
  TileSampling(const Image& src, const Projection& source, const std::vector<LensSource>& lenses,
               const Eigen::Matrix3d& rotation, Interp interp, bool simd, const Siting& siting = {},
               Size target = {});

  // rect of target t into out (rows of stride bytes); kept: what is kept of it. fp: the
  // footprint kernel and its widths over the rect, else the interpolator (kept taps are of that).
  void rect(const Projection& t, const PixelRect& rect, const KeptTile& kept, unsigned char* out,
            int64_t stride, TileScratch& wk, const FootprintField* fp = nullptr) const;
  // Positions m of image im (its taps, SIMD view ss: the source or one of its mip levels).
  void map(const Image& im, const SourceTaps& taps, const SimdSource& ss, const TileMap& m, unsigned char* out,
           int64_t stride, TileScratch& wk, const FootprintField* fp) const;
  // Widens b to the source positions rect of target t samples (a dual-fisheye source's: those of
  // its whole-frame map).
  void widen_to_positions(const Projection& t, const PixelRect& rect, TileScratch& wk,
                          std::array<double, 4>& b) const {
    panoproj::widen_to_positions(source_, rotation_, t, rect, nullptr, simd_, wk.map, b,
                                 siting_for(t));
  }
  // Whether rect of target t from the source runs fused (g filled).
  bool fused(const Projection& t, const PixelRect& rect, SimdGeometry& g) const {
    return fused(source_, rotation_, t, rect, g);
  }
  // The map of rect of target t from the source, into m.
  void map_rect(const Projection& t, const PixelRect& rect, TileMap& m) const {
    map_tile(source_, t, rotation_, rect, m, interp_ == Interp::Nearest, siting_for(t));
  }

  // The siting on target t (the target, or its sub-pixel frame).
  Siting siting_for(const Projection& t) const {
    return siting_.any() ? siting_.on_sub_target(static_cast<int>(size_of(t).width / target_.width))
                         : siting_;
  }
  const Image& image() const { return src_; }
  bool lensed() const { return !lenses_.empty(); }  // a dual fisheye's lenses sampled alone
  const SourceTaps& taps() const { return taps_; }
  Interp interp() const { return interp_; }

 private:
  // From source projection sp through rotation r (the source, or one lens).
  void from(const Projection& sp, const Eigen::Matrix3d& r, const Projection& t,
            const PixelRect& rect, const KeptTile& kept, unsigned char* out, int64_t stride,
            TileScratch& wk, const FootprintField* fp) const;
  bool fused(const Projection& sp, const Eigen::Matrix3d& r, const Projection& t,
             const PixelRect& rect, SimdGeometry& g) const;
  // The samples the SIMD kernels left in m (rect's pixel indices), by the tap rules.
  void resolve_misses(const Image& im, const SourceTaps& taps, const PixelRect& rect,
                      const SimdMisses& m, unsigned char* out, int64_t stride, TileScratch& wk,
                      const FootprintField* fp) const;

  const Image& src_;
  const Projection& source_;
  const std::vector<LensSource>& lenses_;
  const Eigen::Matrix3d& rotation_;
  Interp interp_;
  bool simd_;
  Siting siting_;
  Size target_;
  SourceTaps taps_;
  SimdSource simd_src_;
};

}  // namespace panoproj
