#pragma once
// A projection's module: everything around its math (lib/include/panoproj/projections/<name>.hpp)
// in one file, lib/src/projections/<name>.cpp, which defines k<Type>Module. The generic entry
// points (projection_catalog, make_projection, default_size, rescaled, shows_whole_sphere) look
// the module up by Kind; nothing else switches over the projections.
#include <vector>

#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"

namespace panoproj {

struct ProjectionModule {
  // Its catalogue entries (names, keys, defaults, ranges; kind is filled in by the catalogue).
  std::vector<ProjectionDef> (*catalog)();
  // Validation that does not depend on the frame; throws Error naming the key. Null: none.
  void (*check)(const ProjectionSpec& spec);
  // The projection on a frame of `size` (checked and non-empty); throws Error.
  Projection (*make)(const ProjectionSpec& spec, Size size);
  // The size with `density` pixels per radian at the centre (checked spec; framed_size helps).
  Size (*default_size)(const ProjectionSpec& spec, double density);
  // The same field on a frame of `size`: positions scale by (sx, sy) = size / p's size. Throws
  // Error if the frame cannot hold it.
  Projection (*rescaled)(const Projection& p, Size size, double sx, double sy);
  // Whether it shows the whole sphere (a conversion to it reads every pixel of any source);
  // null: never.
  bool (*whole_sphere)(const Projection& p) = nullptr;
};

// whole_sphere of the forms that always show it.
inline bool always(const Projection&) { return true; }

#define PANOPROJ_MODULE_(Type) extern const ProjectionModule k##Type##Module;
PANOPROJ_PROJECTIONS(PANOPROJ_MODULE_)
#undef PANOPROJ_MODULE_

const ProjectionModule& module_of(Kind kind);

}  // namespace panoproj
