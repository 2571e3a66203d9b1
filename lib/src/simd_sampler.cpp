// Highway kernels for simd_sampler.hpp, compiled once per target (foreach_target) and chosen at
// run time. Arithmetic in float; the reference (double) agrees within the bounds stated in
// tests/engine_test.cpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "simd_sampler.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// Order matters: foreach_target re-includes this file once per target.
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "simd_sampler.hpp"

HWY_BEFORE_NAMESPACE();
namespace panoproj {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;

// Tap weights for fractional offset t in [0, 1) from the left centre.
template <int K>
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

// Exact half -> float for finite values (inf/NaN become inf/NaN): shift the 15 magnitude bits
// into a float's place and rescale by 2^112 (handles subnormals), then restore the sign.
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
template <PixelType T>
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

template <PixelType PT, class T, int K>
void SampleRowT(const SimdSource& s, const float* xs, const float* ys, const uint8_t* ok,
                int64_t n, unsigned char* out) {
  const DF df;
  const DI di;
  const size_t N = hn::Lanes(df);
  const int nc = s.channels, alpha = s.alpha;
  const int pb = nc * static_cast<int>(sizeof(T));
  const float unit = PT == PixelType::U8 ? 255.0f : (PT == PixelType::U16 ? 65535.0f : 1.0f);
  const VF half = hn::Set(df, 0.5f);
  const VI stride = hn::Set(di, static_cast<int32_t>(s.stride)), vpb = hn::Set(di, pb);
  HWY_ALIGN float res[4][kMaxSimdLanes];
  for (int64_t i = 0; i < n; i += static_cast<int64_t>(N)) {
    const VF X = hn::Sub(hn::LoadU(df, xs + i), half), Y = hn::Sub(hn::LoadU(df, ys + i), half);
    const VF fx = hn::Floor(X), fy = hn::Floor(Y);
    VF wx[K], wy[K];
    Weights<K>(df, hn::Sub(X, fx), wx);
    Weights<K>(df, hn::Sub(Y, fy), wy);
    const VI ix = hn::Sub(hn::ConvertTo(di, fx), hn::Set(di, K / 2 - 1));
    const VI iy = hn::Sub(hn::ConvertTo(di, fy), hn::Set(di, K / 2 - 1));
    const VI off0 = hn::Add(hn::Mul(iy, stride), hn::Mul(ix, vpb));
    VF acc[4] = {hn::Zero(df), hn::Zero(df), hn::Zero(df), hn::Zero(df)};
    for (int r = 0; r < K; ++r) {
      const VI row = hn::Add(off0, hn::Mul(hn::Set(di, r), stride));
      for (int c = 0; c < K; ++c) {
        const VI off = hn::Add(row, hn::Set(di, c * pb));
        const VF w = hn::Mul(wy[r], wx[c]);
        const VI word = PT == PixelType::U8
                            ? hn::GatherOffset(di, reinterpret_cast<const int32_t*>(s.base), off)
                            : hn::Zero(di);
        VF a = hn::Set(df, 1.0f);
        if (alpha >= 0) a = hn::Mul(LoadChannel<PT>(df, s.base, off, alpha, word), hn::Set(df, 1.0f / unit));
        for (int ch = 0; ch < nc; ++ch) {
          const VF v = LoadChannel<PT>(df, s.base, off, ch, word);
          acc[ch] = hn::MulAdd(ch == alpha ? w : hn::Mul(w, a), v, acc[ch]);
        }
      }
    }
    // Unpremultiply, round and clamp in vectors; the scalar loop below only narrows and stores.
    if (alpha >= 0) {
      const VF a = hn::Mul(acc[alpha], hn::Set(df, 1.0f / unit));
      const auto has = hn::Gt(a, hn::Set(df, 1e-12f));
      const VF inv = hn::Div(hn::Set(df, 1.0f), hn::IfThenElse(has, a, hn::Set(df, 1.0f)));
      for (int ch = 0; ch < nc; ++ch)
        if (ch != alpha) acc[ch] = hn::IfThenElseZero(has, hn::Mul(acc[ch], inv));
      acc[alpha] = hn::Mul(hn::Min(hn::Max(a, hn::Zero(df)), hn::Set(df, 1.0f)), hn::Set(df, unit));
    }
    const int64_t m = std::min<int64_t>(static_cast<int64_t>(N), n - i);
    if constexpr (std::is_integral_v<T>) {
      HWY_ALIGN int32_t q[4][kMaxSimdLanes];
      for (int ch = 0; ch < nc; ++ch) {
        const VF c = hn::Min(hn::Max(acc[ch], hn::Zero(df)), hn::Set(df, unit));
        hn::Store(hn::NearestInt(c), di, q[ch]);
      }
      for (int64_t l = 0; l < m; ++l) {
        T* p = reinterpret_cast<T*>(out + (i + l) * pb);
        const bool valid = ok[i + l] != 0;
        for (int ch = 0; ch < nc; ++ch) p[ch] = valid ? static_cast<T>(q[ch][l]) : T{0};
      }
    } else {
      for (int ch = 0; ch < nc; ++ch) hn::Store(acc[ch], df, res[ch]);
      for (int64_t l = 0; l < m; ++l) {
        unsigned char* p = out + (i + l) * pb;
        const bool valid = ok[i + l] != 0;
        for (int ch = 0; ch < nc; ++ch) StoreSample<T>(p + ch * sizeof(T), valid ? res[ch][l] : 0.0f);
      }
    }
  }
}

template <PixelType PT, class T>
void SampleRowK(const SimdSource& s, Interp k, const float* xs, const float* ys, const uint8_t* ok,
                int64_t n, unsigned char* out) {
  switch (k) {
    case Interp::Bilinear: return SampleRowT<PT, T, 2>(s, xs, ys, ok, n, out);
    case Interp::Bicubic: return SampleRowT<PT, T, 4>(s, xs, ys, ok, n, out);
    case Interp::Lanczos3: return SampleRowT<PT, T, 6>(s, xs, ys, ok, n, out);
    case Interp::Nearest: return;  // the engine copies pixels itself
  }
}

void SampleRow(const SimdSource& s, Interp k, const float* xs, const float* ys, const uint8_t* ok,
               int64_t n, unsigned char* out) {
  switch (s.type) {
    case PixelType::U8: return SampleRowK<PixelType::U8, uint8_t>(s, k, xs, ys, ok, n, out);
    case PixelType::U16: return SampleRowK<PixelType::U16, uint16_t>(s, k, xs, ys, ok, n, out);
    case PixelType::F16: return SampleRowK<PixelType::F16, Imath::half>(s, k, xs, ys, ok, n, out);
    case PixelType::F32: return SampleRowK<PixelType::F32, float>(s, k, xs, ys, ok, n, out);
  }
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace panoproj
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace panoproj {
HWY_EXPORT(SampleRow);
HWY_EXPORT(TargetName);

void simd_sample(const SimdSource& src, Interp interp, const float* xs, const float* ys,
                 const uint8_t* ok, int64_t n, unsigned char* out) {
  HWY_DYNAMIC_DISPATCH(SampleRow)(src, interp, xs, ys, ok, n, out);
}

const char* simd_target_name() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace panoproj
#endif
