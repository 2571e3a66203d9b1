// Camera responses (response.hpp).
#include "photometry/response.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

constexpr double kEmorBasis[kResponseSamples][6] = {
#include "photometry/emor_basis.inc"
};
// Code buckets of the inverse's search: a power of two, so code * kBuckets is exact.
constexpr int kBuckets = 4096;

std::string coefficient_text(const std::array<double, 5>& p) {
  std::string s;
  for (size_t k = 0; k < p.size(); ++k) {
    char b[48];
    std::snprintf(b, sizeof b, "%sR%c%.6g", k ? " " : "", static_cast<char>('a' + k), p[k]);
    s += b;
  }
  return s;
}

}  // namespace

Response Response::emor(const std::array<double, 5>& p, const std::string& what) {
  for (double v : p)
    if (!std::isfinite(v) || std::fabs(v) > 1e6)
      throw Error(what + ": response " + coefficient_text(p) +
                  ": each coefficient must be a finite number");
  Response r;
  r.table_.resize(kResponseSamples);
  for (int i = 0; i < kResponseSamples; ++i) {
    double t = kEmorBasis[i][0];
    for (int k = 0; k < 5; ++k)
      t += static_cast<double>(static_cast<float>(p[k])) * kEmorBasis[i][k + 1];
    r.table_[static_cast<size_t>(i)] = t;
  }
  std::vector<double>& t = r.table_;
  const double last = t.back();
  double peak = t[0];
  for (int i = 1; i < kResponseSamples; ++i) {
    const double v = t[static_cast<size_t>(i)];
    const bool falls = v<peak - kMaxResponseFall, above = v> last + kMaxResponseFall;
    if (falls || above) {
      char b[200];
      std::snprintf(b, sizeof b,
                    above ? ": response %s rises to %.4g at irradiance %.4g, above its end %.4g"
                          : ": response %s falls to %.4g at irradiance %.4g after %.4g",
                    coefficient_text(p).c_str(), v, static_cast<double>(i) / (kResponseSamples - 1),
                    above ? last : peak);
      throw Error(what + b +
                  ": not monotonic (a camera response rises from 0 to 1; re-optimise it in Hugin)");
    }
    peak = std::max(peak, v);
  }
  // Hugin's enforceMonotonicity: none above the last, none below the one before.
  for (int j = 0; j + 1 < kResponseSamples; ++j) {
    double& next = t[static_cast<size_t>(j + 1)];
    if (next > last)
      next = last;
    else if (next < t[static_cast<size_t>(j)])
      next = t[static_cast<size_t>(j)];
  }
  if (!(last > t[0]))
    throw Error(what + ": response " + coefficient_text(p) + " does not rise (flat)");
  r.first_.resize(kBuckets);
  size_t i = 0;
  for (int b = 0; b < kBuckets; ++b) {
    const double start = static_cast<double>(b) / kBuckets;
    while (i < t.size() && t[i] < start) ++i;
    r.first_[static_cast<size_t>(b)] = static_cast<uint16_t>(i);
  }
  return r;
}

double Response::irradiance(double v) const {
  if (linear()) return v;
  if (v >= table_.back()) return table_.back();
  if (!(v >= table_[0])) return 0;
  if (v == 1) return 1;
  // The first sample >= v (std::lower_bound's), from its bucket's first on.
  size_t x = first_[static_cast<size_t>(std::min(static_cast<int>(v * kBuckets), kBuckets - 1))];
  while (table_[x] < v) ++x;
  if (x == 0) return 0;
  if (v == table_[x]) return static_cast<double>(x) / (kResponseSamples - 1);
  const double lower = table_[x - 1], upper = table_[x];
  return (static_cast<double>(x - 1) + (v - lower) / (upper - lower)) / (kResponseSamples - 1);
}

}  // namespace panoproj
