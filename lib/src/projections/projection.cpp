// The generic entry points of projection.hpp: each looks the projection's module up by Kind
// (module.hpp) or by the variant's index, which follow the same list (projections/list.hpp).
#include "panoproj/projection.hpp"

#include <sstream>
#include <string>

#include "projections/module.hpp"
#include "panoproj/error.hpp"

namespace panoproj {

const ProjectionModule& module_of(Kind kind) {
#define PANOPROJ_MODULE_ADDRESS_(Type) &k##Type##Module,
  static const ProjectionModule* const modules[] = {PANOPROJ_PROJECTIONS(PANOPROJ_MODULE_ADDRESS_)};
#undef PANOPROJ_MODULE_ADDRESS_
  static_assert(std::size(modules) == std::variant_size_v<Projection>);
  return *modules[static_cast<size_t>(kind)];
}

std::vector<ProjectionCase> projection_cases() {
  std::vector<ProjectionCase> all;
  for (size_t k = 0; k < std::variant_size_v<Projection>; ++k) {
    const std::vector<ProjectionCase> rows = module_of(static_cast<Kind>(k)).cases();
    all.insert(all.end(), rows.begin(), rows.end());
  }
  return all;
}

namespace {
const ProjectionModule& module_of(const Projection& p) { return module_of(static_cast<Kind>(p.index())); }
}  // namespace

Projection make_projection(const ProjectionSpec& s, Size size) {
  const ProjectionModule& m = module_of(s.kind());
  if (m.check) m.check(s);
  if (size.width < 1 || size.height < 1) {
    std::ostringstream o;
    o << "size " << size.width << "x" << size.height << " is empty (expected at least 1x1)";
    throw Error(s.name() + ": " + o.str());
  }
  return m.make(s, size);
}

Size default_size(const ProjectionSpec& s, double density) {
  const ProjectionModule& m = module_of(s.kind());
  if (m.check) m.check(s);
  return m.default_size(s, density);
}

Projection rescaled(const Projection& p, Size size) {
  const Size old = size_of(p);
  const double sx = static_cast<double>(size.width) / static_cast<double>(old.width);
  const double sy = static_cast<double>(size.height) / static_cast<double>(old.height);
  return module_of(p).rescaled(p, size, sx, sy);
}

bool has_window(const Projection& p) {
  return module_of(p).window != nullptr;
}

Projection windowed(const Projection& p, const PixelRect& r) {
  if (!has_window(p) || r.width() <= 0 || r.height() <= 0)
    throw InternalError("no such window of the projection");
  return module_of(p).window(p, r);
}

SamplingFacts framed_facts(const Projection& p) {
  const Size s = size_of(p);
  SamplingFacts f;
  f.x1 = static_cast<double>(s.width), f.y1 = static_cast<double>(s.height);
  return f;
}

SamplingFacts sampling_facts(const Projection& p) {
  const ProjectionModule& m = module_of(p);
  return m.sampling ? m.sampling(p) : framed_facts(p);
}

bool shows_whole_sphere(const Projection& p) {
  const ProjectionModule& m = module_of(p);
  return m.whole_sphere && m.whole_sphere(p);
}

void to_ray_row(const Projection& p, double y, int64_t x0, int64_t n, Ray* rays, uint8_t* ok,
                double centre) {
  std::visit(
      [&](const auto& q) {
        for (int64_t i = 0; i < n; ++i)
          ok[i] = q.to_ray(static_cast<double>(x0 + i) + centre, y, rays[i]) ? 1 : 0;
      },
      p);
}

void to_pixel_row(const Projection& p, const Ray* rays, int64_t n, double* xs, double* ys, uint8_t* ok) {
  std::visit(
      [&](const auto& q) {
        for (int64_t i = 0; i < n; ++i)
          if (ok[i]) ok[i] = q.to_pixel(rays[i], xs[i], ys[i]) ? 1 : 0;
      },
      p);
}

}  // namespace panoproj
