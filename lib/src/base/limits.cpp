#include "panoproj/limits.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "panoproj/error.hpp"

namespace panoproj {

uint64_t add_bytes(uint64_t a, uint64_t b) {
  uint64_t s;
  return __builtin_add_overflow(a, b, &s) ? UINT64_MAX : s;
}

uint64_t image_bytes(Size size, int channels, uint64_t sample_bytes) {
  if (size.width <= 0 || size.height <= 0 || channels <= 0) return 0;
  uint64_t n = static_cast<uint64_t>(size.width);
  for (uint64_t f : {static_cast<uint64_t>(size.height), static_cast<uint64_t>(channels), sample_bytes})
    if (__builtin_mul_overflow(n, f, &n)) return UINT64_MAX;
  return n;
}

uint64_t memory_budget(int64_t limit) {
  if (limit > 0) return static_cast<uint64_t>(limit);
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kb = 0;
  std::string unit;
  while (meminfo >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<uint64_t>(pages) * static_cast<uint64_t>(page) : UINT64_MAX;
}

std::string bytes_text(uint64_t b) {
  char text[48];
  if (b == UINT64_MAX) return "more than 18 EB";
  static const char* const kUnits[] = {"kB", "MB", "GB", "TB", "PB", "EB"};
  if (b < 1000) {
    std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(b));
    return text;
  }
  double v = static_cast<double>(b) / 1000;
  int u = 0;
  while (v >= 1000 && u < 5) v /= 1000, ++u;
  std::snprintf(text, sizeof text, v < 10 ? "%.1f %s" : "%.0f %s", v, kUnits[u]);
  return text;
}

void require_memory(const std::string& what, uint64_t bytes, int64_t limit) {
  const uint64_t budget = memory_budget(limit);
  if (bytes <= budget) return;
  throw Error(what + " needs " + bytes_text(bytes) + ", over the memory limit of " + bytes_text(budget) +
                  (limit > 0 ? " (raise " : " (the memory available now; set ") + option_text("memory-limit") +
                  " to change it, or ask for a smaller size)",
              ErrorKind::Memory);
}

int64_t parse_memory_limit(std::string_view text) {
  const std::string s(text);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  std::string unit(end ? end : "");
  if (!unit.empty() && (unit.back() == 'B' || unit.back() == 'b') && unit.size() == 2) unit.pop_back();
  double scale = 0;
  if (unit.empty()) scale = 1;
  else if (unit == "k" || unit == "K") scale = 1e3;
  else if (unit == "M" || unit == "m") scale = 1e6;
  else if (unit == "G" || unit == "g") scale = 1e9;
  else if (unit == "T" || unit == "t") scale = 1e12;
  const double bytes = v * scale;
  if (end == s.c_str() || scale == 0 || !std::isfinite(bytes) || bytes < 1e6 || bytes > 9e18)
    throw Error("memory limit: " + s + " (expected a size of at least 1M, e.g. 4G, 512M or 800000000)");
  return static_cast<int64_t>(bytes);
}

std::string size_text(Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

}  // namespace panoproj
