// A layer's extent as nona estimates it (estimateImageAlpha, Hugin's ComputeImageROI.cpp): the
// panorama at most 180 px a side, each of its pixel positions (Hugin's: centres at integers) kept
// where it maps inside the image's crop (its rounded position in the crop rectangle, or within
// the crop circle) and outside its masks; that set grown by one pixel (a disc of radius 1), its
// bounding box scaled back, rounded, and cut to the panorama's crop.
#include <cmath>

#include "jobs/stitch/layer_masks.hpp"
#include "jobs/stitch/stitch.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

PixelRect layer_extent(const StitchPlan& plan, const StitchLayer& layer) {
  const PtoProject& p = plan.project;
  const int index = layer.index;
  const PtoImage& im = p.images[static_cast<size_t>(index)];
  const Projection pano = make_projection(*plan.pano, plan.canvas);
  const Projection lens = make_projection(*layer.lens, {im.width, im.height});
  const Eigen::Matrix3d& rotation = layer.rotation;
  const auto W = static_cast<double>(plan.canvas.width),
             H = static_cast<double>(plan.canvas.height);
  const double scale = std::fmin(180.0 / W, 180.0 / H);
  const auto sw = static_cast<int64_t>(std::ceil(W * scale)),
             sh = static_cast<int64_t>(std::ceil(H * scale));
  PixelRect roi{0, 0, plan.canvas.width, plan.canvas.height};
  if (p.pano.crop)
    roi = {p.pano.crop->left, p.pano.crop->top, p.pano.crop->right, p.pano.crop->bottom};
  const int64_t x0 =
      std::max<int64_t>(0, static_cast<int64_t>(std::floor(static_cast<double>(roi.x0) * scale)));
  const int64_t y0 =
      std::max<int64_t>(0, static_cast<int64_t>(std::floor(static_cast<double>(roi.y0) * scale)));
  const int64_t x1 =
      std::min(sw, static_cast<int64_t>(std::ceil(static_cast<double>(roi.x1) * scale)));
  const int64_t y1 =
      std::min(sh, static_cast<int64_t>(std::ceil(static_cast<double>(roi.y1) * scale)));
  std::vector<const PtoMask*> masks = image_masks(p, index);
  int64_t ux = x1, uy = y1, lx = x0 - 1, ly = y0 - 1;
  for (int64_t y = y0; y < y1; ++y)
    for (int64_t x = x0; x < x1; ++x) {
      Ray d;
      double sx, sy;
      if (!to_ray(pano, static_cast<double>(x) / scale + 0.5, static_cast<double>(y) / scale + 0.5,
                  d) ||
          !to_pixel(lens, rotation * d, sx, sy))
        continue;
      sx -= 0.5, sy -= 0.5;
      const double rx = std::round(sx), ry = std::round(sy);
      bool valid = crop_circle(im)
                       ? inside_crop(im, sx, sy)
                       : rx >= 0 && ry >= 0 && rx < static_cast<double>(im.width) &&
                             ry < static_cast<double>(im.height) && inside_crop(im, rx, ry);
      for (size_t k = 0; valid && k < masks.size(); ++k)
        valid = !inside_polygon(masks[k]->xy, rx, ry);
      if (!valid) continue;
      // The disc of radius 1 around it, inside the miniature.
      ux = std::min(ux, std::max(x - 1, int64_t{0})), lx = std::max(lx, std::min(x + 1, sw - 1));
      uy = std::min(uy, std::max(y - 1, int64_t{0})), ly = std::max(ly, std::min(y + 1, sh - 1));
    }
  if (lx < ux || ly < uy) return {};
  const auto round = [](double v) { return static_cast<int64_t>(std::floor(v + 0.5)); };
  PixelRect r{round(static_cast<double>(ux) / scale), round(static_cast<double>(uy) / scale),
              round(static_cast<double>(lx + 1) / scale),
              round(static_cast<double>(ly + 1) / scale)};
  r = {std::max(r.x0, roi.x0), std::max(r.y0, roi.y0), std::min(r.x1, roi.x1),
       std::min(r.y1, roi.y1)};
  return r.x1 > r.x0 && r.y1 > r.y0 ? r : PixelRect{};
}

}  // namespace panoproj
