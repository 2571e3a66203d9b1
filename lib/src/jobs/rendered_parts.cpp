#include "jobs/rendered_parts.hpp"

#include <cstring>
#include <limits>
#include <type_traits>

#include "base/sample_io.hpp"
#include "io/codec.hpp"
#include "io/formats.hpp"

namespace panoproj {

Flat flatten(const Image& part, int64_t x0, int64_t y0, int64_t w, int64_t h, bool partial) {
  const int a = partial ? part.alpha_channel() : -1;
  const int channels = part.channels() - (a >= 0 ? 1 : 0);
  Flat f;
  bool any = a < 0;
  with_sample_type(part.type(), [&](auto sample) {
    using T = decltype(sample);
    for (int64_t y = 0; y < h && !any; ++y) {
      const unsigned char* in = part.pixel(x0, y0 + y) + a * sizeof(T);
      for (int64_t x = 0; x < w && !any; ++x, in += part.pixel_bytes()) any = load<T>(in) > 0;
    }
  });
  f.empty = !any;
  if (f.empty) return f;
  f.image = Image(Size{w, h}, channels, part.type(), -1, Image::Unfilled{});
  if (a < 0) {
    for (int64_t y = 0; y < h; ++y) std::memcpy(f.image.row(y), part.pixel(x0, y0 + y), f.image.row_bytes());
    return f;
  }
  with_sample_type(part.type(), [&](auto sample) {
    using T = decltype(sample);
    const double scale = std::is_integral_v<T> ? 1.0 / static_cast<double>(std::numeric_limits<T>::max()) : 1.0;
    for (int64_t y = 0; y < h; ++y) {
      const unsigned char* in = part.pixel(x0, y0 + y);
      T* out = reinterpret_cast<T*>(f.image.row(y));
      for (int64_t x = 0; x < w; ++x, in += part.pixel_bytes()) {
        const T* px = reinterpret_cast<const T*>(in);
        if constexpr (std::is_same_v<T, uint8_t>) {
          // c a / 255 rounded to nearest: (2 c a + 255) / 510.
          const unsigned alpha = px[a];
          for (int c = 0; c < part.channels(); ++c)
            if (c != a) *out++ = static_cast<uint8_t>((2u * px[c] * alpha + 255u) / 510u);
        } else {
          const double alpha = load<T>(in + a * sizeof(T)) * scale;
          for (int c = 0; c < part.channels(); ++c)
            if (c != a) store<T>(reinterpret_cast<unsigned char*>(out++), load<T>(in + c * sizeof(T)) * alpha);
        }
      }
    }
  });
  return f;
}

std::string encoded(const Image& image, const ImageFormat& f, const WriteOptions& write,
                    const std::string& path) {
  WriteOptions w = write;
  w.threads = 1;
  const PixelType type = f.stored_type(image.type());
  Image converted;
  const Image& in = type != image.type() ? (converted = convert_pixels(image, type)) : image;
  const FileBytes b = f.encode(in, path, w, {});
  return std::string(reinterpret_cast<const char*>(b.data()), b.size());
}

Image mask_of(const Image& view) {
  const int a = view.alpha_channel();
  Image mask(view.size(), 1, PixelType::U8);
  with_sample_type(view.type(), [&](auto sample) {
    using T = decltype(sample);
    const double full =
        std::is_integral_v<T> ? static_cast<double>(std::numeric_limits<T>::max()) : 1.0;
    for (int64_t y = 0; y < view.height(); ++y) {
      uint8_t* out = mask.row(y);
      for (int64_t x = 0; x < view.width(); ++x)
        out[x] = load<T>(view.pixel(x, y) + a * sizeof(T)) >= full ? 255 : 0;
    }
  });
  return mask;
}

}  // namespace panoproj
