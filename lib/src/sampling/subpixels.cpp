#include "sampling/subpixels.hpp"

#include <array>
#include <cstring>
#include <type_traits>
#include <vector>

#include "base/sample_io.hpp"

namespace panoproj {
namespace {

// Means of n x n blocks of integer samples, rounded to nearest: the n rows of each block summed
// into a row of sums (contiguous adds the compiler vectorizes), then each pixel's n columns.
// kN: n fixed at compile time (2, the usual auto case), or 0 for n at run time.
template <class T, int kN>
void integer_means(const unsigned char* sub, int64_t sub_stride, const PixelRect& rect, int n_run,
                   int nc, unsigned char* out, int64_t out_stride) {
  const int n = kN ? kN : n_run;
  const int64_t count = int64_t{n} * n, row_len = rect.width() * n * nc;
  std::vector<uint32_t> sums(static_cast<size_t>(row_len));
  for (int64_t j = 0; j < rect.height(); ++j) {
    std::fill(sums.begin(), sums.end(), 0u);
    for (int b = 0; b < n; ++b) {
      const auto* row = reinterpret_cast<const T*>(sub + (j * n + b) * sub_stride);
      for (int64_t k = 0; k < row_len; ++k) sums[static_cast<size_t>(k)] += row[k];
    }
    auto* o = reinterpret_cast<T*>(out + j * out_stride);
    for (int64_t i = 0; i < rect.width(); ++i)
      for (int c = 0; c < nc; ++c) {
        uint32_t sum = 0;
        for (int a = 0; a < n; ++a) sum += sums[static_cast<size_t>((i * n + a) * nc + c)];
        o[i * nc + c] = static_cast<T>((sum + count / 2) / count);
      }
  }
}

}  // namespace

void average_subpixels(const Image& src, const unsigned char* sub, int64_t sub_stride,
                       const PixelRect& rect, int n, unsigned char* out, int64_t out_stride) {
  const int nc = src.channels(), alpha = src.alpha_channel();
  const auto pb = static_cast<int64_t>(src.pixel_bytes());
  const double unit = unit_of(src.type()), inv = 1.0 / (n * n);
  with_sample_type(src.type(), [&](auto tag) {
    using T = decltype(tag);
    if constexpr (std::is_integral_v<T>) {
      if (alpha < 0) {  // integer sums, rounded to nearest: the common photo case
        if (n == 2) return integer_means<T, 2>(sub, sub_stride, rect, 2, nc, out, out_stride);
        return integer_means<T, 0>(sub, sub_stride, rect, n, nc, out, out_stride);
      }
    }
    for (int64_t j = 0; j < rect.height(); ++j)
      for (int64_t i = 0; i < rect.width(); ++i) {
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
