// One layer (stitch.hpp): the image with its crop and masks as alpha, remapped onto the canvas,
// other images' masks taken out there, alpha made 0 or full, its samples corrected (the
// image's photometry, in float), cropped to what is kept.
#include <algorithm>
#include <atomic>
#include <cstring>

#include "base/parallel.hpp"
#include "jobs/stitch/layer_masks.hpp"
#include "jobs/stitch/pano_spec.hpp"
#include "jobs/stitch/stitch.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {
namespace {

template <class T>
void finish_rows(Image& canvas, const PixelRect& roi, int64_t y0, int64_t y1, PixelRect& kept) {
  const int ch = canvas.channels();
  const double unit = unit_of(canvas.type());
  const double threshold = 0.2 * unit;
  for (int64_t y = y0; y < y1; ++y) {
    auto* row = reinterpret_cast<T*>(canvas.row(y));
    for (int64_t x = 0; x < canvas.size().width; ++x) {
      T* px = row + x * ch;
      const bool keep = static_cast<double>(px[ch - 1]) > threshold && x >= roi.x0 && x < roi.x1 &&
                        y >= roi.y0 && y < roi.y1;
      if (!keep) {
        std::fill(px, px + ch, T{});
        continue;
      }
      px[ch - 1] = static_cast<T>(unit);
      kept.x0 = std::min(kept.x0, x), kept.x1 = std::max(kept.x1, x + 1);
      kept.y0 = std::min(kept.y0, y), kept.y1 = std::max(kept.y1, y + 1);
    }
  }
}

// Alpha 0 or full (over 0.2: nona's ImageMaskInterpolator), nothing outside `roi` (the layer's
// extent); returns the bounding box of what is kept (empty: none).
PixelRect finish_alpha(Image& canvas, const PixelRect& roi, int threads) {
  const int64_t h = canvas.size().height;
  const int n = workers_for(h, threads);
  std::vector<PixelRect> kept(static_cast<size_t>(n), PixelRect{INT64_MAX, INT64_MAX, 0, 0});
  parallel_tasks(n, threads, [&](int64_t k, int) {
    const int64_t y0 = h * k / n, y1 = h * (k + 1) / n;
    PixelRect& r = kept[static_cast<size_t>(k)];
    switch (canvas.type()) {
      case PixelType::U8:
        finish_rows<uint8_t>(canvas, roi, y0, y1, r);
        break;
      case PixelType::U16:
        finish_rows<uint16_t>(canvas, roi, y0, y1, r);
        break;
      default:
        finish_rows<float>(canvas, roi, y0, y1, r);
        break;
    }
  });
  PixelRect box{INT64_MAX, INT64_MAX, 0, 0};
  for (const PixelRect& r : kept)
    box = {std::min(box.x0, r.x0), std::min(box.y0, r.y0), std::max(box.x1, r.x1),
           std::max(box.y1, r.y1)};
  return box.x1 > box.x0 ? box : PixelRect{};
}

// Clears the alpha of `part` (of the panorama `pano`: the canvas or a window of it) where another
// image's mask covers it.
void exclude(const StitchPlan& plan, int index, const Projection& pano, Image& canvas) {
  const std::vector<PanoExclusion> masks = pano_exclusions(plan.project, index);
  if (masks.empty()) return;
  struct Owner {
    Projection lens;
    Eigen::Matrix3d rotation;
  };
  std::vector<Owner> owners;
  for (const PanoExclusion& m : masks) {
    const PtoImage& im = plan.project.images[static_cast<size_t>(m.image)];
    owners.push_back(
        {make_projection(parse_spec(image_spec(plan.project, im)), {im.width, im.height}),
         image_rotation(im)});
  }
  const int ch = canvas.channels();
  const size_t bytes = bytes_of(canvas.type());
  parallel_rows(canvas.size().height, plan.options.threads, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y)
      for (int64_t x = 0; x < canvas.size().width; ++x) {
        unsigned char* alpha = canvas.pixel(x, y) + static_cast<size_t>(ch - 1) * bytes;
        if (std::all_of(alpha, alpha + bytes, [](unsigned char b) { return b == 0; })) continue;
        Ray d;
        if (!to_ray(pano, static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, d)) continue;
        for (size_t k = 0; k < masks.size(); ++k) {
          double sx, sy;
          if (!to_pixel(owners[k].lens, owners[k].rotation * d, sx, sy)) continue;
          const PtoImage& im = plan.project.images[static_cast<size_t>(masks[k].image)];
          if (inside_polygon(masks[k].mask->xy, sx - 0.5, sy - 0.5) &&
              (!masks[k].within_crop || inside_include_clip(im, sx - 0.5, sy - 0.5))) {
            std::memset(alpha, 0, bytes);
            break;
          }
        }
      }
  });
}

Image crop(const Image& canvas, const PixelRect& box) {
  Image out(box.size(), canvas.channels(), canvas.type(), canvas.alpha_channel(),
            Image::Unfilled{});
  const size_t offset = static_cast<size_t>(box.x0) * canvas.pixel_bytes();
  for (int64_t y = box.y0; y < box.y1; ++y)
    std::memcpy(out.row(y - box.y0), canvas.row(y) + offset, out.row_bytes());
  return out;
}

// `part` placed at `extent` on an empty canvas.
Image on_canvas(const Image& part, Size canvas, const PixelRect& extent) {
  Image out(canvas, part.channels(), part.type(), part.alpha_channel());
  for (int64_t y = 0; y < part.size().height; ++y)
    std::memcpy(out.pixel(extent.x0, extent.y0 + y), part.row(y), part.row_bytes());
  return out;
}

}  // namespace

Image layer_source(const StitchPlan& plan, const StitchLayer& l, PixelType type) {
  ConvertOptions with_alpha = plan.options;
  with_alpha.add_alpha = true;
  // The file, or the frame in its place; a rig's lens in a shared frame: its rectangle (checked
  // inside when planned); alpha added.
  Image file = l.frame ? Image() : read_image(l.file, plan.options.memory_limit), cut, storage;
  const Image& whole = l.frame ? *l.frame : file;
  if (l.region) {
    if (whole.size().width < l.region->x1 || whole.size().height < l.region->y1)
      throw Error(l.file + ": changed while the job ran");
    cut = crop(whole, *l.region);
  }
  const Image& read = source_for(l.region ? cut : whole, with_alpha, storage);
  Image source = &read == &storage ? std::move(storage)
                 : &read == &cut   ? std::move(cut)
                 : &read == &file  ? std::move(file)
                                   : read;
  if (source.size() != l.size) throw Error(l.file + ": changed while the job ran");
  mask_source(plan.project, l.index, l.sx, l.sy, source);
  // Float layers from integer files: remapped in float, so nothing is rounded before the end.
  if (type != source.type()) source = convert_pixels(source, type);
  return source;
}

PixelType layer_work_type(const StitchPlan& plan, const StitchLayer& l, const ImageInfo& info) {
  const PixelType out =
      plan.depth.value_or(info.type == PixelType::F16 ? PixelType::F32 : info.type);
  // Corrected samples are made in float from the interpolated codes, rounded only at the end.
  return !l.photometry->identity() || out == PixelType::F32 ? PixelType::F32 : info.type;
}

Image render_window(const StitchPlan& plan, const StitchLayer& l, const Image& source,
                    const PixelRect& window, const PixelRect& extent, Image* weights) {
  const Projection pano = make_projection(*plan.pano, plan.canvas);
  const bool whole = window == PixelRect{0, 0, plan.canvas.width, plan.canvas.height};
  const ConversionGeometry geometry{make_projection(*l.spec, l.size),
                                    whole ? pano : windowed(pano, window), l.rotation};
  Image part = Converter(geometry, plan.options).run(source);
  exclude(plan, l.index, geometry.target, part);
  const PixelRect in_window{extent.x0 - window.x0, extent.y0 - window.y0, extent.x1 - window.x0,
                            extent.y1 - window.y0};
  finish_alpha(part, in_window, plan.options.threads);
  if (part.type() == PixelType::F32) {
    // A pixel's position in the image's own (Hugin's) pixels: the file's over its scale.
    const auto position = [&](double x, double y, double& sx, double& sy) {
      Ray d;
      if (!to_ray(geometry.target, x, y, d) ||
          !to_pixel(geometry.source, geometry.rotation * d, sx, sy))
        return false;
      sx = sx / l.sx - 0.5, sy = sy / l.sy - 0.5;
      return true;
    };
    l.photometry->apply(part, position, weights, plan.options.threads);
  }
  return part;
}

RenderedLayer render_layer(const StitchPlan& plan, const StitchLayer& l) {
  const PixelRect extent = layer_extent(plan, l);
  if (extent.width() == 0) return {};
  // Only the extent is made where the panorama has windows; else the canvas, then cut.
  const bool window = has_window(make_projection(*plan.pano, plan.canvas));
  const PixelRect made = window ? extent : PixelRect{0, 0, plan.canvas.width, plan.canvas.height};
  // Before the file is read: its samples (floats where the layer is), the part, the canvas.
  const ImageInfo& info = l.info;
  const int channels = info.channels == 1 || info.channels == 3 ? info.channels + 1 : info.channels;
  const PixelType out =
      plan.depth.value_or(info.type == PixelType::F16 ? PixelType::F32 : info.type);
  const PixelType work = layer_work_type(plan, l, info);
  const int64_t made_px = made.width() * made.height();
  const Projection pano = make_projection(*plan.pano, plan.canvas);
  require_job_memory(
      {make_projection(*l.spec, l.size), window ? windowed(pano, made) : pano, l.rotation},
      channels, work, plan.options,
      image_bytes(l.size, channels, bytes_of(work)) +
          (plan.cropped ? 0 : image_bytes(plan.canvas, channels, bytes_of(out))) +
          (plan.hdr ? made_px : 0),
      "the image and the canvas");
  Image weights;
  Image part = [&] {
    const Image source = layer_source(plan, l, work);
    return render_window(plan, l, source, made, extent, plan.hdr ? &weights : nullptr);
  }();
  const PixelRect in_made{extent.x0 - made.x0, extent.y0 - made.y0, extent.x1 - made.x0,
                          extent.y1 - made.y0};
  if (!window) {
    part = crop(part, in_made);
    if (plan.hdr) weights = crop(weights, in_made);
  }
  if (part.type() != out) part = convert_pixels(part, out);
  if (plan.cropped) return {std::move(part), extent.x0, extent.y0, std::move(weights)};
  return {on_canvas(part, plan.canvas, extent), 0, 0,
          plan.hdr ? on_canvas(weights, plan.canvas, extent) : Image()};
}

}  // namespace panoproj
