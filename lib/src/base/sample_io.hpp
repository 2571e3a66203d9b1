#pragma once
// One sample of any pixel type as a double and back (integers rounded to nearest and clamped to
// their range), and the dispatch from PixelType to its C++ type. Internal.
#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "panoproj/image.hpp"

namespace panoproj {

template <class T>
double load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if constexpr (std::is_same_v<T, Imath::half>) return static_cast<float>(v);
  else return static_cast<double>(v);
}

template <class T>
void store(unsigned char* p, double v) {
  if constexpr (std::is_integral_v<T>) {
    constexpr double kMax = static_cast<double>(std::numeric_limits<T>::max());
    const T t = static_cast<T>(std::clamp(std::nearbyint(v), 0.0, kMax));
    std::memcpy(p, &t, sizeof(T));
  } else {
    const T t = static_cast<T>(static_cast<float>(v));
    std::memcpy(p, &t, sizeof(T));
  }
}

// f(T{}) with T the sample type of t (uint8_t, uint16_t, Imath::half, float).
template <class F>
decltype(auto) with_sample_type(PixelType t, F&& f) {
  switch (t) {
    case PixelType::U8: return f(uint8_t{});
    case PixelType::U16: return f(uint16_t{});
    case PixelType::F16: return f(Imath::half{});
    case PixelType::F32: break;
  }
  return f(float{});
}

}  // namespace panoproj
