#pragma once
// While a ReuseFreedBuffers lives, the large pixel buffers freed (allocate_pixels' huge-page ones,
// image.hpp) are kept, up to the bytes the live scopes allow, for the next allocation of their
// size: a buffer given back to the kernel comes back as fresh pages it faults in and zeroes on
// first touch (a batch's encoded frames: 3% of a JPEG batch's time). When the last scope ends,
// those kept are freed. Internal.
#include <cstddef>

namespace panoproj {

class ReuseFreedBuffers {
 public:
  // Adds up to `bytes` of freed buffers kept (at most kMostBytes for one scope).
  explicit ReuseFreedBuffers(size_t bytes);
  ~ReuseFreedBuffers();
  ReuseFreedBuffers(const ReuseFreedBuffers&) = delete;
  ReuseFreedBuffers& operator=(const ReuseFreedBuffers&) = delete;
  static constexpr size_t kMostBytes = size_t{256} << 20;
  static size_t held_bytes();  // the freed buffers kept now

 private:
  size_t bytes_;
};

}  // namespace panoproj
