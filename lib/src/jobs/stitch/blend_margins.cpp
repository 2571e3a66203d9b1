// Margins of the blended panorama (blend_margins.hpp).
#include "jobs/stitch/blend_margins.hpp"

#include <algorithm>
#include <cmath>

#include "base/parallel.hpp"
#include "jobs/stitch/layer_masks.hpp"
#include "panoproj/spec.hpp"

namespace panoproj {

LayerMargin::LayerMargin(const StitchPlan& plan, const StitchLayer& layer)
    : image_(&plan.project.images[static_cast<size_t>(layer.index)]),
      lens_(make_projection(*layer.lens, {image_->width, image_->height})),
      rotation_(layer.rotation),
      per_radian_(center_density(lens_)) {
  if (const auto* f = std::get_if<Fisheye>(&lens_)) field_ = f->psi_max();
  if (const auto* p = std::get_if<PanoTools>(&lens_); p && p->lens() == PanoToolsLens::Fisheye)
    field_ = Fisheye::law_limit(p->model());  // (an orthographic's 90 degrees: inside its frame)
}

double LayerMargin::at(const Ray& d) const {
  double px, py;
  const Ray l = rotation_ * d;
  if (!to_pixel(lens_, l, px, py)) return kNoMargin;
  // Hugin's positions (pixel centres at integers): the frame's edges at -1/2 and w - 1/2.
  const double x = px - 0.5, y = py - 0.5;
  const PtoImage& im = *image_;
  PtoRect r{0, im.width, 0, im.height};
  double m = 0;
  if (const auto c = crop_circle(im)) {
    m = c->radius - std::hypot(x - c->cx, y - c->cy);
  } else {
    if (im.crop)
      r = {std::max(r.left, im.crop->left), std::min(r.right, im.crop->right),
           std::max(r.top, im.crop->top), std::min(r.bottom, im.crop->bottom)};
    m = INFINITY;
  }
  m = std::min({m, x - (static_cast<double>(r.left) - 0.5), static_cast<double>(r.right) - 0.5 - x,
                y - (static_cast<double>(r.top) - 0.5), static_cast<double>(r.bottom) - 0.5 - y});
  m /= per_radian_;
  if (field_ > 0) m = std::min(m, field_ - std::atan2(std::hypot(l.x(), l.y()), l.z()));
  return std::max(m, static_cast<double>(kNoMargin));
}

void LayerMargin::over(const Projection& pano, const PixelRect& rect, float* out,
                       int threads) const {
  const int64_t w = rect.width(), h = rect.height();
  if (w <= 0 || h <= 0) return;
  const auto exact = [&](int64_t x, int64_t y) {
    Ray d;
    if (!to_ray(pano, static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, d))
      return kNoMargin;
    return static_cast<float>(at(d));
  };
  // Nodes on the panorama's grid (multiples of kStep), so that every rectangle gets the same
  // values at a pixel.
  const int64_t gx0 = rect.x0 / kStep, gy0 = rect.y0 / kStep;
  const int64_t cols = (rect.x1 - 1) / kStep - gx0 + 2, node_rows = (rect.y1 - 1) / kStep - gy0 + 2;
  std::vector<float> node(static_cast<size_t>(cols * node_rows));
  parallel_row_blocks(
      node_rows, threads,
      [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r)
          for (int64_t c = 0; c < cols; ++c)
            node[static_cast<size_t>(r * cols + c)] = exact((gx0 + c) * kStep, (gy0 + r) * kStep);
      },
      8);
  constexpr float inv = 1.0f / static_cast<float>(kStep);
  parallel_row_blocks(h, threads, [&](int64_t j0, int64_t j1) {
    for (int64_t y = rect.y0 + j0; y < rect.y0 + j1; ++y) {
      const int64_t r = y / kStep - gy0;
      const float ty = static_cast<float>(y % kStep) * inv;
      float* row = out + (y - rect.y0) * w;
      for (int64_t x = rect.x0; x < rect.x1; ++x) {
        const int64_t c = x / kStep - gx0;
        const float* n0 = node.data() + r * cols + c;
        const float* n1 = n0 + cols;
        const float n00 = n0[0], n01 = n0[1], n10 = n1[0], n11 = n1[1];
        const bool smooth =
            n00 > kNoMargin && n01 > kNoMargin && n10 > kNoMargin && n11 > kNoMargin;
        // No node with a pixel: the cell is taken as without (a lens's field ends smoothly, so a
        // sliver of it inside a cell kStep wide lies on the layer's very edge, at margin < 0).
        const bool none =
            n00 == kNoMargin && n01 == kNoMargin && n10 == kNoMargin && n11 == kNoMargin;
        const float tx = static_cast<float>(x % kStep) * inv;
        const float a = n00 + ty * (n10 - n00), b = n01 + ty * (n11 - n01);
        row[x - rect.x0] = smooth ? a + tx * (b - a) : none ? kNoMargin : exact(x, y);
      }
    }
  });
}

}  // namespace panoproj
