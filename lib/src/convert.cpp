#include "panoproj/convert.hpp"

#include <cmath>
#include <sstream>

#include "panoproj/error.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {

Plan make_plan(Size source_size, const ProjectionSpec& from, const ProjectionSpec& to,
               const ConvertOptions& o) {
  for (const auto& [name, v] : {std::pair{"yaw", o.yaw}, {"pitch", o.pitch}, {"roll", o.roll}}) {
    if (!std::isfinite(v) || std::fabs(v) > 1e6) {
      std::ostringstream s;
      s << name << ": " << v << " (expected a finite angle in degrees)";
      throw Error(s.str());
    }
  }
  if (o.threads < 0)
    throw Error("threads: " + std::to_string(o.threads) + " (expected 0 for all cores, or more)");
  Projection source = make_projection(from, source_size);
  Size size;
  if (o.size) {
    size = *o.size;
    if (size.width < 1 || size.height < 1)
      throw Error("size: " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                  " (expected at least 1x1)");
  } else {
    size = default_size(to, center_density(source));
  }
  Projection target = make_projection(to, size);
  return {std::move(source), std::move(target), rotation_from_ypr(o.yaw, o.pitch, o.roll)};
}

Antialias antialias_of(const ConvertOptions& options) {
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

Image convert(const Image& source, const ProjectionSpec& from, const ProjectionSpec& to,
              const ConvertOptions& options) {
  const Plan plan = make_plan(source.size(), from, to, options);
  Image storage;
  return Converter(plan.source, plan.target, plan.rotation, options.interp, options.engine, options.threads, false,
                   antialias_of(options), options.edges)
      .run(source_for(source, options, storage));
}

}  // namespace panoproj
