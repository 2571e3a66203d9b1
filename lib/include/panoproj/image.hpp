#pragma once
// An interleaved image in memory: 1 to 4 channels of uint8, uint16, half or float samples,
// rows stored top to bottom with 64-bit offsets (no size limit but memory).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace panoproj {

// An image's (or a projection frame's) width and height in pixels.
struct Size {
  int64_t width = 0;
  int64_t height = 0;
  bool operator==(const Size&) const = default;
};

// Pixels [x0, x1) x [y0, y1) of a frame.
struct PixelRect {
  int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int64_t width() const { return x1 - x0; }
  int64_t height() const { return y1 - y0; }
  Size size() const { return {x1 - x0, y1 - y0}; }
  bool operator==(const PixelRect&) const = default;
};

enum class PixelType { U8, U16, F16, F32 };

// (Inline: the SIMD sampler's planning loop asks per vector.)
constexpr size_t bytes_of(PixelType t) {
  switch (t) {
    case PixelType::U8: return 1;
    case PixelType::U16:
    case PixelType::F16: return 2;
    case PixelType::F32: return 4;
  }
  return 1;
}
const char* name_of(PixelType t);
// Largest sample value mapping to 1.0 (255, 65535; 1 for half and float).
double unit_of(PixelType t);

// Pixel memory: allocated without value-initializing (std::vector would zero every byte), for
// buffers written whole before they are read; buffers of 2 MB and more start on a 2 MB boundary
// and are advised for transparent huge pages, so that the gathers of a remap over a large source
// do not miss the TLB on nearly every row (one 4 KB page holds a third of a 4096-px RGB row).
void* allocate_pixels(size_t bytes);
void free_pixels(void* p, size_t bytes) noexcept;

template <class T>
struct PixelAllocator {
  using value_type = T;
  PixelAllocator() = default;
  template <class U>
  PixelAllocator(const PixelAllocator<U>&) noexcept {}
  T* allocate(size_t n) { return static_cast<T*>(allocate_pixels(n * sizeof(T))); }
  void deallocate(T* p, size_t n) noexcept { free_pixels(p, n * sizeof(T)); }
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
  template <class U>
  bool operator==(const PixelAllocator<U>&) const noexcept { return true; }
};

class Image {
 public:
  Image() = default;
  // Zero-filled. alpha_channel: index of the alpha channel, or -1.
  Image(Size size, int channels, PixelType type, int alpha_channel = -1);
  // Not filled: for outputs written whole (the engine's), saving a pass over memory.
  struct Unfilled {};
  Image(Size size, int channels, PixelType type, int alpha_channel, Unfilled);
  // A view of pixels owned elsewhere (e.g. a numpy array): rows of width * pixel_bytes() bytes,
  // back to back, exactly byte_size() bytes, alive and unmoved for as long as the view is used.
  // Nothing is copied; copies of a view are views of the same pixels.
  static Image view(unsigned char* pixels, Size size, int channels, PixelType type, int alpha_channel = -1);
  bool is_view() const { return view_; }
  Image(const Image& o) { *this = o; }
  Image& operator=(const Image& o);
  // A vector's move keeps its buffer, so data_ stays valid; the moved-from image is left empty
  // (0 x 0, no pixels), never a second name for the pixels it gave away.
  Image(Image&& o) noexcept { *this = std::move(o); }
  Image& operator=(Image&& o) noexcept;

  Size size() const { return size_; }
  int64_t width() const { return size_.width; }
  int64_t height() const { return size_.height; }
  int channels() const { return channels_; }
  PixelType type() const { return type_; }
  int alpha_channel() const { return alpha_; }
  size_t pixel_bytes() const { return static_cast<size_t>(channels_) * bytes_of(type_); }
  size_t row_bytes() const { return static_cast<size_t>(size_.width) * pixel_bytes(); }
  size_t byte_size() const { return bytes_; }

  unsigned char* data() { return data_; }
  const unsigned char* data() const { return data_; }
  unsigned char* row(int64_t y) { return data_ + static_cast<size_t>(y) * row_bytes(); }
  const unsigned char* row(int64_t y) const { return data_ + static_cast<size_t>(y) * row_bytes(); }
  unsigned char* pixel(int64_t x, int64_t y) {
    return row(y) + static_cast<size_t>(x) * pixel_bytes();
  }
  const unsigned char* pixel(int64_t x, int64_t y) const {
    return row(y) + static_cast<size_t>(x) * pixel_bytes();
  }

  // A window of a larger frame: this image holds frame pixels [origin, origin + size) of a frame
  // of frame_size() (e.g. the rows of a source file a view needs). Projections and samplers
  // address frame coordinates through at(); by default the window is the whole frame.
  void set_window(int64_t origin_x, int64_t origin_y, Size frame_size) {
    ox_ = origin_x;
    oy_ = origin_y;
    frame_ = frame_size;
  }
  int64_t origin_x() const { return ox_; }
  int64_t origin_y() const { return oy_; }
  Size frame_size() const { return frame_.width ? frame_ : size_; }
  const unsigned char* at(int64_t frame_x, int64_t frame_y) const { return pixel(frame_x - ox_, frame_y - oy_); }

  bool operator==(const Image& o) const;

  // A copy with one more channel, an opaque alpha (unit_of(type)), after the others; the same
  // window. For images without alpha and with at most 3 channels.
  Image with_alpha() const;

 private:
  Size size_{};
  int channels_ = 0;
  PixelType type_ = PixelType::U8;
  int alpha_ = -1;
  int64_t ox_ = 0, oy_ = 0;
  Size frame_{};  // 0 x 0: the image is the whole frame
  size_t bytes_ = 0;
  std::vector<unsigned char, PixelAllocator<unsigned char>> pixels_;  // empty for a view
  unsigned char* data_ = nullptr;  // pixels_.data(), or the viewed pixels
  bool view_ = false;
};

// An image's rows coming in from the top (a decoder's progress): called with k once rows [0, k)
// are in.
using RowsArrived = std::function<void(int64_t rows)>;


}  // namespace panoproj
