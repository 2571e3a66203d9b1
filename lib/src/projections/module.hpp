#pragma once
// A projection's module: everything around its math (lib/include/panoproj/projections/<name>.hpp)
// in one file, lib/src/projections/<name>.cpp, which defines k<Type>Module. The generic entry
// points (projection_catalog, make_projection, default_size, rescaled, shows_whole_sphere) look
// the module up by Kind; nothing else switches over the projections.
#include <string>
#include <vector>

#include "geometry/sampling_facts.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"

namespace panoproj {

// One row of a case table: a spec at the sizes it is checked at, and the bound of its round
// trips there in pixels (pixel -> ray -> pixel as a distance; ray -> pixel -> ray as an angle
// over one pixel's angle).
struct ProjectionCase {
  std::string spec;
  std::vector<Size> sizes;
  double bound_px = 1e-6;
};

// Sizes the tables share: a single pixel, a photo, and a frame over 32767 px each way.
inline constexpr Size kTinyFrame{1, 1}, kPhotoFrame{4096, 2048}, kHugeFrame{40000, 20000};

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
  // Its case table: the specs and sizes the stability report and the round-trip, extremes and
  // SIMD tests check it at (its parameters' extremes and ordinary values, 1x1 to 40000 px).
  std::vector<ProjectionCase> (*cases)();
  // Whether it shows the whole sphere (a conversion to it reads every pixel of any source);
  // null: never.
  bool (*whole_sphere)(const Projection& p) = nullptr;
  // What sampling needs to know of it as a source (geometry/sampling_facts.hpp); null: the frame,
  // clamped.
  SamplingFacts (*sampling)(const Projection& p) = nullptr;
  // The part r of p's frame as a frame of its own (pixel (i, j) of it is p's (r.x0 + i, r.y0 + j)):
  // only a layer's part of a canvas is made. Null: none (projection.hpp: has_window).
  Projection (*window)(const Projection& p, const PixelRect& r) = nullptr;
};

// whole_sphere of the forms that always show it.
inline bool always(const Projection&) { return true; }

#define PANOPROJ_MODULE_(Type) extern const ProjectionModule k##Type##Module;
PANOPROJ_PROJECTIONS(PANOPROJ_MODULE_)
#undef PANOPROJ_MODULE_

const ProjectionModule& module_of(Kind kind);

// Every module's case table, in catalogue order.
std::vector<ProjectionCase> projection_cases();

}  // namespace panoproj
