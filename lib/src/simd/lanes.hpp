#pragma once
// What the SIMD lanes of every projection share (simd/<projection>.hpp): the float error budget,
// and lane(). Each projection's lanes struct is set by a template describe(..., lanes) called for
// double and for float lanes, which computes in double and rounds each value once.
#include <cmath>
#include <limits>
#include <type_traits>

namespace panoproj::simd {

// A double parameter in lane type T; beyond float's range, infinity ("unbounded" limits such
// as 1e300; a plain conversion of those is undefined).
template <class T>
T lane(double v) {
  if constexpr (std::is_same_v<T, float>) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    if (std::fabs(v) > std::numeric_limits<float>::max()) return v > 0 ? inf : -inf;
  }
  return static_cast<T>(v);
}

// Error bound of float lanes, in source pixels: lanes that could exceed it are computed in
// double (each source's coarse limits).
inline constexpr double kFloatTolerance = 1.0 / 1024;
// Largest absolute error of a float unit ray after the target's projection and the rotation
// (measured at <= 2.4e-7 over the pairs of tests/simd_geometry_test.cpp; with margin).
inline constexpr double kFloatRayError = 2.5e-7;
inline constexpr double kHalfUlp = 0x1p-24;  // relative rounding of a float

}  // namespace panoproj::simd
