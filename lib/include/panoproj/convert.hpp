#pragma once
// One conversion, in memory: plan (projections bound to sizes, rotation) then remap.
#include <optional>

#include "panoproj/antialias.hpp"
#include "panoproj/engine.hpp"
#include "panoproj/image.hpp"
#include "panoproj/interpolator.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

struct ConvertOptions {
  double yaw = 0, pitch = 0, roll = 0;  // degrees, see rotation.hpp
  Interp interp = Interp::Bicubic;
  int threads = 0;                      // 0: all cores
  Engine engine = Engine::Simd;         // see engine.hpp
  std::optional<Antialias> antialias;   // see antialias.hpp; default: auto, off for the
                                        // reference engine (which has none)
  std::optional<Size> size;             // output size; default: default_size() at the source's
                                        // centre density (square pixels)
  EdgeFill edges;                       // edge_fill.hpp: pixels without a (whole) source
  bool add_alpha = false;               // give a source without alpha an opaque one first, so
                                        // the output has alpha (0 where it has no source)
  int64_t memory_limit = 0;             // bytes a job may allocate; 0: the memory available
                                        // (limits.hpp)
};

// Largest side of an output (the image formats' 32-bit sides).
inline constexpr int64_t kMaxSide = 2147483647;

// The source as the conversion takes it: with an opaque alpha channel added when add_alpha asks
// for one and it has none (in storage), else source itself (not copied).
const Image& source_for(const Image& source, const ConvertOptions& options, Image& storage);

struct Plan {
  Projection source, target;
  Eigen::Matrix3d rotation;
};

// options.antialias, or its default for options.engine.
Antialias antialias_of(const ConvertOptions& options);

// Throws panoproj::Error on bad parameters (non-finite angles, sizes, specs), and (ErrorKind::
// Memory) for an output that would not fit options.memory_limit even at one byte a pixel.
Plan make_plan(Size source_size, const ProjectionSpec& from, const ProjectionSpec& to,
               const ConvertOptions& options);
// Throws ErrorKind::Memory unless the plan's output of `channels` x `type` (one more channel with
// add_alpha) and `more` bytes fit options.memory_limit.
void require_job_memory(const Plan& plan, int channels, PixelType type, const ConvertOptions& options,
                        uint64_t more);
Image convert(const Image& source, const ProjectionSpec& from, const ProjectionSpec& to,
              const ConvertOptions& options);
// The plan's Converter with the options' kernel, engine, threads, antialiasing and edges
// (cache_map: keep the tile maps for many runs).
Converter converter_for(const Plan& plan, const ConvertOptions& options, bool cache_map = false);

}  // namespace panoproj
