#pragma once
// Sizes, memory and threads, checked before anything is planned or allocated: byte counts that
// cannot overflow, a budget (default: the machine's available memory) that a job's buffers must
// fit, and the thread count.
#include <cstdint>
#include <string>
#include <string_view>

#include "panoproj/image.hpp"

namespace panoproj {

// Threads: 0 is all cores; throws Error unless 0 <= threads <= kMaxThreads.
inline constexpr int kMaxThreads = 1024;
void check_threads(int64_t threads);
int resolve_threads(int threads);  // 0 -> the cores

// w x h x channels x sample_bytes, saturating at UINT64_MAX instead of overflowing.
uint64_t image_bytes(Size size, int channels, uint64_t sample_bytes);
uint64_t add_bytes(uint64_t a, uint64_t b);

// The bytes a job may allocate: `limit` when positive, else 3/4 of the memory available now
// (MemAvailable in /proc/meminfo, else physical memory), or of less where the process's cgroup
// (v1 or v2, and those above it) or its address-space limit (RLIMIT_AS) leaves less; at least
// 1 GiB is left free where that is 2 GiB or more, else half.
uint64_t memory_budget(int64_t limit);

// Throws Error(ErrorKind::Memory): "<what> needs 6.4 GB, over the memory limit of 2.0 GB (...)".
void require_memory(const std::string& what, uint64_t bytes, int64_t limit);

// "1.5 GB", "312 MB", "4 kB", "12 bytes" (decimal units).
std::string bytes_text(uint64_t bytes);
// "4G", "512M", "1.5GB", "800000000": bytes; throws Error naming the text otherwise.
int64_t parse_memory_limit(std::string_view text);

// "4096x2048".
std::string size_text(Size size);

}  // namespace panoproj
