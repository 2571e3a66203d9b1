// Crops and masks (layer_masks.hpp).
#include "jobs/stitch/layer_masks.hpp"

#include <algorithm>
#include <cstring>

#include "base/parallel.hpp"

namespace panoproj {

namespace {

// Whether the image's crop is the circle inscribed in its S rectangle: circular fisheyes (f2),
// Thoby's (f20) and orthographic ones (f8), as SrcPanoImage::isCircularCrop says.
bool circular_crop(const PtoImage& im) {
  return im.lens_type == 2 || im.lens_type == 8 || im.lens_type == 20;
}

}  // namespace

std::optional<CropCircle> crop_circle(const PtoImage& im) {
  if (im.circle) return CropCircle{(*im.circle)[0], (*im.circle)[1], (*im.circle)[2]};
  if (!im.crop || !circular_crop(im)) return std::nullopt;
  const PtoRect& r = *im.crop;  // the circle inscribed in the rectangle
  return CropCircle{0.5 * static_cast<double>(r.left + r.right),
                    0.5 * static_cast<double>(r.top + r.bottom),
                    0.5 * static_cast<double>(std::min(r.right - r.left, r.bottom - r.top))};
}

bool inside_crop(const PtoImage& im, double x, double y) {
  if (const auto c = crop_circle(im))
    return (x - c->cx) * (x - c->cx) + (y - c->cy) * (y - c->cy) < c->radius * c->radius;
  if (!im.crop) return true;
  const PtoRect& r = *im.crop;
  return x >= static_cast<double>(r.left) && x < static_cast<double>(r.right) &&
         y >= static_cast<double>(r.top) && y < static_cast<double>(r.bottom);
}

bool inside_include_clip(const PtoImage& im, double x, double y) {
  PtoRect r{0, im.width, 0, im.height};
  if (const auto c = crop_circle(im)) {
    const double radius = c->radius > 10 ? c->radius - 2 : c->radius;
    return (x - c->cx) * (x - c->cx) + (y - c->cy) * (y - c->cy) <= radius * radius;
  }
  if (im.crop)
    r = {std::max(r.left, im.crop->left), std::min(r.right, im.crop->right),
         std::max(r.top, im.crop->top), std::min(r.bottom, im.crop->bottom)};
  if (r.right - r.left > 10 && r.bottom - r.top > 10)
    r = {r.left + 2, r.right - 2, r.top + 2, r.bottom - 2};
  return x >= static_cast<double>(r.left) && x <= static_cast<double>(r.right) &&
         y >= static_cast<double>(r.top) && y <= static_cast<double>(r.bottom);
}

std::vector<double> crossings(const std::vector<double>& xy, double y) {
  std::vector<double> out;
  const size_t n = xy.size() / 2;
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const double xi = xy[2 * i], yi = xy[2 * i + 1], xj = xy[2 * j], yj = xy[2 * j + 1];
    if ((yi > y) != (yj > y)) out.push_back((xj - xi) * (y - yi) / (yj - yi) + xi);
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool inside_polygon(const std::vector<double>& xy, double x, double y) {
  const std::vector<double> c = crossings(xy, y);
  return (c.end() - std::upper_bound(c.begin(), c.end(), x)) % 2 == 1;
}

std::vector<const PtoMask*> image_masks(const PtoProject& p, int index) {
  std::vector<const PtoMask*> out;
  const int lens = p.images[static_cast<size_t>(index)].lens;
  for (const PtoMask& m : p.masks) {
    if ((m.type == 0 || m.type == 2) && m.image == index) out.push_back(&m);
    if (m.type == 4 && p.images[static_cast<size_t>(m.image)].lens == lens) out.push_back(&m);
  }
  return out;
}

namespace {

void clear_alpha(Image& im, int64_t x, int64_t y) {
  unsigned char* px = im.pixel(x, y) + static_cast<size_t>(im.channels() - 1) * bytes_of(im.type());
  std::memset(px, 0, bytes_of(im.type()));
}

}  // namespace

void mask_source(const PtoProject& p, int index, double sx, double sy, Image& source) {
  const PtoImage& im = p.images[static_cast<size_t>(index)];
  const std::vector<const PtoMask*> masks = image_masks(p, index);
  if (!im.crop && !im.circle && masks.empty()) return;
  parallel_rows(source.size().height, 0, [&](int64_t y0, int64_t y1) {
    std::vector<std::vector<double>> rows(masks.size());
    std::vector<size_t> next(masks.size());
    for (int64_t y = y0; y < y1; ++y) {
      // The project's position of the file's pixel centres, in Hugin's coordinates; each mask's
      // crossings of the row, passed left to right (inside: an odd number of them to the right).
      const double hy = (static_cast<double>(y) + 0.5) / sy - 0.5;
      for (size_t k = 0; k < masks.size(); ++k) rows[k] = crossings(masks[k]->xy, hy), next[k] = 0;
      for (int64_t x = 0; x < source.size().width; ++x) {
        const double hx = (static_cast<double>(x) + 0.5) / sx - 0.5;
        bool keep = inside_crop(im, hx, hy);
        for (size_t k = 0; k < masks.size(); ++k) {
          while (next[k] < rows[k].size() && rows[k][next[k]] <= hx) ++next[k];
          if ((rows[k].size() - next[k]) % 2 == 1) keep = false;
        }
        if (!keep) clear_alpha(source, x, y);
      }
    }
  });
}

std::vector<PanoExclusion> pano_exclusions(const PtoProject& p, int index) {
  std::vector<PanoExclusion> out;
  const int stack = p.images[static_cast<size_t>(index)].stack;
  for (const PtoMask& m : p.masks) {
    if (m.image == index) continue;
    const PtoImage& owner = p.images[static_cast<size_t>(m.image)];
    if (owner.disabled) continue;
    const bool same_stack = owner.stack == stack;
    if (m.type == 1 || (m.type == 3 && !same_stack)) out.push_back({m.image, &m, true});
    if (m.type == 2 && same_stack) out.push_back({m.image, &m, false});
  }
  return out;
}

}  // namespace panoproj
