// Large pixel buffers freed within a ReuseFreedBuffers scope serve the next allocations of their
// size (base/pixel_buffers.hpp), within the bytes the scopes allow, and are freed when the last
// scope ends.
#include "base/pixel_buffers.hpp"

#include <gtest/gtest.h>

#include "panoproj/image.hpp"

namespace panoproj {
namespace {

constexpr size_t kMB = size_t{1} << 20;

TEST(PixelBuffers, AFreedBufferServesTheNextOfItsSizeWithinAScope) {
  ASSERT_EQ(ReuseFreedBuffers::held_bytes(), 0u);
  {
    const ReuseFreedBuffers reuse(64 * kMB);
    void* a = allocate_pixels(5 * kMB);
    void* other = allocate_pixels(9 * kMB);
    free_pixels(a, 5 * kMB);
    EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 6 * kMB);  // (whole 2 MB pages)
    void* b = allocate_pixels(5 * kMB + 123);  // the same pages
    EXPECT_EQ(b, a);
    EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 0u);
    void* c = allocate_pixels(5 * kMB);  // none kept: a new one
    EXPECT_NE(c, b);
    EXPECT_NE(c, other);
    free_pixels(b, 5 * kMB + 123), free_pixels(c, 5 * kMB), free_pixels(other, 9 * kMB);
    EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 22 * kMB);
    // Small buffers are malloc's.
    void* small = allocate_pixels(kMB);
    free_pixels(small, kMB);
    EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 22 * kMB);
  }
  EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 0u) << "the scope's end frees them";
  void* d = allocate_pixels(5 * kMB);
  free_pixels(d, 5 * kMB);
  EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 0u) << "no scope: nothing kept";
}

TEST(PixelBuffers, KeptBytesStayWithinWhatTheScopesAllow) {
  {
    const ReuseFreedBuffers reuse(10 * kMB);
    void* big = allocate_pixels(12 * kMB);
    free_pixels(big, 12 * kMB);
    EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 0u) << "larger than allowed";
    void* a = allocate_pixels(6 * kMB);
    void* b = allocate_pixels(4 * kMB);
    free_pixels(a, 6 * kMB), free_pixels(b, 4 * kMB);
    EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 10 * kMB);
    void* c = allocate_pixels(2 * kMB);
    free_pixels(c, 2 * kMB);  // the oldest (a) goes
    EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 6 * kMB);
    {
      const ReuseFreedBuffers more(20 * kMB);  // scopes add up
      void* d = allocate_pixels(20 * kMB);
      free_pixels(d, 20 * kMB);
      EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 26 * kMB);
    }
    EXPECT_LE(ReuseFreedBuffers::held_bytes(), 10 * kMB) << "back within the outer scope's";
  }
  EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 0u);
  const ReuseFreedBuffers huge(size_t{1} << 40);
  void* e = allocate_pixels(ReuseFreedBuffers::kMostBytes + kMB);
  free_pixels(e, ReuseFreedBuffers::kMostBytes + kMB);
  EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 0u) << "a scope allows at most kMostBytes";
}

TEST(PixelBuffers, AnImageOnAReusedBufferIsStillFilledWithZeros) {
  const ReuseFreedBuffers reuse(64 * kMB);
  const Size size{2048, 1024};
  {
    Image dirty(size, 3, PixelType::U8, -1, Image::Unfilled{});
    std::fill(dirty.data(), dirty.data() + dirty.byte_size(), 0xA5);
  }
  ASSERT_GT(ReuseFreedBuffers::held_bytes(), 0u);
  const Image clean(size, 3, PixelType::U8);
  EXPECT_EQ(ReuseFreedBuffers::held_bytes(), 0u) << "it took the freed one";
  for (size_t i = 0; i < clean.byte_size(); ++i) ASSERT_EQ(clean.data()[i], 0) << i;
}

}  // namespace
}  // namespace panoproj
