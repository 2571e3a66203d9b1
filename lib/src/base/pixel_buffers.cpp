// Pixel buffers: huge-page advice for large ones (image.hpp), and their reuse within a scope
// (pixel_buffers.hpp).
#include "base/pixel_buffers.hpp"

#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <new>
#include <vector>

#include "panoproj/image.hpp"

namespace panoproj {
namespace {

constexpr size_t kHugePage = size_t{2} << 20;
constexpr size_t kHugeFrom = size_t{2} << 20;
constexpr size_t kMostKept = 16;  // buffers

size_t rounded(size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }

struct Kept {
  std::mutex mutex;
  size_t allowed = 0, held = 0;  // bytes
  std::vector<std::pair<void*, size_t>> buffers;  // oldest first (room for kMostKept: no allocation when freeing)
  Kept() { buffers.reserve(kMostKept); }
  void drop_oldest() {
    std::free(buffers.front().first);
    held -= buffers.front().second;
    buffers.erase(buffers.begin());
  }
};
Kept& kept() {
  static Kept* k = new Kept;  // (never destroyed: images may be freed during static destruction)
  return *k;
}

}  // namespace

void* allocate_pixels(size_t bytes) {
  if (bytes < kHugeFrom) {
    if (void* p = std::malloc(bytes ? bytes : 1)) return p;
    throw std::bad_alloc();
  }
  const size_t size = rounded(bytes);
  {
    Kept& k = kept();
    const std::lock_guard<std::mutex> lock(k.mutex);
    for (auto it = k.buffers.rbegin(); it != k.buffers.rend(); ++it)
      if (it->second == size) {
        void* p = it->first;
        k.held -= size;
        k.buffers.erase(std::next(it).base());
        return p;
      }
  }
  void* p = std::aligned_alloc(kHugePage, size);
  if (!p) throw std::bad_alloc();
  madvise(p, size, MADV_HUGEPAGE);  // a hint: without THP the pages stay 4 KB
  return p;
}

void free_pixels(void* p, size_t bytes) noexcept {
  if (p && bytes >= kHugeFrom) {
    const size_t size = rounded(bytes);
    Kept& k = kept();
    const std::lock_guard<std::mutex> lock(k.mutex);
    if (size <= k.allowed) {
      while (!k.buffers.empty() && (k.held + size > k.allowed || k.buffers.size() == kMostKept)) k.drop_oldest();
      k.buffers.emplace_back(p, size);
      k.held += size;
      return;
    }
  }
  std::free(p);
}

ReuseFreedBuffers::ReuseFreedBuffers(size_t bytes) : bytes_(std::min(bytes, kMostBytes)) {
  Kept& k = kept();
  const std::lock_guard<std::mutex> lock(k.mutex);
  k.allowed += bytes_;
}

ReuseFreedBuffers::~ReuseFreedBuffers() {
  Kept& k = kept();
  const std::lock_guard<std::mutex> lock(k.mutex);
  k.allowed -= bytes_;
  while (!k.buffers.empty() && k.held > k.allowed) k.drop_oldest();
}

size_t ReuseFreedBuffers::held_bytes() {
  Kept& k = kept();
  const std::lock_guard<std::mutex> lock(k.mutex);
  return k.held;
}

}  // namespace panoproj
