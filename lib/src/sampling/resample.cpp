// Reference remap (scalar). See resample.hpp.
#include "sampling/resample.hpp"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "base/parallel.hpp"
#include "geometry/source_taps.hpp"
#include "sampling/footprint_kernel.hpp"
#include "sampling/reference_sampler.hpp"
#include "base/sample_io.hpp"

namespace panoproj {
namespace {

// One output row: samples at (xs[i], ys[i]) where ok[i]; with box widths ex, ey, the footprint
// kernel (footprint_kernel.hpp) instead of interp's.
template <class T>
void sample_row(const Image& src, const SourceTaps& taps, Interp interp, const double* xs,
                const double* ys, const float* ex, const float* ey, const uint8_t* ok, int64_t n, unsigned char* out) {
  const int nc = src.channels(), alpha = src.alpha_channel();
  const size_t pb = src.pixel_bytes();
  if (ex) interp = kFootprintGrid;  // its taps; the footprint kernel's weights below
  const int k = support(interp);
  const double unit = unit_of(src.type());
  // Taps stay inside the window the caller read (a guard: the footprint already ensures it).
  const int64_t wx0 = src.origin_x(), wy0 = src.origin_y();
  const int64_t wx1 = wx0 + src.width() - 1, wy1 = wy0 + src.height() - 1;
  auto at = [&](int64_t x, int64_t y) {
    return src.at(std::clamp(x, wx0, wx1), std::clamp(y, wy0, wy1));
  };
  const bool dering = !ex && derings(interp);
  double wx[6], wy[6], acc[4], lo[4], hi[4];  // lo, hi: the central 2x2 taps' range (dering)
  for (int64_t i = 0; i < n; ++i, out += pb) {
    if (!ok[i]) {
      std::memset(out, 0, pb);
      continue;
    }
    const int face = taps.face_at(xs[i], ys[i]);
    const int64_t bx = first_tap(interp, xs[i]), by = first_tap(interp, ys[i]);
    SourceTaps::Part parts[4];
    if (interp == Interp::Nearest) {
      // The pixel containing the sample, copied untouched (its largest part off a cube face).
      const int n_parts = taps.resolve(bx, by, face, parts);
      const auto* best = std::max_element(parts, parts + n_parts,
                                          [](const auto& a, const auto& b) { return a.w < b.w; });
      std::memcpy(out, at(best->x, best->y), pb);
      continue;
    }
    if (ex) {
      footprint_weights(xs[i], ex[i], wx);
      footprint_weights(ys[i], ey[i], wy);
    } else {
      tap_weights(interp, xs[i], wx);
      tap_weights(interp, ys[i], wy);
    }
    std::fill(acc, acc + 4, 0.0);
    std::fill(lo, lo + 4, HUGE_VAL);
    std::fill(hi, hi + 4, -HUGE_VAL);
    for (int r = 0; r < k; ++r) {
      for (int c = 0; c < k; ++c) {
        // The tap's (premultiplied) value: its pixel, or the parts of a neighbouring cube face.
        double tap[4] = {0, 0, 0, 0};
        const int n_parts = taps.resolve(bx + c, by + r, face, parts);
        for (int q = 0; q < n_parts; ++q) {
          const unsigned char* p = at(parts[q].x, parts[q].y);
          // Premultiplied alpha: colour taps are weighted by their alpha.
          const double a = alpha >= 0 ? load<T>(p + alpha * sizeof(T)) / unit : 1.0;
          for (int ch = 0; ch < nc; ++ch) {
            const double v = load<T>(p + ch * sizeof(T));
            tap[ch] += parts[q].w * (ch == alpha ? v : v * a);
          }
        }
        const bool central = (r == k / 2 - 1 || r == k / 2) && (c == k / 2 - 1 || c == k / 2);
        for (int ch = 0; ch < nc; ++ch) {
          acc[ch] += wx[c] * wy[r] * tap[ch];
          if (dering && central) lo[ch] = std::min(lo[ch], tap[ch]), hi[ch] = std::max(hi[ch], tap[ch]);
        }
      }
    }
    if (dering)
      for (int ch = 0; ch < nc; ++ch) acc[ch] = std::clamp(acc[ch], lo[ch], hi[ch]);
    if (alpha >= 0) {
      const double a = acc[alpha] / unit;  // interpolated alpha, [0, 1] after clamping
      for (int ch = 0; ch < nc; ++ch) {
        if (ch == alpha) continue;
        acc[ch] = a > 1e-12 ? acc[ch] / a : 0.0;
      }
      acc[alpha] = std::clamp(a, 0.0, 1.0) * unit;
    }
    for (int ch = 0; ch < nc; ++ch) store<T>(out + ch * sizeof(T), acc[ch]);
  }
}

}  // namespace

void sample_reference(const Image& src, const SourceTaps& taps, Interp interp, const double* xs,
                      const double* ys, const uint8_t* ok, int64_t n, unsigned char* out) {
  with_sample_type(src.type(), [&](auto t) { sample_row<decltype(t)>(src, taps, interp, xs, ys, nullptr, nullptr, ok, n, out); });
}

void sample_footprint_reference(const Image& src, const SourceTaps& taps, const double* xs, const double* ys,
                                const float* ex, const float* ey, const uint8_t* ok, int64_t n, unsigned char* out) {
  with_sample_type(src.type(), [&](auto t) { sample_row<decltype(t)>(src, taps, Interp::Bilinear, xs, ys, ex, ey, ok, n, out); });
}

Image remap(const Image& src, const Projection& src_proj, const Projection& dst_proj,
            const Eigen::Matrix3d& rotation, const RemapOptions& options) {
  const Size out_size = size_of(dst_proj);
  Image out(out_size, src.channels(), src.type(), src.alpha_channel());
  const SourceTaps taps(src_proj);
  const int64_t w = out_size.width;
  parallel_rows(out_size.height, options.threads, [&](int64_t y0, int64_t y1) {
    std::vector<Ray> rays(static_cast<size_t>(w));
    std::vector<double> xs(static_cast<size_t>(w)), ys(static_cast<size_t>(w));
    std::vector<uint8_t> ok(static_cast<size_t>(w));
    for (int64_t y = y0; y < y1; ++y) {
      to_ray_row(dst_proj, static_cast<double>(y) + 0.5, 0, w, rays.data(), ok.data());
      for (int64_t i = 0; i < w; ++i) rays[i] = rotation * rays[i];
      to_pixel_row(src_proj, rays.data(), w, xs.data(), ys.data(), ok.data());
      sample_reference(src, taps, options.interp, xs.data(), ys.data(), ok.data(), w, out.row(y));
    }
  });
  return out;
}

}  // namespace panoproj
