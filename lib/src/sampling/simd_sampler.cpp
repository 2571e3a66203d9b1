// Highway kernels for simd_sampler.hpp, compiled once per target (foreach_target) and chosen at
// run time. Positions and tap indices in double; weights and accumulation in float. The reference
// (double) agrees within the bounds stated in tests/engine_test.cpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sampling/simd_sampler.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// Order matters: foreach_target re-includes this file once per target.
#include <hwy/contrib/math/math-inl.h>
#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include "panoproj/error.hpp"
#include "simd/tile_rows-inl.h"
#include "sampling/planned_taps.hpp"
#include "sampling/simd_sampler.hpp"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One lane per output pixel. Positions come in float or double vectors (DP); the samples use float
// and int32 vectors of the same lane count (DF, DI below).
constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(float);

// Tap weights for fractional offset t in [0, 1) from the left centre.
template <int K, class DF, class VF = hn::Vec<DF>>
HWY_INLINE void Weights(DF df, VF t, VF* w) {
  if constexpr (K == 2) {
    w[0] = hn::Sub(hn::Set(df, 1.0f), t);
    w[1] = t;
  } else if constexpr (K == 4) {
    // Keys a = -0.5 (Catmull-Rom) as cubics in t, taps at -1, 0, 1, 2.
    const VF t2 = hn::Mul(t, t), t3 = hn::Mul(t2, t);
    const VF h = hn::Set(df, 0.5f);
    w[0] = hn::Sub(hn::Sub(t2, hn::Mul(h, t3)), hn::Mul(h, t));
    w[1] = hn::Add(hn::Sub(hn::Mul(hn::Set(df, 1.5f), t3), hn::Mul(hn::Set(df, 2.5f), t2)),
                   hn::Set(df, 1.0f));
    w[2] = hn::Add(hn::Add(hn::Mul(hn::Set(df, -1.5f), t3), hn::Mul(hn::Set(df, 2.0f), t2)),
                   hn::Mul(h, t));
    w[3] = hn::Mul(h, hn::Sub(t3, t2));
  } else {
    // Lanczos-3, taps at d_i = t + 2 - i: L(d) = 3 sin(pi d) sin(pi d / 3) / (pi d)^2, with
    // sin(pi d_i) = (-1)^i sin(pi t) and sin(pi d_i / 3) from sin/cos(pi t / 3) by angle addition.
    constexpr float kPi = 3.14159265358979f, kR3 = 0.866025403784439f;
    const VF sp = hn::Sin(df, hn::Mul(t, hn::Set(df, kPi)));
    const VF a = hn::Mul(t, hn::Set(df, kPi / 3));
    const VF s3 = hn::Sin(df, a), c3 = hn::Cos(df, a);
    constexpr float kCos[6] = {-0.5f, 0.5f, 1.0f, 0.5f, -0.5f, -1.0f};
    constexpr float kSin[6] = {kR3, kR3, 0.0f, -kR3, -kR3, 0.0f};
    VF sum = hn::Zero(df);
    for (int i = 0; i < 6; ++i) {
      const VF d = hn::Add(t, hn::Set(df, static_cast<float>(2 - i)));
      const VF s_third = hn::MulAdd(s3, hn::Set(df, kCos[i]), hn::Mul(c3, hn::Set(df, kSin[i])));
      const VF num = hn::Mul(hn::Mul(hn::Set(df, (i % 2 ? -3.0f : 3.0f) / (kPi * kPi)), sp), s_third);
      const VF d2 = hn::Mul(d, d);
      const auto at_zero = hn::Lt(d2, hn::Set(df, 1e-10f));
      w[i] = hn::IfThenElse(at_zero, hn::Set(df, 1.0f), hn::Div(num, hn::IfThenElse(at_zero, hn::Set(df, 1.0f), d2)));
      sum = hn::Add(sum, w[i]);
    }
    const VF inv = hn::Div(hn::Set(df, 1.0f), sum);
    for (int i = 0; i < 6; ++i) w[i] = hn::Mul(w[i], inv);
  }
}

// The footprint kernel's tap weights (footprint_kernel.hpp) for fraction t and box width e:
// min(1, max(0, (e + 1) / 2 - |d|)) at the taps' distances d = t + 2 - i, over their sum (e).
template <class DF, class VF = hn::Vec<DF>>
HWY_INLINE void FootprintWeights(DF df, VF t, VF e, VF* w) {
  const VF h = hn::Mul(hn::Add(e, hn::Set(df, 1.0f)), hn::Set(df, 0.5f));
  VF sum = hn::Zero(df);
  for (int i = 0; i < kFootprintTaps; ++i) {
    const VF d = hn::Abs(hn::Add(t, hn::Set(df, static_cast<float>(kFootprintTaps / 2 - 1 - i))));
    w[i] = hn::Min(hn::Set(df, 1.0f), hn::Max(hn::Zero(df), hn::Sub(h, d)));
    sum = hn::Add(sum, w[i]);
  }
  const VF inv = hn::Div(hn::Set(df, 1.0f), sum);
  for (int i = 0; i < kFootprintTaps; ++i) w[i] = hn::Mul(w[i], inv);
}

// Exact half -> float for finite values (inf/NaN become inf/NaN): shift the 15 magnitude bits
// into a float's place and rescale by 2^112 (handles subnormals), then restore the sign.
template <class DF, class VF = hn::Vec<DF>, class DI = hn::RebindToSigned<DF>, class VI = hn::Vec<DI>>
HWY_INLINE VF HalfToFloat(DF df, VI h) {
  const DI di;
  const VI mag = hn::And(h, hn::Set(di, 0x7fff));
  VF f = hn::Mul(hn::BitCast(df, hn::ShiftLeft<13>(mag)), hn::BitCast(df, hn::Set(di, 0x77800000)));
  const auto special = hn::RebindMask(df, hn::Gt(mag, hn::Set(di, 0x7bff)));  // inf or NaN
  const VI inf_nan = hn::Or(hn::Set(di, 0x7f800000), hn::ShiftLeft<13>(hn::And(mag, hn::Set(di, 0x3ff))));
  f = hn::IfThenElse(special, hn::BitCast(df, inf_nan), f);
  return hn::BitCast(df, hn::Or(hn::BitCast(di, f), hn::ShiftLeft<16>(hn::And(h, hn::Set(di, 0x8000)))));
}

// Loads channel c of the pixels at byte offsets off as float.
template <PixelType T, class DF, class VF = hn::Vec<DF>, class DI = hn::RebindToSigned<DF>, class VI = hn::Vec<DI>>
HWY_INLINE VF LoadChannel(DF df, const unsigned char* base, VI off, int c, VI word) {
  const DI di;
  if constexpr (T == PixelType::U8) {
    return hn::ConvertTo(df, hn::And(hn::ShiftRightSame(word, 8 * c), hn::Set(di, 0xff)));
  } else if constexpr (T == PixelType::U16) {
    const VI v = hn::GatherOffset(di, reinterpret_cast<const int32_t*>(base), hn::Add(off, hn::Set(di, 2 * c)));
    return hn::ConvertTo(df, hn::And(v, hn::Set(di, 0xffff)));
  } else if constexpr (T == PixelType::F16) {
    const VI v = hn::GatherOffset(di, reinterpret_cast<const int32_t*>(base), hn::Add(off, hn::Set(di, 2 * c)));
    return HalfToFloat(df, v);
  } else {
    return hn::GatherOffset(df, reinterpret_cast<const float*>(base), hn::Add(off, hn::Set(di, 4 * c)));
  }
}

template <class T>
HWY_INLINE void StoreSample(unsigned char* p, float v) {
  if constexpr (std::is_integral_v<T>) {
    constexpr float kMax = static_cast<float>(std::numeric_limits<T>::max());
    const T t = static_cast<T>(std::clamp(std::nearbyint(v), 0.0f, kMax));
    std::memcpy(p, &t, sizeof(T));
  } else {
    const T t = static_cast<T>(v);
    std::memcpy(p, &t, sizeof(T));
  }
}

// Per-call constants of PlanLanes in the position type, in registers (the compiler cannot hoist
// loads from the SimdSource past the stores, which may alias anything).
template <class DP, class VP = hn::Vec<DP>>
struct Bounds {
  VP cw, ch, inv_cw, inv_ch, x0, x1, y0, y1, tail;
  VP ex[7], ey[7];
  int nx = 0, ny = 0;  // uneven cells: edges ex[0..nx], ey[0..ny]
  bool cells;
  bool whole;  // every byte of the window within int32 offsets of its start
  explicit Bounds(const SimdSource& s)
      : cells(s.cell_w > 0), whole(static_cast<double>(s.y1 - s.y0) * static_cast<double>(s.stride) < 2147483647.0) {
    using P = hn::TFromD<DP>;
    const DP dp;
    // The buffer ends with the window's last row, and nothing may be read past it: the gathers
    // read up to max(8, pb + 2) bytes from a tap's start (pb + 2: a 32-bit read of a uint16
    // pixel's last channel), so that row's last taps stay this many pixels before its end.
    const int pb = s.channels * static_cast<int>(bytes_of(s.type));
    tail = hn::Set(dp, static_cast<P>((std::max(8, pb + 2) - 1) / pb));
    cw = hn::Set(dp, static_cast<P>(s.cell_w)), ch = hn::Set(dp, static_cast<P>(s.cell_h));
    inv_cw = hn::Set(dp, static_cast<P>(cells ? 1.0 / static_cast<double>(s.cell_w) : 0.0));
    inv_ch = hn::Set(dp, static_cast<P>(cells ? 1.0 / static_cast<double>(s.cell_h) : 0.0));
    x0 = hn::Set(dp, static_cast<P>(s.x0)), x1 = hn::Set(dp, static_cast<P>(s.x1));
    y0 = hn::Set(dp, static_cast<P>(s.y0)), y1 = hn::Set(dp, static_cast<P>(s.y1));
    if (s.cells_x) {
      nx = s.cells_x->n, ny = s.cells_y->n;
      for (int k = 0; k <= nx; ++k) ex[k] = hn::Set(dp, static_cast<P>(s.cells_x->edge[k]));
      for (int k = 0; k <= ny; ++k) ey[k] = hn::Set(dp, static_cast<P>(s.cells_y->edge[k]));
    }
  }
};

// Float copy of a position-type vector.
template <class DF, class V>
HWY_INLINE hn::Vec<DF> ToFloat(DF df, V v) {
  if constexpr (std::is_same_v<hn::TFromV<V>, float>) return v;
  else return hn::DemoteTo(df, v);
}

// The taps of up to one float vector of output pixels (phase 1's product, phase 2's input).
struct TapBlock {
  const unsigned char* base;  // the row of the block's lowest first tap
  int64_t index;              // output pixel index of lane 0 (row-major in the rect)
  int64_t m;                  // lanes in use
  bool any;                   // some lane is sampled here (else the block is written as 0)
  HWY_ALIGN int32_t off[kMaxLanes];    // byte offset of the first tap from base; -1: not here
  HWY_ALIGN float tx[kMaxLanes], ty[kMaxLanes];  // fractions from the first-but-(K/2 - 1) tap
  HWY_ALIGN float ex[kMaxLanes], ey[kMaxLanes];  // the footprint kernel's box widths (its blocks only)
};

// A block's tap weights along x and y: the kernel's, or the footprint kernel's.
template <int K, class DF, class VF = hn::Vec<DF>>
HWY_INLINE void BlockWeights(const SimdSource& s, const TapBlock& blk, DF df, VF* wx, VF* wy) {
  if constexpr (K == kFootprintTaps) {
    if (s.footprint != nullptr) {
      FootprintWeights(df, hn::Load(df, blk.tx), hn::Load(df, blk.ex), wx);
      FootprintWeights(df, hn::Load(df, blk.ty), hn::Load(df, blk.ey), wy);
      return;
    }
  }
  Weights<K>(df, hn::Load(df, blk.tx), wx);
  Weights<K>(df, hn::Load(df, blk.ty), wy);
}

constexpr int kChunkBlocks = 64;  // blocks per chunk (see Chunked)

// The missed samples of one chunk, kept on the stack while the chunk is planned: the planning
// loop then makes no calls (a vector's growth would be one), so the compiler keeps the geometry's
// parameters in registers across it. Appended to SimdMisses after the chunk.
struct ChunkMisses {
  int n = 0;
  int64_t index[kChunkBlocks * kMaxLanes];
  double xs[kChunkBlocks * kMaxLanes], ys[kChunkBlocks * kMaxLanes];
  void append_to(SimdMisses& m) const {
    m.index.insert(m.index.end(), index, index + n);
    m.xs.insert(m.xs.end(), xs, xs + n);
    m.ys.insert(m.ys.end(), ys, ys + n);
  }
};

// Phase 1 for one vector of positions: first taps and fractions (floor(s) for nearest, else
// floor(s - 0.5) - (K/2 - 1), as interpolator.cpp), and the check that all taps lie in the
// sample's cell (a cube face, else the frame) and in the window, within int32 byte offsets of
// the lowest tap row. Other valid lanes go to misses. Prefetches the taps' cache lines so that
// phase 2, a few rows later, finds them in cache.
// Float positions are exact integers + fractions up to 2^24 px (use_float allows far less).
template <class DP, class VP = hn::Vec<DP>, class MP = hn::Mask<DP>>
HWY_INLINE void PlanLanes(const SimdSource& s, int K, const Bounds<DP>& b, VP sx, VP sy, MP ok, int64_t index,
                          int64_t m, TapBlock& blk, ChunkMisses& misses) {
  using P = hn::TFromD<DP>;
  using DF = hn::Rebind<float, DP>;
  using DI = hn::Rebind<int32_t, DP>;
  using VI = hn::Vec<DI>;
  const DP dp;
  const DF df;
  const DI di;
  const int pb = s.channels * static_cast<int>(bytes_of(s.type));
  const VP shift = hn::Set(dp, static_cast<P>(K == 1 ? 0.0 : 0.5 + (K / 2 - 1)));
  const VP X = hn::Sub(sx, shift), Y = hn::Sub(sy, shift);
  const VP fx = hn::Floor(X), fy = hn::Floor(Y);
  const VP k = hn::Set(dp, static_cast<P>(K));
  VP lo_x = b.x0, hi_x = hn::Sub(b.x1, k), lo_y = b.y0, hi_y = hn::Sub(b.y1, k);
  if (b.cells) {
    // (A rounding of s / cell at a cell edge only sends the sample to the reference.)
    const VP cx = hn::Mul(hn::Floor(hn::Mul(sx, b.inv_cw)), b.cw), cy = hn::Mul(hn::Floor(hn::Mul(sy, b.inv_ch)), b.ch);
    lo_x = hn::Max(cx, b.x0), hi_x = hn::Sub(hn::Min(hn::Add(cx, b.cw), b.x1), k);
    lo_y = hn::Max(cy, b.y0), hi_y = hn::Sub(hn::Min(hn::Add(cy, b.ch), b.y1), k);
  } else if (b.nx > 0) {
    // Uneven cells: the edges around the sample (a position at an edge belongs to the next cell).
    VP cx0 = b.ex[0], cx1 = b.ex[1], cy0 = b.ey[0], cy1 = b.ey[1];
    for (int e = 1; e < b.nx; ++e) {
      const MP past = hn::Ge(sx, b.ex[e]);
      cx0 = hn::IfThenElse(past, b.ex[e], cx0), cx1 = hn::IfThenElse(past, b.ex[e + 1], cx1);
    }
    for (int e = 1; e < b.ny; ++e) {
      const MP past = hn::Ge(sy, b.ey[e]);
      cy0 = hn::IfThenElse(past, b.ey[e], cy0), cy1 = hn::IfThenElse(past, b.ey[e + 1], cy1);
    }
    lo_x = hn::Max(cx0, b.x0), hi_x = hn::Sub(hn::Min(cx1, b.x1), k);
    lo_y = hn::Max(cy0, b.y0), hi_y = hn::Sub(hn::Min(cy1, b.y1), k);
  }
  MP inside = hn::And(hn::And(ok, hn::And(hn::Ge(fx, lo_x), hn::Le(fx, hi_x))),
                      hn::And(hn::Ge(fy, lo_y), hn::Le(fy, hi_y)));
  const VP last_y = hn::Sub(b.y1, k), tail_x = hn::Sub(hn::Sub(b.x1, k), b.tail);
  inside = hn::And(inside, hn::Or(hn::Lt(fy, last_y), hn::Le(fx, tail_x)));
  // The reach test runs in the position type (float: with 1% margin for its rounding), the
  // offsets themselves in exact integers.
  P y_min = 0;
  VI ioff = hn::Set(di, -1);
  const bool any = !hn::AllFalse(dp, inside);
  if (any) {
    // A window under 2 GB takes offsets from its first row; a larger one from the block's
    // lowest row, and lanes beyond int32 reach from there go to the reference.
    y_min = b.whole ? static_cast<P>(s.y0)
                    : hn::GetLane(hn::MinOfLanes(dp, hn::IfThenElse(inside, fy, hn::Set(dp, std::numeric_limits<P>::max()))));
    const VP row = hn::Sub(fy, hn::Set(dp, y_min)), col = hn::Sub(fx, b.x0);
    const VP off = hn::MulAdd(row, hn::Set(dp, static_cast<P>(s.stride)), hn::Mul(col, hn::Set(dp, static_cast<P>(pb))));
    if (!b.whole) {
      const double reach = 2147483647.0 - (K - 1) * static_cast<double>(s.stride) - (K + 1) * pb;
      inside = hn::And(inside, hn::Le(off, hn::Set(dp, static_cast<P>(std::is_same_v<P, float> ? 0.99 * reach : reach))));
    }
    if constexpr (std::is_same_v<P, float>) {
      const VI o = hn::Add(hn::Mul(hn::ConvertTo(di, row), hn::Set(di, static_cast<int32_t>(s.stride))),
                           hn::Mul(hn::ConvertTo(di, col), hn::Set(di, pb)));
      ioff = hn::IfThenElse(hn::RebindMask(di, inside), o, ioff);
    } else {
      ioff = hn::DemoteTo(di, hn::IfThenElse(inside, off, hn::Set(dp, -1.0)));
    }
  }
  const MP missed = hn::AndNot(inside, ok);
  if (HWY_UNLIKELY(!hn::AllFalse(dp, missed))) {
    HWY_ALIGN P bx[kMaxLanes] = {}, by[kMaxLanes] = {}, bm[kMaxLanes] = {};  // (rare: zeroed for gcc's sake)
    hn::Store(sx, dp, bx);
    hn::Store(sy, dp, by);
    hn::Store(hn::IfThenElseZero(missed, hn::Set(dp, P(1))), dp, bm);
    for (int64_t l = 0; l < m; ++l)
      if (bm[l] != P(0)) misses.index[misses.n] = index + l, misses.xs[misses.n] = bx[l], misses.ys[misses.n++] = by[l];
  }
  blk.index = index;
  blk.m = m;
  blk.any = any;
  blk.base = s.base + static_cast<int64_t>(y_min - static_cast<P>(s.y0)) * s.stride;
  if constexpr (!std::is_same_v<P, float>) {  // fewer lanes than phase 2 reads: the rest unused
    const hn::ScalableTag<int32_t> d32;
    hn::Store(hn::Set(d32, -1), d32, blk.off);
  }
  hn::Store(ioff, di, blk.off);
  if (K > 1) {
    hn::Store(ToFloat(df, hn::Sub(X, fx)), df, blk.tx);
    hn::Store(ToFloat(df, hn::Sub(Y, fy)), df, blk.ty);
  }
  if (any) {
    // The first and last lanes' taps, row by row: the lanes in between lie mostly between them.
    // (From the register where the block is full: a scalar read of the vector just stored
    // waited for it, ~12% of the planning's samples on Zen 3.)
    constexpr size_t kLast = hn::MaxLanes(DI()) - 1;
    const int32_t lane0 = hn::GetLane(ioff), lane_m = m == kLast + 1 ? hn::ExtractLane(ioff, kLast) : blk.off[m - 1];
    const int32_t first = lane0 >= 0 ? lane0 : 0, last = lane_m >= 0 ? lane_m : first;
    for (int r = 0; r < K; ++r) {
      hwy::Prefetch(blk.base + first + r * s.stride);
      hwy::Prefetch(blk.base + last + r * s.stride + (K - 1) * pb);
    }
  }
}

// Stores m pixels of pb <= 4 bytes from little-endian words, 4 bytes at a time while that stays
// inside the m pixels (the spare bytes are overwritten by the following pixels), then exactly.
HWY_INLINE void StoreWords(const uint32_t* w, int64_t m, int pb, unsigned char* p) {
  int64_t l = 0;
  for (; l * pb + 4 <= m * pb; ++l) std::memcpy(p + l * pb, &w[l], 4);
  for (; l < m; ++l) std::memcpy(p + l * pb, &w[l], static_cast<size_t>(pb));
}

// Stores the m pixels of a vector of packed words (one per lane, pb <= 4 bytes used): a full RGB
// vector packs each 128-bit block's four pixels into 12 bytes (byte shuffle), closes the gaps
// between blocks (32-bit lane permutation) and stores the 3N bytes under a mask; RGBA is stored
// as is; other cases go through StoreWords.
template <class DU, class VU = hn::Vec<DU>>
HWY_INLINE void StorePixels(DU du, VU word, int64_t m, int pb, unsigned char* p) {
#if HWY_TARGET != HWY_SCALAR
  const auto N = static_cast<int64_t>(hn::Lanes(du));
  if (m == N && pb == 4) return hn::StoreU(word, du, reinterpret_cast<uint32_t*>(p));
  if (m == N && pb == 3 && N % 4 == 0) {
    const hn::Repartition<uint8_t, DU> d8;
    HWY_ALIGN static constexpr uint8_t kPack[64] = {
        0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 0x80, 0x80, 0x80, 0x80, 0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 0x80, 0x80, 0x80, 0x80,
        0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 0x80, 0x80, 0x80, 0x80, 0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 0x80, 0x80, 0x80, 0x80};
    // Lane i < 3N/4 takes the (i % 3)-th word of block i / 3; the rest take the blocks' spare words.
    constexpr size_t kN = hn::MaxLanes(DU());
    HWY_ALIGN static constexpr auto kGather = [] {
      std::array<int32_t, kN> a{};
      for (size_t i = 0; i < kN; ++i)
        a[i] = static_cast<int32_t>(i < 3 * kN / 4 ? (i / 3) * 4 + i % 3 : (i - 3 * kN / 4) * 4 + 3);
      return a;
    }();
    static_assert(HWY_MAX_BYTES <= 64);
    const VU packed = hn::BitCast(du, hn::TableLookupBytes(hn::BitCast(d8, word), hn::Load(d8, kPack)));
    const VU dense = hn::TableLookupLanes(packed, hn::SetTableIndices(du, kGather.data()));
#if HWY_TARGET <= HWY_AVX3
    return hn::BlendedStore(dense, hn::FirstN(du, static_cast<size_t>(3 * N / 4)), du, reinterpret_cast<uint32_t*>(p));
#else
    // Plain stores of the lower half and the upper half's first quarter: AVX2's masked store
    // (vpmaskmovd) is microcoded on Zen 2/3, ~1/3 of e->pinhole bilinear's time there (perf).
    const hn::Half<DU> dh;
    hn::StoreU(hn::LowerHalf(dh, dense), dh, reinterpret_cast<uint32_t*>(p));
    const hn::Repartition<uint64_t, decltype(dh)> d64;
    if constexpr (kN == 8) {
      const uint64_t rest = hn::GetLane(hn::BitCast(d64, hn::UpperHalf(dh, dense)));
      std::memcpy(p + 16, &rest, 8);
    } else {
      static_assert(kN == 4);
      const uint32_t rest = hn::GetLane(hn::UpperHalf(dh, dense));
      std::memcpy(p + 8, &rest, 4);
    }
    return;
#endif
  }
#endif
  HWY_ALIGN uint32_t w32[kMaxLanes];
  hn::Store(word, du, w32);
  StoreWords(w32, m, pb, p);
}

#if HWY_TARGET != HWY_SCALAR
// The fixed-point uint8 kernels' reads: for a byte offset from each lane's first tap, 8 bytes
// per lane, split into two words: the pixel there and the next one (pb bytes on), channels in
// their low pb bytes. Also their common end: invalid lanes 0, then stored.
class TapPairs {
 public:
  using DU = hn::RebindToUnsigned<hn::ScalableTag<float>>;
  using VU = hn::Vec<DU>;

  // off: a vector's first-tap byte offsets from base (-1: not sampled here), m of them in use.
  TapPairs(const SimdSource& s, const unsigned char* base, const int32_t* off, int64_t m)
      : pb_(s.channels), base_(reinterpret_cast<const uint64_t*>(base)), off_(off), m_(m) {
#if HWY_TARGET <= HWY_AVX2
    // Lanes not sampled read the base. (Clamped once here, read per lane from memory by Fetch:
    // the compiler moved each offset through vector registers and back, ~6 instructions a read.)
    const hn::RebindToSigned<DU> di;
    hn::Store(hn::Max(hn::LoadU(di, off), hn::Zero(di)), di, at_);
#else
    const hn::RebindToSigned<DU> di;
    const hn::Half<decltype(di)> dih;
    const auto off_v = hn::Max(hn::LoadU(di, off), hn::Zero(di));
    lo_ = hn::PromoteTo(DI64(), hn::LowerHalf(dih, off_v));
    hi_ = hn::PromoteTo(DI64(), hn::UpperHalf(dih, off_v));
#endif
  }

  // For R byte offsets at once (each lane's offset read once for all R).
  template <int R>
  void Get(const int64_t (&bytes)[R], VU (&first)[R], VU (&second)[R]) const {
    const DU du;
    V64 lo[R], hi[R];
    Fetch<R>(bytes, lo, hi);
    for (int r = 0; r < R; ++r) {
      first[r] = hn::ConcatEven(du, hn::BitCast(du, hi[r]), hn::BitCast(du, lo[r]));
      second[r] = hn::ConcatEven(du, hn::BitCast(du, hn::ShiftRightSame(hi[r], 8 * pb_)),
                                 hn::BitCast(du, hn::ShiftRightSame(lo[r], 8 * pb_)));
    }
  }
  void Get(int64_t bytes, VU& first, VU& second) const {
    VU f[1], s[1];
    Get<1>({bytes}, f, s);
    first = f[0], second = s[0];
  }

  // Stores the m pixels from one packed word per lane at o; lanes not sampled here are 0.
  void Store(VU word, unsigned char* o) const {
    const DU du;
    const hn::RebindToSigned<DU> di;
    word = hn::IfThenElseZero(hn::RebindMask(du, hn::Gt(hn::LoadU(di, off_), hn::Set(di, -1))), word);
    StorePixels(du, word, m_, pb_, o);
  }

 private:
  using D64 = hn::Repartition<uint64_t, DU>;
  using DI64 = hn::RebindToSigned<D64>;
  using V64 = hn::Vec<D64>;

  // The 8 bytes at each lane's first tap + bytes[r]: lanes [0, N/2) in lo[r], [N/2, N) in hi[r].
  template <int R>
  void Fetch(const int64_t (&bytes)[R], V64 (&lo)[R], V64 (&hi)[R]) const {
#if HWY_TARGET <= HWY_AVX2
    // 64-bit loads into 128-bit halves, then inserts: on Zen 4 two 8-lane gathers take ~10 ns per
    // 16 lanes in L1, these loads ~6 ns (a micro-benchmark; e->cube bilinear ~7% less); on Zen 3
    // (AVX2) the 4-lane vpgatherqq were the wait behind ~40% of GatherBlocks' samples (perf).
    const unsigned char* p = reinterpret_cast<const unsigned char*>(base_);
    // (A volatile read: else gcc keeps the stored vector and extracts each lane through vector
    // registers again.)
    auto at = [&](int l) { return p + static_cast<const volatile int32_t*>(at_)[l]; };
    auto two = [&](int l, __m128i (&out)[R]) {
      const unsigned char *a = at(l), *b = at(l + 1);
      for (int r = 0; r < R; ++r) {
        const __m128i v = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(a + bytes[r]));
        out[r] = _mm_castpd_si128(_mm_loadh_pd(_mm_castsi128_pd(v), reinterpret_cast<const double*>(b + bytes[r])));
      }
    };
#if HWY_TARGET <= HWY_AVX3
    auto eight = [&](int l, V64 (&out)[R]) {
      __m128i q[4][R];
      for (int k = 0; k < 4; ++k) two(l + 2 * k, q[k]);
      for (int r = 0; r < R; ++r) {
        const __m256i a = _mm256_set_m128i(q[1][r], q[0][r]), b = _mm256_set_m128i(q[3][r], q[2][r]);
        // gcc 12's own header passes an undefined vector to the masked builtin behind this and
        // then warns that it "may be used uninitialized" (a false positive: no lane is kept).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
        out[r] = V64{_mm512_inserti64x4(_mm512_castsi256_si512(a), b, 1)};
#pragma GCC diagnostic pop
      }
    };
    eight(0, lo), eight(8, hi);
#else
    auto four = [&](int l, V64 (&out)[R]) {
      __m128i q[2][R];
      two(l, q[0]), two(l + 2, q[1]);
      for (int r = 0; r < R; ++r) out[r] = V64{_mm256_set_m128i(q[1][r], q[0][r])};
    };
    four(0, lo), four(4, hi);
#endif
#else
    const D64 d64;
    for (int r = 0; r < R; ++r) {
      const auto at = hn::Set(DI64(), bytes[r]);
      lo[r] = hn::GatherOffset(d64, base_, hn::Add(lo_, at)), hi[r] = hn::GatherOffset(d64, base_, hn::Add(hi_, at));
    }
#endif
  }

  int pb_;
  const uint64_t* base_;
  const int32_t* off_;
  int64_t m_;
#if HWY_TARGET <= HWY_AVX2
  HWY_ALIGN int32_t at_[kMaxLanes];  // first-tap offsets, 0 for lanes not sampled
#else
  hn::Vec<DI64> lo_, hi_;  // 64-bit first-tap offsets of lanes [0, N/2) and [N/2, N)
#endif
};

// The bilinear uint8 weights of a block's lanes, w = round(t 65535) along x in the low 16 bits
// and along y in the high ones (lanes not sampled: any value). Phase 2's input, and what a kept
// plan stores (planned_taps.hpp).
HWY_INLINE TapPairs::VU PackedWeightsU8(const TapBlock& blk) {
  using DF = hn::ScalableTag<float>;
  const DF df;
  const TapPairs::DU du;
  auto weight = [&](const float* t) {
    return hn::BitCast(du, hn::NearestInt(hn::Mul(hn::Load(df, t), hn::Set(df, 65535.0f))));
  };
  return hn::Or(hn::And(weight(blk.tx), hn::Set(du, 0xFFFFu)), hn::ShiftLeft<16>(weight(blk.ty)));
}

// Phase 2 for bilinear uint8 without alpha (the common photo case), all channels at once in
// 16-bit fixed point: one 8-byte read per pixel and row (TapPairs) fetches both taps (8 bytes from the
// first; the second starts pb bytes in). Channels 0, 2 and 1, 3 of each RGBx word sit in the
// two 16-bit halves of a lane, scaled by 256; weights w (PackedWeightsU8) and 65535 - w (1/65536
// px steps); each product keeps its high 16 bits. The truncations lower the result by < 0.02 LSB
// before the final rounding, so it stays within 1 LSB of the exact blend. Writes the taps' pixels at o.
HWY_INLINE void BilinearU8(const SimdSource& s, const TapPairs& taps, TapPairs::VU packed, unsigned char* o) {
  using DU = TapPairs::DU;
  using VU = TapPairs::VU;
  using D16 = hn::Repartition<uint16_t, DU>;
  using V16 = hn::Vec<D16>;
  const DU du;
  const D16 d16;
  const VU low = hn::Set(du, 0xFFFFu), high = hn::Set(du, 0xFFFF0000u);
  // Each weight in both 16-bit halves of its lane.
  const V16 wx1 = hn::BitCast(d16, hn::Or(hn::And(packed, low), hn::ShiftLeft<16>(packed)));
  const V16 wy1 = hn::BitCast(d16, hn::Or(hn::ShiftRight<16>(packed), hn::And(packed, high)));
  const V16 wx0 = hn::Not(wx1), wy0 = hn::Not(wy1);  // 65535 - w in each half
  const VU high_bytes = hn::Set(du, 0xFF00FF00u);
  V16 even[2], odd[2];  // horizontal blends of rows 0 and 1: channels 0, 2 and 1, 3, x 256
  VU first[2], second[2];  // both taps of rows 0 and 1
  taps.Get<2>({0, s.stride}, first, second);
  for (int r = 0; r < 2; ++r) {
    const VU p0 = first[r], p1 = second[r];
    const V16 e0 = hn::BitCast(d16, hn::And(hn::ShiftLeft<8>(p0), high_bytes));
    const V16 e1 = hn::BitCast(d16, hn::And(hn::ShiftLeft<8>(p1), high_bytes));
    const V16 o0 = hn::BitCast(d16, hn::And(p0, high_bytes)), o1 = hn::BitCast(d16, hn::And(p1, high_bytes));
    even[r] = hn::Add(hn::MulHigh(e0, wx0), hn::MulHigh(e1, wx1));
    odd[r] = hn::Add(hn::MulHigh(o0, wx0), hn::MulHigh(o1, wx1));
  }
  const V16 half = hn::Set(d16, 128);
  const V16 ve = hn::ShiftRight<8>(hn::Add(hn::Add(hn::MulHigh(even[0], wy0), hn::MulHigh(even[1], wy1)), half));
  const V16 vo = hn::ShiftRight<8>(hn::Add(hn::Add(hn::MulHigh(odd[0], wy0), hn::MulHigh(odd[1], wy1)), half));
  taps.Store(hn::Or(hn::BitCast(du, ve), hn::ShiftLeft<8>(hn::BitCast(du, vo))), o);
}

// Phase 2 for bicubic and Lanczos-3 uint8 without alpha, in 16-bit fixed point: 8-byte reads
// fetch two taps at a time; channels 0, 2 and 1, 3 of each word sit in the two 16-bit halves of a
// lane, scaled by 64; weights are signed Q15 (1.0 stored as 32767); products round
// (MulFixedPoint15: ~1/128 LSB each) and sums saturate, which only matters where the result
// clamps to 0 or 255 anyway (Lanczos-3's |weights| sum to <= 1.54 per axis). Within 1 LSB of the
// exact blend.
template <int K>
HWY_INLINE void SeparableU8(const SimdSource& s, const TapBlock& blk, unsigned char* o) {
  using DF = hn::ScalableTag<float>;
  using DU = TapPairs::DU;
  using VU = TapPairs::VU;
  using D16 = hn::Repartition<int16_t, DU>;
  using V16 = hn::Vec<D16>;
  const DF df;
  const DU du;
  const D16 d16;
  const int pb = s.channels;
  const TapPairs taps(s, blk.base, blk.off, blk.m);
  auto q15 = [&](hn::Vec<DF> w) {  // both 16-bit halves of each lane
    const auto q = hn::BitCast(du, hn::NearestInt(hn::Min(hn::Mul(w, hn::Set(df, 32768.0f)), hn::Set(df, 32767.0f))));
    return hn::BitCast(d16, hn::Or(hn::And(q, hn::Set(du, 0xFFFFu)), hn::ShiftLeft<16>(q)));
  };
  hn::Vec<DF> fx[K], fy[K];
  BlockWeights<K>(s, blk, df, fx, fy);
  V16 wx[K];
  for (int c = 0; c < K; ++c) wx[c] = q15(fx[c]);
  const VU mask = hn::Set(du, 0x3FC03FC0u);
  V16 ve = hn::Zero(d16), vo = hn::Zero(d16);
  for (int r = 0; r < K; ++r) {
    V16 he = hn::Zero(d16), ho = hn::Zero(d16);
    for (int q = 0; q < K / 2; ++q) {
      VU t[2];  // taps 2q and 2q + 1 of row r
      taps.Get(static_cast<int64_t>(r) * s.stride + 2 * q * pb, t[0], t[1]);
      for (int k = 0; k < 2; ++k) {
        const V16 e = hn::BitCast(d16, hn::And(hn::ShiftLeft<6>(t[k]), mask));
        const V16 od = hn::BitCast(d16, hn::And(hn::ShiftRight<2>(t[k]), mask));
        he = hn::SaturatedAdd(he, hn::MulFixedPoint15(e, wx[2 * q + k]));
        ho = hn::SaturatedAdd(ho, hn::MulFixedPoint15(od, wx[2 * q + k]));
      }
    }
    const V16 wy = q15(fy[r]);
    ve = hn::SaturatedAdd(ve, hn::MulFixedPoint15(he, wy));
    vo = hn::SaturatedAdd(vo, hn::MulFixedPoint15(ho, wy));
  }
  // Clamp to [0, 255 x 64], round away the scale.
  const V16 lo = hn::Zero(d16), top = hn::Set(d16, int16_t{255 * 64}), half = hn::Set(d16, int16_t{32});
  ve = hn::ShiftRight<6>(hn::Add(hn::Min(hn::Max(ve, lo), top), half));
  vo = hn::ShiftRight<6>(hn::Add(hn::Min(hn::Max(vo, lo), top), half));
  taps.Store(hn::Or(hn::BitCast(du, ve), hn::ShiftLeft<8>(hn::BitCast(du, vo))), o + blk.index * pb);
}
#endif

// A gray kernel's taps: the 4 bytes at p + offset for each lane, by one gather, or (x86) by
// 32-bit loads inserted into 128-bit quarters. Which is faster depends on the CPU (GathersWin).
template <class DU, class VI>
HWY_INLINE hn::Vec<DU> WordsByGather(DU du, const unsigned char* p, VI off) {
  const hn::RebindToSigned<DU> di;
  return hn::BitCast(du, hn::GatherOffset(di, reinterpret_cast<const int32_t*>(p), off));
}
#if HWY_TARGET <= HWY_AVX2
// at: the offsets in memory (read per lane: the compiler moved a vector's lanes through vector
// registers again, ~6 instructions a read).
template <class DU>
HWY_INLINE hn::Vec<DU> WordsByLoads(DU, const unsigned char* p, const int32_t* at) {
  auto word = [&](int l) {
    int32_t v;
    std::memcpy(&v, p + static_cast<const volatile int32_t*>(at)[l], sizeof v);
    return v;
  };
  auto quad = [&](int l) {
    __m128i v = _mm_cvtsi32_si128(word(l));
    v = _mm_insert_epi32(v, word(l + 1), 1);
    v = _mm_insert_epi32(v, word(l + 2), 2);
    return _mm_insert_epi32(v, word(l + 3), 3);
  };
#if HWY_TARGET <= HWY_AVX3
  __m512i z = _mm512_castsi128_si512(quad(0));
  z = _mm512_inserti32x4(z, quad(4), 1);
  z = _mm512_inserti32x4(z, quad(8), 2);
  return hn::Vec<DU>{_mm512_inserti32x4(z, quad(12), 3)};
#else
  return hn::Vec<DU>{_mm256_set_m128i(quad(4), quad(0))};
#endif
}
#endif

// Whether gathers fetch the gray kernels' taps faster than loads on this CPU, timed once per
// process (~0.1 ms, the faster of three tries each over 2048 vectors in L1): Zen 4's 16-lane
// gather took 3x the loads' time; on a Sapphire Rapids-class Xeon the loads' inserts are the
// slower (docs/decisions.md). Both fetch the same words. simd_gray_fetch() forces one (tests).
bool GathersWin() {
#if HWY_TARGET <= HWY_AVX2
  if (const int forced = simd_gray_fetch(); forced >= 0) return forced == 1;
  static const bool win = [] {
    const hn::ScalableTag<uint32_t> du;
    const hn::RebindToSigned<decltype(du)> di;
    constexpr int kVectors = 256, kBytes = 16384;
    static unsigned char buf[kBytes + 4];
    HWY_ALIGN static int32_t offs[kVectors][kMaxLanes];
    uint32_t r = 12345;
    for (auto& b : buf) b = static_cast<unsigned char>(r = r * 1103515245u + 12345u);
    for (auto& v : offs)
      for (auto& o : v) o = static_cast<int32_t>((r = r * 1103515245u + 12345u) >> 8) % kBytes;
    auto time = [&](bool gather) {
      auto acc = hn::Zero(du);
      const auto t0 = std::chrono::steady_clock::now();
      for (int rep = 0; rep < 8; ++rep)
        for (const auto& v : offs)
          acc = hn::Xor(
              acc, gather ? WordsByGather(du, buf, hn::Load(di, v)) : WordsByLoads(du, buf, v));
      const auto t = std::chrono::steady_clock::now() - t0;
      static volatile uint32_t sink;  // (the loop kept)
      sink = hn::GetLane(acc);
      return t;
    };
    auto g = time(true), l = time(false);
    for (int k = 0; k < 2; ++k) g = std::min(g, time(true)), l = std::min(l, time(false));
    return g < l;
  }();
  return win;
#else
  return true;
#endif
}

// Phase 2 for 4- and 6-tap kernels on one channel of uint8 or uint16 samples (a video's planes,
// gray images): a row's taps are consecutive samples, so a 32-bit gather fetches four uint8 taps
// or two uint16 ones (uint8 with 6 taps: a second gather at tap 2, whose last two bytes are taps 4
// and 5; no byte past the last tap is read). uint16 rows are blended in float; uint8 rows as two
// pairs of 16-bit lanes (taps 0, 2 and 1, 3) multiplied by Q14 weights and summed in 32 bits
// (pmaddwd), the rows then in float: each weight's rounding (at most 2^-15) moves a result by
// under 0.04 LSB. Writes the block's pixels.
template <class T, int K>
HWY_INLINE void GrayTaps(const SimdSource& s, const TapBlock& blk, unsigned char* o, bool gather) {
  static_assert(K == 4 || K == 6);
  using DF = hn::ScalableTag<float>;
  using DI = hn::RebindToSigned<DF>;
  using DU = hn::RebindToUnsigned<DF>;
  using VF = hn::Vec<DF>;
  const DF df;
  const DI di;
  const DU du;
  constexpr int kPerWord = 4 / static_cast<int>(sizeof(T));
  VF fx[K], fy[K];
  BlockWeights<K>(s, blk, df, fx, fy);
  const auto at = hn::Load(di, blk.off);
  const auto sampled = hn::Gt(at, hn::Set(di, -1));
  const auto off0 = hn::Max(at, hn::Zero(di));  // lanes not sampled read the base row
  const auto mask = hn::Set(du, sizeof(T) == 1 ? 0xFFu : 0xFFFFu);
  auto tap = [&](hn::Vec<DU> word, int k) {
    return hn::ConvertTo(
        df, hn::BitCast(
                di, hn::And(hn::ShiftRightSame(word, 8 * static_cast<int>(sizeof(T)) * k), mask)));
  };
  HWY_ALIGN int32_t at_lanes[kMaxLanes];
  hn::Store(off0, di, at_lanes);
  auto words = [&](int64_t add) {
#if HWY_TARGET <= HWY_AVX2
    if (!gather) return WordsByLoads(du, blk.base + add, at_lanes);
#endif
    return WordsByGather(du, blk.base + add, off0);
  };
  VF acc = hn::Zero(df);
#if HWY_TARGET != HWY_SCALAR
  constexpr bool kPairs = sizeof(T) == 1;
#else
  constexpr bool kPairs = false;
#endif
  if constexpr (kPairs) {
#if HWY_TARGET != HWY_SCALAR
    const hn::Repartition<int16_t, DI> d16;
    auto q14 = [&](VF w) { return hn::NearestInt(hn::Mul(w, hn::Set(df, 16384.0f))); };
    auto pair = [&](hn::Vec<DI> low, hn::Vec<DI> high) {
      return hn::BitCast(d16, hn::Or(hn::And(low, hn::Set(di, 0xFFFF)), hn::ShiftLeft<16>(high)));
    };
    // The second word (6 taps) is read at tap 2: its taps 2 and 3 weigh 0 there.
    const auto none = hn::Zero(di);
    const auto w02 = pair(q14(fx[0]), q14(fx[2])), w13 = pair(q14(fx[1]), q14(fx[3]));
    const auto w24 = pair(none, q14(fx[K == 6 ? 4 : 0])), w35 = pair(none, q14(fx[K == 6 ? 5 : 0]));
    const auto low_bytes = hn::Set(du, 0x00FF00FFu);
    for (int r = 0; r < K; ++r) {
      hn::Vec<DI> sum = none, more = none;
      auto blend = [&](int64_t add, decltype(w02) we, decltype(w02) wo) {
        const auto word = words(r * s.stride + add);
        const auto even = hn::BitCast(d16, hn::And(word, low_bytes));
        const auto odd = hn::BitCast(d16, hn::And(hn::ShiftRight<8>(word), low_bytes));
        sum = hn::ReorderWidenMulAccumulate(di, even, we, sum, more);
        sum = hn::ReorderWidenMulAccumulate(di, odd, wo, sum, more);
      };
      blend(0, w02, w13);
      if constexpr (K == 6) blend(2, w24, w35);
      const VF h = hn::ConvertTo(df, hn::RearrangeToOddPlusEven(sum, more));
      acc = hn::MulAdd(h, hn::Mul(fy[r], hn::Set(df, 1.0f / 16384)), acc);
    }
#endif
  } else {
    for (int r = 0; r < K; ++r) {
      VF h = hn::Zero(df);
      for (int first = 0; first < K; first += kPerWord) {
        const int from = std::min(first, K - kPerWord);  // the word's first tap
        const auto word = words(r * s.stride + from * static_cast<int64_t>(sizeof(T)));
        for (int k = first; k < std::min(first + kPerWord, K); ++k)
          h = hn::MulAdd(tap(word, k - from), fx[k], h);
      }
      acc = hn::MulAdd(h, fy[r], acc);
    }
  }
  const float unit = sizeof(T) == 1 ? 255.0f : 65535.0f;
  const auto v = hn::IfThenElseZero(
      sampled, hn::NearestInt(hn::Min(hn::Max(acc, hn::Zero(df)), hn::Set(df, unit))));
  const hn::Rebind<T, DI> dt;
  T* to = reinterpret_cast<T*>(o) + blk.index;
  // (A whole block stored as is: a copy of a size known only at run time is a call.)
  if (blk.m == static_cast<int64_t>(hn::Lanes(dt))) return hn::StoreU(hn::DemoteTo(dt, v), dt, to);
  HWY_ALIGN T samples[hn::MaxLanes(dt)];
  hn::Store(hn::DemoteTo(dt, v), dt, samples);
  std::memcpy(to, samples, sizeof(T) * static_cast<size_t>(blk.m));
}

// Phase 2: gathers and blends one block's taps, writes its m output pixels (0 where not sampled
// here: misses and invalid lanes). gather: GathersWin().
template <PixelType PT, class T, int K>
HWY_INLINE void GatherBlock(const SimdSource& s, const TapBlock& blk, unsigned char* out,
                            bool gather) {
  (void)gather;  // (the gray kernels' alone)
  using DF = hn::ScalableTag<float>;
  using DI = hn::RebindToSigned<DF>;
  using VF = hn::Vec<DF>;
  using VI = hn::Vec<DI>;
  const DF df;
  const DI di;
  const int nc = s.channels, alpha = s.alpha;
  const int pb = nc * static_cast<int>(sizeof(T));
  const unsigned char* base = blk.base;
  const int64_t m = blk.m;
  if (!blk.any) {
    std::memset(out + blk.index * pb, 0, static_cast<size_t>(m * pb));
    return;
  }
#if HWY_TARGET != HWY_SCALAR
  if constexpr (PT == PixelType::U8 && K == 2) {
    if (alpha < 0) return BilinearU8(s, TapPairs(s, blk.base, blk.off, blk.m), PackedWeightsU8(blk), out + blk.index * pb);
  } else if constexpr (PT == PixelType::U8 && (K == 4 || K == 6)) {
    if (alpha < 0 && !s.dering)
      return nc == 1 ? GrayTaps<uint8_t, K>(s, blk, out, gather) : SeparableU8<K>(s, blk, out);
  } else if constexpr (PT == PixelType::U8 && K > 2) {
    if (alpha < 0 && !s.dering) return SeparableU8<K>(s, blk, out);
  } else if constexpr (PT == PixelType::U16 && (K == 4 || K == 6)) {
    if (alpha < 0 && !s.dering && nc == 1) return GrayTaps<uint16_t, K>(s, blk, out, gather);
  }
#endif
  unsigned char* o = out + blk.index * pb;
  if constexpr (K == 1) {
    if (pb <= 4) {  // one 32-bit gather per pixel, its first pb bytes kept
      const VI at = hn::Load(di, blk.off);
      const VI word = hn::IfThenElseZero(hn::Gt(at, hn::Set(di, -1)),
                                         hn::GatherOffset(di, reinterpret_cast<const int32_t*>(base), hn::Max(at, hn::Zero(di))));
      const hn::RebindToUnsigned<DI> du;
      return StorePixels(du, hn::BitCast(du, word), m, pb, o);
    }
    for (int64_t l = 0; l < m; ++l) {
      if (blk.off[l] >= 0) std::memcpy(o + l * pb, base + blk.off[l], static_cast<size_t>(pb));
      else std::memset(o + l * pb, 0, static_cast<size_t>(pb));
    }
  } else {
    const float unit = PT == PixelType::U8 ? 255.0f : (PT == PixelType::U16 ? 65535.0f : 1.0f);
    VF wx[K], wy[K];
    BlockWeights<K>(s, blk, df, wx, wy);
    const VI stride = hn::Set(di, static_cast<int32_t>(s.stride));
    const VI off0 = hn::Max(hn::Load(di, blk.off), hn::Zero(di));  // lanes not sampled read the base row
    VF acc[4] = {hn::Zero(df), hn::Zero(df), hn::Zero(df), hn::Zero(df)};
    // Dering: the range of the central 2x2 taps' (premultiplied) values, per channel.
    VF lo[4], hi[4];
    for (int c2 = 0; c2 < 4; ++c2) lo[c2] = hn::Set(df, HUGE_VALF), hi[c2] = hn::Set(df, -HUGE_VALF);
    for (int r = 0; r < K; ++r) {
      const VI row = hn::Add(off0, hn::Mul(hn::Set(di, r), stride));
      for (int c = 0; c < K; ++c) {
        const VI at = hn::Add(row, hn::Set(di, c * pb));
        const VF w = hn::Mul(wy[r], wx[c]);
        const VI word = PT == PixelType::U8 ? hn::GatherOffset(di, reinterpret_cast<const int32_t*>(base), at)
                                            : hn::Zero(di);
        VF a = hn::Set(df, 1.0f);
        if (alpha >= 0) a = hn::Mul(LoadChannel<PT>(df, base, at, alpha, word), hn::Set(df, 1.0f / unit));
        const bool central = s.dering && (r == K / 2 - 1 || r == K / 2) && (c == K / 2 - 1 || c == K / 2);
        for (int c2 = 0; c2 < nc; ++c2) {
          const VF v = LoadChannel<PT>(df, base, at, c2, word);
          acc[c2] = hn::MulAdd(c2 == alpha ? w : hn::Mul(w, a), v, acc[c2]);
          if (central) {
            const VF tap = c2 == alpha ? v : hn::Mul(v, a);
            lo[c2] = hn::Min(lo[c2], tap), hi[c2] = hn::Max(hi[c2], tap);
          }
        }
      }
    }
    if (s.dering)
      for (int c2 = 0; c2 < nc; ++c2) acc[c2] = hn::Min(hn::Max(acc[c2], lo[c2]), hi[c2]);
    // Unpremultiply, round and clamp in vectors; the scalar loop below only narrows and stores.
    if (alpha >= 0) {
      const VF a = hn::Mul(acc[alpha], hn::Set(df, 1.0f / unit));
      const auto has = hn::Gt(a, hn::Set(df, 1e-12f));
      const VF inv = hn::Div(hn::Set(df, 1.0f), hn::IfThenElse(has, a, hn::Set(df, 1.0f)));
      for (int c2 = 0; c2 < nc; ++c2)
        if (c2 != alpha) acc[c2] = hn::IfThenElseZero(has, hn::Mul(acc[c2], inv));
      acc[alpha] = hn::Mul(hn::Min(hn::Max(a, hn::Zero(df)), hn::Set(df, 1.0f)), hn::Set(df, unit));
    }
    const auto valid = hn::Gt(hn::Load(di, blk.off), hn::Set(di, -1));
    if constexpr (PT == PixelType::U8) {
      // Channels packed into one little-endian word per pixel.
      VI word = hn::Zero(di);
      for (int c2 = 0; c2 < nc; ++c2)
        word = hn::Or(word, hn::ShiftLeftSame(hn::NearestInt(hn::Min(hn::Max(acc[c2], hn::Zero(df)), hn::Set(df, unit))), 8 * c2));
      word = hn::IfThenElseZero(valid, word);
      StorePixels(hn::RebindToUnsigned<DI>(), hn::BitCast(hn::RebindToUnsigned<DI>(), word), m, pb, o);
    } else if constexpr (PT == PixelType::U16) {
      HWY_ALIGN int32_t q[4][kMaxLanes] = {};  // (zeroed: gcc cannot see nc <= 4 stores cover it)
      for (int c2 = 0; c2 < nc; ++c2)
        hn::Store(hn::IfThenElseZero(valid, hn::NearestInt(hn::Min(hn::Max(acc[c2], hn::Zero(df)), hn::Set(df, unit)))), di, q[c2]);
      for (int64_t l = 0; l < m; ++l) {
        T* p = reinterpret_cast<T*>(o + l * pb);
        for (int c2 = 0; c2 < nc; ++c2) p[c2] = static_cast<T>(q[c2][l]);
      }
    } else {
      HWY_ALIGN float res[4][kMaxLanes];
      for (int c2 = 0; c2 < nc; ++c2) hn::Store(acc[c2], df, res[c2]);
      for (int64_t l = 0; l < m; ++l) {
        unsigned char* p = o + l * pb;
        const bool valid = blk.off[l] >= 0;
        for (int c2 = 0; c2 < nc; ++c2) StoreSample<T>(p + c2 * sizeof(T), valid ? res[c2][l] : 0.0f);
      }
    }
  }
}

// Rows of a rect in chunks of kChunkBlocks blocks: phase 1 for the chunk's rows, then phase 2
// for its blocks. The chunk's planning time is the prefetch distance. Phase 1 (the geometry, the
// same for every pixel type and kernel: K is a value there) is compiled once per target; phase
// 2 per type and kernel.
template <PixelType PT, class T, int K>
HWY_NOINLINE void GatherBlocks(const SimdSource& s, const TapBlock* blocks, int n, int64_t w, unsigned char* out,
                               int64_t out_stride) {
  const int64_t pb = s.channels * static_cast<int64_t>(sizeof(T));
  int64_t j = n > 0 ? blocks[0].index / w : 0;  // the blocks' row: they come in row-major order
  const bool gather = GathersWin();
  for (int q = 0; q < n; ++q) {
    while (blocks[q].index >= (j + 1) * w) ++j;
    GatherBlock<PT, T, K>(s, blocks[q], out + j * out_stride - j * w * pb, gather);
  }
}

template <PixelType PT, class T, int K>
struct GatherF {
  template <class... A>
  static void run(A&&... a) { GatherBlocks<PT, T, K>(a...); }
};

template <template <PixelType, class, int> class F, class... A>
void Dispatch(PixelType t, Interp k, A&&... args);

// The footprint kernel's widths for the lanes of a block from rect pixel (i, j) on, as
// FootprintField::at computes them.
HWY_INLINE void FieldLanes(const FootprintField& f, int64_t i, int64_t j, TapBlock& blk) {
  using DF = hn::ScalableTag<float>;
  using VF = hn::Vec<DF>;
  const DF df;
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), two = hn::Set(df, 2.0f);
  const VF col = hn::Add(hn::Iota(df, 0.0f), hn::Set(df, static_cast<float>(i)));
  const VF u = hn::Min(hn::Max(hn::MulAdd(col, hn::Set(df, f.du), hn::Set(df, f.u0)), zero), two);
  // The row's blend of the points' rows (scalar), then per lane of the three columns.
  const float v = std::clamp(f.v0 + static_cast<float>(j) * f.dv, 0.0f, 2.0f);
  float cx[3] = {}, cy[3] = {};
  for (int r = 0; r < 3; ++r) {
    const float hv = std::max(0.0f, 1.0f - std::fabs(v - static_cast<float>(r)));
    for (int c = 0; c < 3; ++c) cx[c] += hv * f.ex[3 * r + c], cy[c] += hv * f.ey[3 * r + c];
  }
  VF wx = zero, wy = zero;
  for (int c = 0; c < 3; ++c) {
    const VF hu = hn::Max(zero, hn::Sub(one, hn::Abs(hn::Sub(u, hn::Set(df, static_cast<float>(c))))));
    wx = hn::MulAdd(hu, hn::Set(df, cx[c]), wx), wy = hn::MulAdd(hu, hn::Set(df, cy[c]), wy);
  }
  const VF scale = hn::Set(df, f.scale), reach = hn::Set(df, static_cast<float>(kFootprintReach));
  hn::Store(hn::Min(hn::Max(hn::Mul(wx, scale), one), reach), df, blk.ex);
  hn::Store(hn::Min(hn::Max(hn::Mul(wy, scale), one), reach), df, blk.ey);
}

// Phase 1 for rows [j0, j1) of a tile map's rect.
HWY_NOINLINE int PlanMapRows(const SimdSource& s, int K, const TileMap& tm, int64_t j0, int64_t j1, TapBlock* blk,
                             SimdMisses& misses) {
  const DD dd;
  const auto N = static_cast<int64_t>(hn::Lanes(dd));
  const PixelRect& rect = tm.rect;
  const Bounds<DD> b(s);
  HWY_ALIGN double bx[kMaxLanes], by[kMaxLanes], bo[kMaxLanes];
  ChunkMisses chunk;
  int n = 0;
  for (int64_t j = j0; j < j1; ++j)
    for (int64_t i = 0; i < rect.width(); i += N) {
      const int64_t m = std::min(N, rect.width() - i);
      const size_t k = static_cast<size_t>(j * rect.width() + i);
      for (int64_t l = 0; l < N; ++l) {
        bx[l] = l < m ? tm.xs[k + l] : 0.0;
        by[l] = l < m ? tm.ys[k + l] : 0.0;
        bo[l] = l < m && tm.ok[k + l] ? 1.0 : 0.0;
      }
      if (s.footprint) FieldLanes(*s.footprint, i, j, blk[n]);
      PlanLanes(s, K, b, hn::Load(dd, bx), hn::Load(dd, by), hn::Ne(hn::Load(dd, bo), hn::Zero(dd)),
                j * rect.width() + i, m, blk[n++], chunk);
    }
  chunk.append_to(misses);
  return n;
}

// Phase 1 for rows [j0, j1) of a fused tile: the geometry in registers, then the taps.
HWY_NOINLINE int PlanFusedRows(const SimdSource& s, int K, const TileRows& rows,
                               const PixelRect& rect, int64_t j0, int64_t j1, TapBlock* blk,
                               SimdMisses& misses) {
  const Bounds<DD> bd(s);
  const Bounds<hn::ScalableTag<float>> bf(s);
  ChunkMisses chunk;
  int n = 0;
  for (int64_t j = j0; j < j1; ++j)
    rows.Row(rect.y0 + j, [&](auto sx, auto sy, auto ok, int64_t i, int64_t m) {
      if (s.footprint) FieldLanes(*s.footprint, i, j, blk[n]);
      if constexpr (std::is_same_v<hn::TFromV<decltype(sx)>, float>) {
        PlanLanes(s, K, bf, sx, sy, ok, j * rect.width() + i, m, blk[n++], chunk);
      } else {
        PlanLanes(s, K, bd, sx, sy, ok, j * rect.width() + i, m, blk[n++], chunk);
      }
    });
  chunk.append_to(misses);
  return n;
}

// Chunks of rows of rect: plan(j0, j1, blocks) -> block count, then the gathers.
template <class Plan>
void Chunked(const SimdSource& s, Interp interp, const PixelRect& rect, int64_t blocks_per_row,
             unsigned char* out, int64_t out_stride, Plan&& plan) {
  if (blocks_per_row > kChunkBlocks)  // a row must fit a chunk: rects up to kTile wide do
    throw InternalError("a " + std::to_string(rect.width()) +
                        "-px rect is wider than the SIMD sampler's chunks (at most " +
                        std::to_string(kTile) + ")");
  TapBlock blocks[kChunkBlocks];
  const int64_t rows = std::max<int64_t>(1, kChunkBlocks / blocks_per_row);
  for (int64_t j0 = 0; j0 < rect.height(); j0 += rows) {
    const int n = plan(j0, std::min(rect.height(), j0 + rows), blocks);
    Dispatch<GatherF>(s.type, interp, s, static_cast<const TapBlock*>(blocks), n, rect.width(), out,
                      out_stride);
  }
}

// Calls F<PT, T, K>::run(args...) for the source's type and the kernel.
template <template <PixelType, class, int> class F, class... A>
void Dispatch(PixelType t, Interp k, A&&... args) {
  auto with_type = [&](auto pt, auto tag) {
    using T = typename decltype(tag)::type;
    constexpr PixelType PT = decltype(pt)::value;
    switch (kernel_of(k)) {
      case Interp::Nearest: return F<PT, T, 1>::run(args...);
      case Interp::Bilinear: return F<PT, T, 2>::run(args...);
      case Interp::Bicubic: return F<PT, T, 4>::run(args...);
      case Interp::Lanczos3: return F<PT, T, 6>::run(args...);
      default: return;
    }
  };
  switch (t) {
    case PixelType::U8: return with_type(std::integral_constant<PixelType, PixelType::U8>{}, std::type_identity<uint8_t>{});
    case PixelType::U16: return with_type(std::integral_constant<PixelType, PixelType::U16>{}, std::type_identity<uint16_t>{});
    case PixelType::F16: return with_type(std::integral_constant<PixelType, PixelType::F16>{}, std::type_identity<Imath::half>{});
    case PixelType::F32: return with_type(std::integral_constant<PixelType, PixelType::F32>{}, std::type_identity<float>{});
  }
}

// The kernel of interp, or the footprint kernel on its taps (of the kernel with that support).
Interp KernelFor(Interp k, const FootprintField* footprint) {
  return footprint ? kFootprintGrid : k;
}

void SampleMap(const SimdSource& source, Interp interp, const TileMap& tm, unsigned char* out, int64_t out_stride,
               SimdMisses& misses, const FootprintField* footprint) {
  SimdSource s = source;
  s.dering = derings(interp) && !footprint, s.footprint = footprint;
  const Interp k = KernelFor(interp, footprint);
  const auto N = static_cast<int64_t>(hn::Lanes(DD()));
  Chunked(s, k, tm.rect, (tm.rect.width() + N - 1) / N, out, out_stride,
          [&](int64_t j0, int64_t j1, TapBlock* blk) {
            return PlanMapRows(s, support(k), tm, j0, j1, blk, misses);
          });
}

// Copies n planned blocks' taps and weights (compact) or fractions into record (PlannedTaps' layout).
HWY_NOINLINE void RecordBlocks(const TapBlock* blocks, int n, PlannedTaps& record) {
  for (int q = 0; q < n; ++q) {
    const TapBlock& b = blocks[q];
    const auto at = static_cast<size_t>(b.index), bytes = static_cast<size_t>(b.m) * 4;
    std::memcpy(record.off.data() + at, b.off, bytes);
#if HWY_TARGET != HWY_SCALAR
    if (record.compact) {
      HWY_ALIGN uint32_t w[kMaxLanes];
      hn::Store(PackedWeightsU8(b), TapPairs::DU(), w);
      std::memcpy(record.weights.data() + at, w, bytes);
      continue;
    }
#endif
    std::memcpy(record.tx.data() + at, b.tx, bytes);
    std::memcpy(record.ty.data() + at, b.ty, bytes);
  }
}

// How far ahead of its replay a kept array is prefetched (a frame's are past the caches).
inline constexpr int64_t kKeptAhead = 512;  // pixels

// The pixels of rect from kept fractions: chunks of blocks filled from the record (the
// footprint kernel's widths from its field, as phase 1), their taps prefetched, then phase 2.
template <PixelType PT, class T, int K>
struct ReplayF {
  static void run(const PlannedTaps& p, const PixelRect& rect, const SimdSource& s,
                  unsigned char* out, int64_t out_stride) {
    const hn::ScalableTag<float> df;
    const hn::ScalableTag<int32_t> di;
    const auto N = static_cast<int64_t>(hn::Lanes(df));
    const int64_t pb = s.channels * static_cast<int64_t>(sizeof(T)),
                  total = rect.width() * rect.height();
    TapBlock blocks[kChunkBlocks];
    int n = 0;
    for (int64_t j = 0; j < rect.height(); ++j)
      for (int64_t i = 0; i < rect.width(); i += N) {
        const int64_t at = j * rect.width() + i, m = std::min(N, rect.width() - i);
        TapBlock& b = blocks[n++];
        const int64_t ahead = std::min(at + kKeptAhead, total - 1);  // (inside the arrays)
        hwy::Prefetch(p.off.data() + ahead);
        hwy::Prefetch(p.tx.data() + ahead);
        hwy::Prefetch(p.ty.data() + ahead);
        b.base = s.base, b.index = at, b.m = m;
        // (Vectors, not memcpy of a size known only at run time: a call each. Lanes past m:
        // unused.)
        hn::Store(hn::LoadU(di, p.off.data() + at), di, b.off);
        hn::Store(hn::LoadU(df, p.tx.data() + at), df, b.tx);
        hn::Store(hn::LoadU(df, p.ty.data() + at), df, b.ty);
        if (s.footprint) FieldLanes(*s.footprint, i, j, b);
        // The first and last sampled lanes' taps (most blocks: every lane sampled).
        const size_t sampled =
            hn::CountTrue(di, hn::And(hn::FirstN(di, static_cast<size_t>(m)),
                                      hn::Gt(hn::Load(di, b.off), hn::Set(di, -1))));
        b.any = sampled > 0;
        int32_t first = b.off[0], last = b.off[m - 1];
        if (b.any && sampled < static_cast<size_t>(m)) {
          first = last = -1;
          for (int64_t l = 0; l < m; ++l)
            if (b.off[l] >= 0) last = b.off[l], first = first < 0 ? last : first;
        }
        for (int r = 0; b.any && r < K; ++r) {
          hwy::Prefetch(s.base + first + r * s.stride);
          hwy::Prefetch(s.base + last + r * s.stride + (K - 1) * pb);
        }
        if (n == kChunkBlocks || (j == rect.height() - 1 && i + N >= rect.width())) {
          GatherBlocks<PT, T, K>(s, blocks, n, rect.width(), out, out_stride);
          n = 0;
        }
      }
  }
};

#if HWY_TARGET != HWY_SCALAR
// The pixels of rect from kept compact taps: phase 2 alone, each vector's taps prefetched a few
// rows ahead (the planning's prefetches did that before).
HWY_NOINLINE void ReplayCompact(const PlannedTaps& p, const PixelRect& rect, const SimdSource& s,
                                unsigned char* out, int64_t out_stride) {
  const TapPairs::DU du;
  const auto N = static_cast<int64_t>(hn::Lanes(du));
  const int64_t pb = s.channels, total = rect.width() * rect.height();
  constexpr int64_t kAhead = 4 * kTile;  // pixels
  static_assert(kMaxLanes <= PlannedTaps::kPad);
  const int32_t* off = p.off.data();
  for (int64_t j = 0; j < rect.height(); ++j) {
    unsigned char* row = out + j * out_stride;
    for (int64_t i = 0; i < rect.width(); i += N) {
      const int64_t at = j * rect.width() + i, m = std::min(N, rect.width() - i);
      if (at + kAhead + N <= total) {
        const int32_t first = off[at + kAhead], last = off[at + kAhead + N - 1];
        if (first >= 0) hwy::Prefetch(s.base + first), hwy::Prefetch(s.base + first + s.stride);
        if (last >= 0) hwy::Prefetch(s.base + last + pb), hwy::Prefetch(s.base + last + pb + s.stride);
      }
      BilinearU8(s, TapPairs(s, s.base, off + at, m), hn::LoadU(du, p.weights.data() + at), row + i * pb);
    }
  }
}
#endif

void Convert(const SimdGeometry& g, const PixelRect& rect, const SimdSource& source, Interp interp,
             unsigned char* out, int64_t out_stride, SimdMisses& misses,
             const FootprintField* footprint, PlannedTaps* record) {
  SimdSource s = source;
  s.dering = derings(interp) && !footprint, s.footprint = footprint;
  const Interp k = KernelFor(interp, footprint);
  const auto NF = static_cast<int64_t>(hn::Lanes(hn::ScalableTag<float>())), ND = static_cast<int64_t>(hn::Lanes(DD()));
  const TileRows rows(g, rect, grid_suits(s.type));
  // A coarse float vector becomes NF / ND double blocks.
  Chunked(s, k, rect, (rect.width() + NF - 1) / NF * ((NF + ND - 1) / ND), out, out_stride,
          [&](int64_t j0, int64_t j1, TapBlock* blk) {
            const int n = PlanFusedRows(s, support(k), rows, rect, j0, j1, blk, misses);
            if (record) RecordBlocks(blk, n, *record);
            return n;
          });
}

bool KeepsTaps(const SimdSource& s) { return Bounds<DD>(s).whole; }

bool KeepsCompactTaps(const SimdSource& s, Interp interp, const FootprintField* footprint) {
  // (The scalar target has no fixed-point bilinear kernel.)
  return HWY_TARGET != HWY_SCALAR && s.type == PixelType::U8 && s.alpha < 0 && interp == Interp::Bilinear && !footprint;
}

void ReplayTaps(const PlannedTaps& p, const PixelRect& rect, const SimdSource& source,
                Interp interp, const FootprintField* footprint, unsigned char* out,
                int64_t out_stride) {
  SimdSource s = source;
  s.dering = derings(interp) && !footprint, s.footprint = footprint;
#if HWY_TARGET != HWY_SCALAR
  if (p.compact) return ReplayCompact(p, rect, s, out, out_stride);
#endif
  if (p.compact) throw InternalError("compact planned taps replayed on the scalar target");
  Dispatch<ReplayF>(s.type, KernelFor(interp, footprint), p, rect, static_cast<const SimdSource&>(s), out, out_stride);
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace panoproj {
namespace {
std::atomic<int> gray_fetch{-1};
}  // namespace

int simd_gray_fetch() {
  return gray_fetch.load(std::memory_order_relaxed);
}
void set_simd_gray_fetch(int fetch) {
  gray_fetch.store(fetch, std::memory_order_relaxed);
}

HWY_EXPORT(SampleMap);
HWY_EXPORT(Convert);
HWY_EXPORT(TargetName);
HWY_EXPORT(KeepsTaps);
HWY_EXPORT(KeepsCompactTaps);
HWY_EXPORT(ReplayTaps);

void simd_sample(const SimdSource& src, Interp interp, const TileMap& tm, unsigned char* out, int64_t out_stride,
                 SimdMisses& misses, const FootprintField* footprint) {
  HWY_DYNAMIC_DISPATCH(SampleMap)(src, interp, tm, out, out_stride, misses, footprint);
}

void simd_convert(const SimdGeometry& g, const PixelRect& rect, const SimdSource& src,
                  Interp interp, unsigned char* out, int64_t out_stride, SimdMisses& misses,
                  const FootprintField* footprint, PlannedTaps* record) {
  HWY_DYNAMIC_DISPATCH(Convert)(g, rect, src, interp, out, out_stride, misses, footprint, record);
}

bool keeps_taps(const SimdSource& src) { return HWY_DYNAMIC_DISPATCH(KeepsTaps)(src); }

bool keeps_compact_taps(const SimdSource& src, Interp interp, const FootprintField* footprint) {
  return HWY_DYNAMIC_DISPATCH(KeepsCompactTaps)(src, interp, footprint);
}

void simd_replay(const PlannedTaps& taps, const PixelRect& rect, const SimdSource& src,
                 Interp interp, const FootprintField* footprint, unsigned char* out,
                 int64_t out_stride) {
  HWY_DYNAMIC_DISPATCH(ReplayTaps)(taps, rect, src, interp, footprint, out, out_stride);
}

const char* simd_target_name() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace panoproj
#endif
