#include "panoproj/limits.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <optional>
#include <string>

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

namespace {

// The first number in a file (a cgroup's "max" reads as none).
std::optional<uint64_t> number_in(const std::string& path) {
  std::ifstream f(path);
  std::string word;
  if (!(f >> word) || word.empty() || !std::isdigit(static_cast<unsigned char>(word[0]))) return std::nullopt;
  return std::strtoull(word.c_str(), nullptr, 10);
}

// A key's number in a cgroup's memory.stat ("inactive_file 1234"), or 0.
uint64_t stat_in(const std::string& path, const std::string& key) {
  std::ifstream f(path);
  std::string k;
  uint64_t v = 0;
  while (f >> k >> v)
    if (k == key) return v;
  return 0;
}

// What a cgroup still lets this process allocate: the least, over its cgroup and the ones above
// it, of limit - working set (v2: memory.max, memory.current; v1: the memory controller's
// limit_in_bytes, usage_in_bytes), the working set being usage less the inactive file cache,
// which the kernel reclaims first (as the kubelet counts it). UINT64_MAX when none limits it.
uint64_t cgroup_room() {
  std::ifstream cgroups("/proc/self/cgroup");
  uint64_t room = UINT64_MAX;
  for (std::string line; std::getline(cgroups, line);) {
    const size_t a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string controllers = line.substr(a + 1, b - a - 1);
    std::string path = line.substr(b + 1);
    const bool v2 = controllers.empty();
    bool v1 = false;
    for (size_t at = 0; at <= controllers.size();) {
      const size_t end = std::min(controllers.find(',', at), controllers.size());
      v1 |= controllers.compare(at, end - at, "memory") == 0;
      at = end + 1;
    }
    if (!v2 && !v1) continue;
    const std::string base = v2 ? "/sys/fs/cgroup" : "/sys/fs/cgroup/memory";
    for (int depth = 0; depth < 64; ++depth) {
      const std::string dir = base + (path == "/" ? "" : path);
      const auto max = number_in(dir + (v2 ? "/memory.max" : "/memory.limit_in_bytes"));
      if (max && *max < (uint64_t{1} << 62)) {
        const uint64_t usage = number_in(dir + (v2 ? "/memory.current" : "/memory.usage_in_bytes")).value_or(0);
        const uint64_t cache = stat_in(dir + "/memory.stat", v2 ? "inactive_file" : "total_inactive_file");
        const uint64_t used = usage > cache ? usage - cache : 0;
        room = std::min(room, *max > used ? *max - used : 0);
      }
      if (path.empty() || path == "/") break;
      path = path.substr(0, path.rfind('/'));
      if (path.empty()) path = "/";
    }
  }
  return room;
}

// What the address-space limit (ulimit -v) leaves: RLIMIT_AS less the address space in use.
uint64_t address_space_room() {
  rlimit r{};
  if (::getrlimit(RLIMIT_AS, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return UINT64_MAX;
  std::ifstream statm("/proc/self/statm");
  uint64_t pages = 0;
  statm >> pages;
  const uint64_t used = pages * static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
  return r.rlim_cur > used ? r.rlim_cur - used : 0;
}

struct Budget {
  uint64_t bytes;
  const char* what;
};

Budget default_budget() {
  Budget b{UINT64_MAX, "3/4 of the memory available now"};
  std::ifstream meminfo("/proc/meminfo");
  std::string key, unit;
  uint64_t kb = 0;
  while (meminfo >> key >> kb >> unit)
    if (key == "MemAvailable:") {
      b.bytes = kb * 1024;
      break;
    }
  if (b.bytes == UINT64_MAX) {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) b.bytes = static_cast<uint64_t>(pages) * static_cast<uint64_t>(page);
  }
  if (const uint64_t c = cgroup_room(); c < b.bytes)
    b = {c, "3/4 of what the process's cgroup still allows"};
  if (const uint64_t a = address_space_room(); a < b.bytes)
    b = {a, "3/4 of what the address-space limit (ulimit -v) leaves"};
  // The machine stays usable: a quarter of it left to everything else, at least 1 GiB where there
  // are 2 GiB (else half).
  constexpr uint64_t kGiB = uint64_t{1} << 30;
  if (b.bytes != UINT64_MAX) b.bytes -= std::max(b.bytes / 4, std::min(kGiB, b.bytes / 2));
  return b;
}

}  // namespace

uint64_t memory_budget(int64_t limit) {
  if (limit > 0) return static_cast<uint64_t>(limit);
  return default_budget().bytes;
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
  const Budget budget = limit > 0 ? Budget{static_cast<uint64_t>(limit), nullptr} : default_budget();
  if (bytes <= budget.bytes) return;
  throw Error(what + " needs " + bytes_text(bytes) + ", over the memory limit of " + bytes_text(budget.bytes) +
                  (limit > 0 ? " (raise " : " (" + std::string(budget.what) + "; set ") + option_text("memory-limit") +
                  " to change it, or ask for a smaller size)",
              ErrorKind::Memory);
}

int64_t parse_memory_limit(std::string_view text) {
  const std::string s(text);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  std::string unit(end ? end : "");
  // Decimal units (k, M, G, T: 10^3n, also with B) and binary ones (KiB, MiB, GiB, TiB: 2^10n).
  const bool binary =
      unit.size() == 3 && (unit[1] == 'i' || unit[1] == 'I') && (unit[2] == 'B' || unit[2] == 'b');
  if (binary) unit.resize(1);
  if (!binary && unit.size() == 2 && (unit.back() == 'B' || unit.back() == 'b')) unit.pop_back();
  double scale = 0;
  const std::string units = "kmgt";
  if (unit.empty())
    scale = 1;
  else if (const auto at = unit.size() == 1 ? units.find(static_cast<char>(std::tolower(
                                                  static_cast<unsigned char>(unit[0]))))
                                            : std::string::npos;
           at != std::string::npos)
    scale = std::pow(binary ? 1024.0 : 1000.0, static_cast<double>(at + 1));
  const double bytes = v * scale;
  if (end == s.c_str() || scale == 0 || !std::isfinite(bytes) || bytes < 0)
    throw Error("memory limit: " + s.substr(0, 40) +
                " (expected a size such as 4G, 4GiB, 512M or 800000000)");
  if (bytes < 1e6) throw Error("memory limit: " + s + " (expected at least 1M: a job needs more)");
  if (bytes > 9e18)
    throw Error("memory limit: " + s +
                " (expected at most 9E18 bytes; leave it out for the memory available)");
  return static_cast<int64_t>(bytes);
}

std::string size_text(Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

}  // namespace panoproj
