#include "panoproj/convert.hpp"

#include <cmath>
#include <sstream>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "base/parallel.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {

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
  Projection source = make_projection(from, source_size);
  Size size;
  if (o.size) {
    size = *o.size;
    if (size.width < 1 || size.height < 1 || size.width > kMaxSide || size.height > kMaxSide)
      throw Error("size: " + size_text(size) + " (expected 1 to " + std::to_string(kMaxSide) + " pixels a side)");
  } else {
    size = default_size(to, center_density(source));
  }
  Projection target = make_projection(to, size);
  // Absurd sizes stop here, before any per-tile work: the output alone, at one byte a pixel.
  require_memory("output " + size_text(size_of(target)), image_bytes(size_of(target), 1, 1), o.memory_limit);
  return {std::move(source), std::move(target), rotation_from_ypr(o.yaw, o.pitch, o.roll)};
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
                        const ConvertOptions& options, uint64_t more) {
  const Size out = size_of(geometry.target);
  const int out_channels = channels + (options.add_alpha && channels < 4 && channels != 2 ? 1 : 0);
  require_memory("output " + size_text(out) + " (" + std::to_string(out_channels) + " channels of " + name_of(type) + ")",
                 add_bytes(image_bytes(out, out_channels, bytes_of(type)), more), options.memory_limit);
}

Image convert(const Image& source, const ProjectionSpec& from, const ProjectionSpec& to,
              const ConvertOptions& options) {
  const ConversionGeometry geometry = make_geometry(source.size(), from, to, options);
  require_job_memory(geometry, source.channels(), source.type(), options, 0);
  Image storage;
  return converter_for(geometry, options).run(source_for(source, options, storage));
}

Converter converter_for(const ConversionGeometry& geometry, const ConvertOptions& options, bool cache_map) {
  return Converter(geometry.source, geometry.target, geometry.rotation, options.interp, options.engine,
                   options.threads, cache_map, antialias_of(options), options.edges);
}

}  // namespace panoproj
