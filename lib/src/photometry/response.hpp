#pragma once
// A camera response: the code value (0..1) a camera records for a linear irradiance (0..1). EMoR
// responses (Grossberg and Nayar 2004: f0 + sum p_k h_k, emor_basis.inc) are tabulated at the
// kResponseSamples irradiances i / (kResponseSamples - 1), as Hugin tabulates them, and looked up
// with linear interpolation both ways; the linear response has no table.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace panoproj {

inline constexpr int kResponseSamples = 1024;
// A curve that falls by more than this (an 8-bit code step) below its running maximum, or passes
// its last sample by more, is refused; smaller dips are flattened as Hugin's enforceMonotonicity.
inline constexpr double kMaxResponseFall = 1.0 / 255.0;

class Response {
 public:
  Response() = default;  // linear
  // p: the EMoR coefficients (a project's Ra..Re), held as floats as Hugin holds them. Throws
  // Error naming `what` for a coefficient that is not finite or a curve that is not a response.
  static Response emor(const std::array<double, 5>& p, const std::string& what);

  bool linear() const { return table_.empty(); }
  bool operator==(const Response& o) const { return table_ == o.table_; }
  // Irradiance to code: below 0 gives 0, above 1 the last sample (Hugin's LUTFunctor).
  // (Inline: once per corrected sample.)
  double code(double e) const {
    if (linear()) return e;
    if (e > 1) return table_.back();
    if (!(e >= 0)) return 0;
    const double x = e * (kResponseSamples - 1);
    const auto i = static_cast<size_t>(x);
    const double f = x - static_cast<double>(i);
    if (i + 1 < table_.size()) return (1 - f) * table_[i] + f * table_[i + 1];
    return table_[i];
  }
  // Code to irradiance: the exact inverse of the interpolated table, codes from its last sample
  // up giving that sample and codes below 0 giving 0 (Hugin's InvLUTFunctor); linear: the code.
  double irradiance(double code) const;

 private:
  std::vector<double> table_;    // non-decreasing, kResponseSamples
  std::vector<uint16_t> first_;  // per code bucket [b, b + 1) / kBuckets: the first sample >= b
};

}  // namespace panoproj
