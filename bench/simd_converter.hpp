#pragma once
// The benchmarks' conversion: the simd engine's Converter of a pair with a kernel, antialiasing
// off (the kernel alone, as the peers' remaps).
#include "panoproj/convert.hpp"

namespace panoproj::bench {

inline Converter simd_converter(const Projection& source, const Projection& target,
                                const Eigen::Matrix3d& rotation, Interp interp, int threads) {
  ConvertOptions o;
  o.interp = interp, o.threads = threads, o.antialias = Antialias{};
  return Converter(ConversionGeometry{source, target, rotation}, o);
}

}  // namespace panoproj::bench
