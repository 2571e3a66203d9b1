#include "sampling/dual_blend.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "base/sample_io.hpp"

namespace panoproj {
namespace {

// Local offsets of the nodes along an extent of n pixels: 0, step, 2 step, ..., n - 1.
std::vector<int64_t> node_offsets(int64_t n) {
  std::vector<int64_t> o;
  for (int64_t i = 0; i < n - 1; i += kDualNodeStep) o.push_back(i);
  o.push_back(n - 1);
  return o;
}

double angle_between(const Ray& a, const Ray& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

template <class T>
void blend_typed(const float* w, const PixelRect& rect, float unit, int nc, int alpha,
                 unsigned char* a, int64_t as, const unsigned char* b, int64_t bs) {
  // The results are convex combinations of two samples, so within their type's range: integers
  // round by adding 1/2.
  auto store = [](T* p, float v) {
    if constexpr (std::is_integral_v<T>) *p = static_cast<T>(v + 0.5f);
    else *p = static_cast<T>(v);
  };
  for (int64_t j = 0; j < rect.height(); ++j) {
    T* pa = reinterpret_cast<T*>(a + j * as);
    const T* pb = reinterpret_cast<const T*>(b + j * bs);
    const float* wr = w + j * rect.width();
    if constexpr (std::is_integral_v<T>) {
      // One integer channel (a video's plane, gray): the same sums without branches, so that
      // they vectorize (w0 = 1 gives a, w0 = 0 gives b, exactly).
      if (nc == 1 && alpha < 0) {
        T* __restrict o = pa;
        const T* __restrict q = pb;
        const float* __restrict k = wr;
        const int64_t n = rect.width();
        for (int64_t i = 0; i < n; ++i)  // (through int32: the same truncation, in vectors)
          o[i] = static_cast<T>(static_cast<int32_t>(
              k[i] * static_cast<float>(o[i]) + (1.0f - k[i]) * static_cast<float>(q[i]) + 0.5f));
        continue;
      }
    }
    for (int64_t i = 0; i < rect.width(); ++i, pa += nc, pb += nc) {
      const float w0 = wr[i];
      if (w0 == 1.0f) continue;
      if (w0 == 0.0f) {
        std::copy(pb, pb + nc, pa);
        continue;
      }
      float k0 = w0, k1 = 1.0f - w0;
      if (alpha >= 0) {  // colours weighted by their alphas; the alphas blend plainly
        k0 *= static_cast<float>(pa[alpha]) / unit, k1 *= static_cast<float>(pb[alpha]) / unit;
        const float sum = k0 + k1;
        k0 = sum > 0 ? k0 / sum : 0.0f, k1 = sum > 0 ? k1 / sum : 0.0f;
      }
      for (int c = 0; c < nc; ++c) {
        const auto va = static_cast<float>(pa[c]), vb = static_cast<float>(pb[c]);
        store(pa + c, c == alpha ? w0 * va + (1.0f - w0) * vb : k0 * va + k1 * vb);
      }
    }
  }
}

}  // namespace

template <class Pair>
int dual_weights(const Pair& d, const Projection& target, const Eigen::Matrix3d& rotation,
                 const PixelRect& rect, std::vector<float>& w) {
  const std::vector<int64_t> nx = node_offsets(rect.width()), ny = node_offsets(rect.height());
  const size_t cols = nx.size();
  std::vector<Ray> rays(cols * ny.size());
  std::vector<double> m0(rays.size()), m1(rays.size());
  bool all_rays = true;
  for (size_t r = 0; r < ny.size(); ++r)
    for (size_t c = 0; c < cols; ++c) {
      Ray& ray = rays[r * cols + c];
      if (!to_ray(target, static_cast<double>(rect.x0 + nx[c]) + 0.5, static_cast<double>(rect.y0 + ny[r]) + 0.5, ray)) {
        all_rays = false;
        continue;
      }
      ray = rotation * ray;
      m0[r * cols + c] = d.margin(0, ray), m1[r * cols + c] = d.margin(1, ray);
    }
  w.resize(static_cast<size_t>(rect.width() * rect.height()));
  if (!all_rays) {  // an outline crosses the tile: every pixel exactly
    for (int64_t j = 0; j < rect.height(); ++j)
      for (int64_t i = 0; i < rect.width(); ++i) {
        Ray ray;
        const bool has = to_ray(target, static_cast<double>(rect.x0 + i) + 0.5, static_cast<double>(rect.y0 + j) + 0.5, ray);
        if (has) ray = rotation * ray;
        w[static_cast<size_t>(j * rect.width() + i)] =
            has ? static_cast<float>(d.weight0(d.margin(0, ray), d.margin(1, ray))) : 1.0f;
      }
    return -1;
  }
  // delta: the largest angle between neighbouring nodes, so every pixel lies within delta of a
  // node; margins move by at most that angle, their difference by twice it (1.5x: room for
  // curvature).
  double delta = 0;
  for (size_t r = 0; r < ny.size(); ++r)
    for (size_t c = 0; c < cols; ++c) {
      if (c + 1 < cols) delta = std::max(delta, angle_between(rays[r * cols + c], rays[r * cols + c + 1]));
      if (r + 1 < ny.size()) delta = std::max(delta, angle_between(rays[r * cols + c], rays[(r + 1) * cols + c]));
    }
  const double f = d.feather();
  bool only0 = true, only1 = true;
  for (size_t q = 0; q < rays.size(); ++q) {
    const double diff = m0[q] - m1[q];
    only0 &= diff - f >= 3.0 * delta || m1[q] <= -2.0 * delta;
    only1 &= -diff - f >= 3.0 * delta || m0[q] <= -2.0 * delta;
  }
  if (only0) return 0;
  if (only1) return 1;
  // Bilinear in the node cell holding each pixel: the node rows' margins interpolated to pixel row
  // j at each node column (a0, a1), then along the row.
  std::vector<double> a0(cols), a1(cols);
  size_t r = 0;
  for (int64_t j = 0; j < rect.height(); ++j) {
    while (r + 2 < ny.size() && ny[r + 1] <= j) ++r;
    const size_t r1 = std::min(r + 1, ny.size() - 1);
    const double ty = r1 > r ? static_cast<double>(j - ny[r]) / static_cast<double>(ny[r1] - ny[r]) : 0.0;
    for (size_t c = 0; c < cols; ++c) {
      a0[c] = m0[r * cols + c] + ty * (m0[r1 * cols + c] - m0[r * cols + c]);
      a1[c] = m1[r * cols + c] + ty * (m1[r1 * cols + c] - m1[r * cols + c]);
    }
    float* row = w.data() + j * rect.width();
    if (cols == 1) {
      row[0] = static_cast<float>(d.weight0(a0[0], a1[0]));
      continue;
    }
    for (size_t c = 0; c + 1 < cols; ++c) {
      const double inv = 1.0 / static_cast<double>(nx[c + 1] - nx[c]);
      const double d0 = (a0[c + 1] - a0[c]) * inv, d1 = (a1[c + 1] - a1[c]) * inv;
      for (int64_t i = nx[c]; i < (c + 2 < cols ? nx[c + 1] : rect.width()); ++i) {
        const auto t = static_cast<double>(i - nx[c]);
        row[i] = static_cast<float>(d.weight0(a0[c] + t * d0, a1[c] + t * d1));
      }
    }
  }
  return -1;
}

template int dual_weights(const DualFisheye&, const Projection&, const Eigen::Matrix3d&,
                          const PixelRect&, std::vector<float>&);
template int dual_weights(const GoProMax&, const Projection&, const Eigen::Matrix3d&,
                          const PixelRect&, std::vector<float>&);

void blend_lenses(const float* w, const PixelRect& rect, PixelType type, int channels, int alpha,
                  unsigned char* a, int64_t a_stride, const unsigned char* b, int64_t b_stride) {
  const auto unit = static_cast<float>(unit_of(type));
  with_sample_type(type, [&](auto t) {
    blend_typed<decltype(t)>(w, rect, unit, channels, alpha, a, a_stride, b, b_stride);
  });
}

}  // namespace panoproj
