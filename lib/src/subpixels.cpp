#include "subpixels.hpp"

#include <array>
#include <cstring>
#include <type_traits>

#include "sample_io.hpp"

namespace panoproj {

void average_subpixels(const Image& src, const unsigned char* sub, int64_t sub_stride, const TileRect& rect, int n,
                       unsigned char* out, int64_t out_stride) {
  const int nc = src.channels(), alpha = src.alpha_channel();
  const auto pb = static_cast<int64_t>(src.pixel_bytes());
  const double unit = unit_of(src.type()), inv = 1.0 / (n * n);
  with_sample_type(src.type(), [&](auto tag) {
    using T = decltype(tag);
    if constexpr (std::is_integral_v<T>) {
      if (alpha < 0) {  // integer sums, rounded to nearest: the common photo case
        const int64_t count = int64_t{n} * n;
        for (int64_t j = 0; j < rect.h; ++j)
          for (int64_t i = 0; i < rect.w; ++i)
            for (int c = 0; c < nc; ++c) {
              int64_t sum = 0;
              for (int b = 0; b < n; ++b) {
                const unsigned char* p = sub + (j * n + b) * sub_stride + ((i * n) * nc + c) * sizeof(T);
                for (int a = 0; a < n; ++a, p += pb) {
                  T v;
                  std::memcpy(&v, p, sizeof(T));
                  sum += v;
                }
              }
              const T m = static_cast<T>((sum + count / 2) / count);
              std::memcpy(out + j * out_stride + (i * nc + c) * sizeof(T), &m, sizeof(T));
            }
        return;
      }
    }
    for (int64_t j = 0; j < rect.h; ++j)
      for (int64_t i = 0; i < rect.w; ++i) {
        std::array<double, 4> acc{};
        for (int b = 0; b < n; ++b) {
          const unsigned char* p = sub + (j * n + b) * sub_stride + i * n * pb;
          for (int a = 0; a < n; ++a, p += pb) {
            const double cover = alpha >= 0 ? load<T>(p + alpha * sizeof(T)) / unit : 1.0;
            for (int c = 0; c < nc; ++c) acc[c] += c == alpha ? cover * unit : load<T>(p + c * sizeof(T)) * cover;
          }
        }
        unsigned char* o = out + j * out_stride + i * pb;
        const double cover = alpha >= 0 ? acc[alpha] * inv / unit : 1.0;
        for (int c = 0; c < nc; ++c) {
          const double v = acc[c] * inv;
          store<T>(o + c * sizeof(T), c == alpha || alpha < 0 ? v : (cover > 1e-12 ? v / cover : 0.0));
        }
      }
  });
}

}  // namespace panoproj
