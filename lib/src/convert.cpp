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

Image convert(const Image& source, const ProjectionSpec& from, const ProjectionSpec& to,
              const ConvertOptions& options) {
  const Plan plan = make_plan(source.size(), from, to, options);
  return Converter(plan.source, plan.target, plan.rotation, options.interp, options.engine, options.threads, false,
                   antialias_of(options))
      .run(source);
}

}  // namespace panoproj
