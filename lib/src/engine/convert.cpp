#include "panoproj/convert.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "base/parallel.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {

namespace {

StereoLayout stereo_layout(const ProjectionSpec& s) {
  const std::string l = s.choice("stereo");
  return l == "tb" ? StereoLayout::TopBottom : l == "sbs" ? StereoLayout::SideBySide : StereoLayout::Mono;
}

Stereo stereo_of(const ProjectionSpec& from, const ProjectionSpec& to) {
  const Stereo s{stereo_layout(from), stereo_layout(to), from.choice("eye") == "right" ? 1 : 0};
  if (from.given("eye") && s.source == StereoLayout::Mono)
    throw Error(from.str() + ": eye=" + from.choice("eye") + " picks an eye of a stereo source (add stereo=tb or sbs)");
  if (to.given("eye"))
    throw Error(to.str() + ": eye= is for the source (a stereo target gets both eyes; a mono one the source's eye=)");
  if (from.given("eye") && s.target != StereoLayout::Mono)
    throw Error(from.str() + ": eye= with a stereo target (it gets both eyes; drop eye= or make the target mono)");
  for (const ProjectionSpec* p : {&from, &to})
    if (stereo_layout(*p) != StereoLayout::Mono && p->kind() == Kind::Cubemap && p->choice("layout") == "files")
      throw Error(p->str() + ": stereo= with layout=files (stereo cubes are one image: use layout 6x1, 3x2, eac, ...)");
  return s;
}

}  // namespace

Size stereo_frame(Size eye, StereoLayout layout) {
  if (layout == StereoLayout::TopBottom) return {eye.width, 2 * eye.height};
  if (layout == StereoLayout::SideBySide) return {2 * eye.width, eye.height};
  return eye;
}

Size stereo_eye(Size frame, StereoLayout layout, const char* what) {
  if (layout == StereoLayout::Mono) return frame;
  const bool tb = layout == StereoLayout::TopBottom;
  if ((tb ? frame.height : frame.width) % 2 != 0)
    throw Error(std::string(what) + ": " + size_text(frame) + " does not split into two eyes " +
                (tb ? "top and bottom (stereo=tb needs an even height)" : "side by side (stereo=sbs needs an even width)"));
  return tb ? Size{frame.width, frame.height / 2} : Size{frame.width / 2, frame.height};
}

std::array<int64_t, 2> stereo_origin(Size eye, StereoLayout layout, int e) {
  if (layout == StereoLayout::TopBottom) return {0, e * eye.height};
  if (layout == StereoLayout::SideBySide) return {e * eye.width, 0};
  return {0, 0};
}

namespace {

// The smallest side of a default output size; below it the field is refused, not rendered.
constexpr int64_t kMinDefaultSide = 8;

// Throws unless some pixel of p has a direction: pixel centres on a grid of up to 256 x 256 (every
// pixel of a smaller frame) and the frame's centre.
void require_valid_pixels(const Projection& p, const ProjectionSpec& spec, const char* role) {
  const Size s = size_of(p);
  const int64_t nx = std::min<int64_t>(s.width, 256), ny = std::min<int64_t>(s.height, 256);
  Ray d;
  if (to_ray(p, 0.5 * static_cast<double>(s.width), 0.5 * static_cast<double>(s.height), d)) return;
  for (int64_t j = 0; j < ny; ++j)
    for (int64_t i = 0; i < nx; ++i) {
      const double x = std::floor((static_cast<double>(i) + 0.5) * static_cast<double>(s.width) / static_cast<double>(nx)) + 0.5;
      const double y = std::floor((static_cast<double>(j) + 0.5) * static_cast<double>(s.height) / static_cast<double>(ny)) + 0.5;
      if (to_ray(p, x, y, d)) return;
    }
  throw Error(std::string(role) + ": " + spec.str() + " on a " + size_text(s) +
              " frame has no pixel that sees a direction (its valid region is empty or under a pixel): give "
              "parameters that show a field");
}

}  // namespace

ConversionGeometry make_geometry(Size source_size, const ProjectionSpec& from, const ProjectionSpec& to,
                                 const ConvertOptions& o) {
  for (const auto& [name, v] : {std::pair{"yaw", o.yaw}, {"pitch", o.pitch}, {"roll", o.roll}}) {
    if (!std::isfinite(v) || std::fabs(v) > 1e6) {
      std::ostringstream s;
      s << name << ": " << v << (std::isfinite(v) ? " (expected degrees within +-1e6; any angle mod 360 turns alike)"
                                                  : " (expected a finite angle in degrees)");
      throw Error(s.str());
    }
  }
  check_threads(o.threads);
  const Stereo stereo = stereo_of(from, to);
  Projection source = make_projection(from, stereo_eye(source_size, stereo.source, "the source"));
  Size size;
  if (o.size) {
    size = *o.size;
    if (size.width < 1 || size.height < 1 || size.width > kMaxSide || size.height > kMaxSide)
      throw Error("size: " + size_text(size) + " (expected 1 to " + std::to_string(kMaxSide) + " pixels a side)");
    size = stereo_eye(size, stereo.target, "size");
  } else {
    size = default_size(to, center_density(source));
    if (size.width < kMinDefaultSide || size.height < kMinDefaultSide)
      throw Error("to: " + to.str() + " at the source's resolution would be " + size_text(size) + " (under " +
                  std::to_string(kMinDefaultSide) + " px a side: its field spans fewer than " +
                  std::to_string(kMinDefaultSide) + " of the source's pixels); give " + option_text("size") +
                  " WxH, or a wider field");
  }
  Projection target = make_projection(to, size);
  require_valid_pixels(source, from, "from");
  require_valid_pixels(target, to, "to");
  // Absurd sizes stop here, before any per-tile work: the output alone, at one byte a pixel.
  const Size frame = stereo_frame(size_of(target), stereo.target);
  if (frame.width > kMaxSide || frame.height > kMaxSide)
    throw Error("size: both eyes' " + size_text(frame) + " (expected at most " + std::to_string(kMaxSide) + " pixels a side)");
  require_memory("output " + size_text(frame), image_bytes(frame, 1, 1), o.memory_limit);
  return {std::move(source), std::move(target), rotation_from_ypr(o.yaw, o.pitch, o.roll), stereo};
}

void require_mono(const ConversionGeometry& g, const char* what) {
  if (g.stereo.any())
    throw Error(std::string(what) + ": stereo= (they are one eye's: give one eye's specs and size without stereo=)");
}

Antialias antialias_of(const ConvertOptions& options) {
  // nearest copies source pixels (labels, masks, ids): it never averages them.
  if (options.interp == Interp::Nearest) {
    if (options.antialias && options.antialias->mode != Antialias::Mode::Off)
      throw Error(option_text("antialias", name_of(*options.antialias)) + " with " +
                  option_text("interp", "nearest") + ": nearest copies source pixels and never averages them (give " +
                  option_text("antialias", "off") + ", or another interp)");
    return {Antialias::Mode::Off, 1};
  }
  if (options.antialias) return *options.antialias;
  return {options.engine == Engine::Reference ? Antialias::Mode::Off : Antialias::Mode::Auto, 1};
}

const Image& source_for(const Image& source, const ConvertOptions& options, Image& storage) {
  if (!options.add_alpha || source.alpha_channel() >= 0) return source;
  if (source.channels() > 3)
    throw Error("alpha: the image has " + std::to_string(source.channels()) +
                " channels and none is alpha (give at most 3 channels, or no --alpha)");
  storage = source.with_alpha();
  return storage;
}

void require_job_memory(const ConversionGeometry& geometry, int channels, PixelType type,
                        const ConvertOptions& options, uint64_t more, const std::string& more_what) {
  const Size out = geometry.target_frame();
  const int out_channels = channels + (options.add_alpha && channels < 4 && channels != 2 ? 1 : 0);
  require_memory("output " + size_text(out) + " (" + std::to_string(out_channels) + " channels of " + name_of(type) + ")" +
                     (more > 0 ? " with " + more_what : ""),
                 add_bytes(image_bytes(out, out_channels, bytes_of(type)), more), options.memory_limit);
}

Image convert(const Image& source, const ProjectionSpec& from, const ProjectionSpec& to,
              const ConvertOptions& options) {
  const ConversionGeometry geometry = make_geometry(source.size(), from, to, options);
  require_job_memory(geometry, source.channels(), source.type(), options, 0);
  Image storage;
  return converter_for(geometry, options).run(source_for(source, options, storage));
}

Converter converter_for(const ConversionGeometry& geometry, const ConvertOptions& options, Keep keep) {
  return Converter(geometry.source, geometry.target, geometry.rotation, options.interp, options.engine,
                   options.threads, keep, antialias_of(options), options.edges, geometry.stereo);
}

}  // namespace panoproj
