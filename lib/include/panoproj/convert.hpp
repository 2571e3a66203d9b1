#pragma once
// Conversions in memory: the Converter (one geometry applied to any number of images), and one
// conversion from specs and options (its ConversionGeometry: projections bound to sizes, and
// the rotation; then the Converter). (Python's panoproj.Plan is a Converter with its options.)
//
// The Converter: output tiles of kTile x kTile pixels over a thread pool. Per tile:
//   - common pairs (lib/src/simd/geometry.hpp): each vector of output pixels computes its source
//     positions in double SIMD registers and samples them at once (fused, no map);
//   - other pairs: a tile map (lib/src/geometry/tile_map.hpp, cubic interpolation of exact
//     nodes, within 1/256 px),
//     then the same SIMD sampling from the map.
// The SIMD kernels (simd_sampler.hpp) take every sample whose taps stay inside one cube face or
// the frame; the rest (seams, poles, face edges) get the reference sampler's tap rules (wrap,
// pole crossing, cube neighbours, clamp). The scalar engine samples everything with the reference.
// Tiles are fixed by the image size, not the thread count, so any number of threads gives the
// same bytes.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <optional>
#include <string_view>

#include "panoproj/image.hpp"
#include "panoproj/options.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

class SourceCorrection;

// Bytes a cached map takes per output pixel (double x, y and a validity byte).
inline constexpr int64_t kCachedMapBytesPerPixel = 2 * sizeof(double) + 1;

// Stereo frames (every projection's stereo= key): two eyes, top and bottom (tb: the left eye on
// top) or side by side (sbs: the left eye on the left), each a whole frame of the projection.
enum class StereoLayout { Mono, TopBottom, SideBySide };
struct Stereo {
  StereoLayout source = StereoLayout::Mono, target = StereoLayout::Mono;
  int eye = 0;  // the source eye (0 left, 1 right) a mono target takes (eye= on the source)
  bool any() const { return source != StereoLayout::Mono || target != StereoLayout::Mono; }
};
// Both eyes' frame from one eye's, and one eye's from both (Error if the frame does not split
// evenly); the pixels [x0, y0] of eye e.
Size stereo_frame(Size eye, StereoLayout layout);
Size stereo_eye(Size frame, StereoLayout layout, const char* what);
std::array<int64_t, 2> stereo_origin(Size eye, StereoLayout layout, int e);

// A conversion's geometry: both projections bound to their frames (one eye's where stereo), the
// rotation, and the stereo frames.
struct ConversionGeometry {
  Projection source, target;
  Eigen::Matrix3d rotation;
  Stereo stereo = {};
  // Where the planes' samples sit (projection.hpp: a video's chroma planes); such geometry takes
  // tile maps (never the fused SIMD geometry) and the simd or scalar engine, without edge fills.
  Siting siting = {};
  // The source's photometric correction (its spec's photometric keys), or null: the Converter
  // corrects each source before sampling it (photometry/source_correction.hpp).
  std::shared_ptr<const SourceCorrection> correction = nullptr;
  Size source_frame() const { return stereo_frame(size_of(source), stereo.source); }
  Size target_frame() const { return stereo_frame(size_of(target), stereo.target); }
};

// The most bytes a Converter of this geometry keeps per output pixel (kCachedMapBytesPerPixel; a
// dual-fisheye source's two lenses, twice that, and 4 for their blend's weight).
int kept_bytes_per_pixel(const ConversionGeometry& geometry);

struct EngineStats {
  int64_t tiles = 0;
  int64_t fused_tiles = 0;   // geometry in registers, no map (simd engine, the common pairs)
  int64_t replayed_tiles = 0;  // fused tiles whose taps an earlier run planned (Keep::MapsAndTaps)
  int64_t simd_misses = 0;  // samples the SIMD kernels left to the reference's tap rules
  int64_t interpolated_cells = 0, exact_cells = 0;  // tile_map.hpp cells of the other tiles
  EngineStats& operator+=(const EngineStats& o) {
    tiles += o.tiles, fused_tiles += o.fused_tiles, replayed_tiles += o.replayed_tiles, simd_misses += o.simd_misses;
    interpolated_cells += o.interpolated_cells, exact_cells += o.exact_cells;
    return *this;
  }
};

// What a Converter keeps for its later runs (at most kCachedMapBytesPerPixel per output pixel).
enum class Keep {
  Nothing,
  // The tile maps of the tiles that are not fused, built on first use: batches and video frames
  // pay for that geometry once. Fused tiles recompute theirs: in registers it costs less than
  // reading a stored map. With auto antialiasing, also each tile's footprint measure; from a dual
  // fisheye, each tile's blend of its lenses.
  Maps,
  // Also the taps each fused tile plans on the run that first samples it (8 bytes a pixel for
  // uint8 bilinear without alpha, else 12; not tiles on sub-pixels or mip levels): later runs on
  // sources of the same layout (window, channels, type) only gather and blend, to the same bytes.
  // For many runs of one plan (Python's Plan, batches).
  MapsAndTaps,
};

// One geometry (projections, rotation, kernel), applied to any number of images of the source's
// size, keeping what `keep` says for later runs. run() may be called from several threads at once.
// Antialiasing (options.hpp: Antialias) needs the simd or scalar engine; mip builds the source's
// levels on each run, as far as they are read.
class Converter {
 public:
  // The geometry's projections (each eye's where stereo: src and out are frames of both eyes
  // where it says so; each eye converts alone, so no tap crosses between eyes) and rotation; the
  // options' kernel, engine, threads, antialiasing (antialias_of) and edges (EdgeFill: what
  // pixels without a source, or on the field's edge, get; by default 0, decided at pixel
  // centres). Its size and rotation options are the geometry's already (make_geometry).
  Converter(const ConversionGeometry& geometry, const ConvertOptions& options,
            Keep keep = Keep::Nothing);

  // Throws panoproj::Error if src's size is not the source projection's. progress, if given,
  // is called from the calling thread with the fraction of tiles done.
  Image run(const Image& src, EngineStats* stats = nullptr,
            const std::function<void(double)>& progress = {}) const;
  // The same into out, reusing its buffer when it already has the output's size and layout
  // (video frames, batches: no new memory per frame). finished: as run_reading's, below.
  void run(const Image& src, Image& out, EngineStats* stats = nullptr,
           const std::function<void(double)>& progress = {},
           const std::function<void(const PixelRect&)>& finished = {}) const;
  // The same while src is read: read(arrived) runs once, first, on one of the run's threads; it
  // fills src (its buffer already the window's size) from the top, calling arrived as its rows
  // come in (RowsArrived, image.hpp). Tiles go in the order their source rows come, each once
  // the rows it reads are in (once all are, for mip, cube and dual-fisheye sources and the
  // reference engine). An exception from read ends the run; it is rethrown. finished, if given,
  // is called from the run's threads with each part of out once its pixels are final (each pixel
  // once; out is allocated by then): to encode it while the rest is made. Parts an edge fill
  // (EdgeFill) or the reference engine finishes later are not reported.
  void run_reading(const Image& src, Image& out,
                   const std::function<void(const RowsArrived&)>& read,
                   EngineStats* stats = nullptr, const std::function<void(double)>& progress = {},
                   const std::function<void(const PixelRect&)>& finished = {}) const;

  // The source pixels [x0, x1) x [y0, y1) that run() reads (with the kernel's taps and the
  // tap rules: a seam or pole crossing widens it to the full width; cubemap sources and targets
  // showing the whole sphere (cubemap, full equirect, the world maps) read all). Read
  // only this part of a large source. With Keep::Maps or more it builds and keeps the tile maps (run()
  // then reuses them); without, it maps tile by tile and keeps nothing.
  PixelRect source_footprint() const;

  const Projection& source() const;
  const Projection& target() const;
  const Stereo& stereo() const;
  Size source_frame() const;  // the image run() takes (both eyes of a stereo source)
  Size target_frame() const;  // the image run() makes
  const Antialias& antialias() const;

  ~Converter();
  Converter(Converter&&) noexcept;
  Converter& operator=(Converter&&) noexcept;

 private:
  struct Impl;  // lib/src/engine/engine.cpp
  std::unique_ptr<Impl> impl_;
};

// The SIMD target in use (e.g. "AVX2").
const char* simd_target();

// Largest side of an output (the image formats' 32-bit sides).
inline constexpr int64_t kMaxSide = 2147483647;

// The source as the conversion takes it: with an opaque alpha channel added when add_alpha asks
// for one and it has none (in storage), else source itself (not copied).
const Image& source_for(const Image& source, const ConvertOptions& options, Image& storage);
// The output's channels for a source of `channels`: one more (alpha, last) with add_alpha unless
// the source has alpha already (2 or 4 channels).
int output_channels(int channels, const ConvertOptions& options);

// Throws Error naming `what` (maps, accuracy: one eye's work) where the geometry is stereo.
void require_mono(const ConversionGeometry& geometry, const char* what);
// Throws Error naming `what` and `instead` where the geometry corrects its source's colours
// (photometric keys) and `what` cannot (maps and accuracy hold positions; a video's planes).
void require_no_correction(const ConversionGeometry& geometry, const std::string& what,
                           const std::string& instead);

// options.antialias, or its default for options.engine.
Antialias antialias_of(const ConvertOptions& options);

// Throws panoproj::Error on bad parameters (non-finite angles, sizes, specs), and (ErrorKind::
// Memory) for an output that would not fit options.memory_limit even at one byte a pixel.
ConversionGeometry make_geometry(Size source_size, const ProjectionSpec& from, const ProjectionSpec& to,
                                 const ConvertOptions& options);
// Throws ErrorKind::Memory unless the geometry's output of `channels` x `type` (one more channel with
// add_alpha) and `more` bytes (named by more_what in the message) fit options.memory_limit.
void require_job_memory(const ConversionGeometry& geometry, int channels, PixelType type,
                        const ConvertOptions& options, uint64_t more,
                        const std::string& more_what = "the job's maps and buffers");
Image convert(const Image& source, const ProjectionSpec& from, const ProjectionSpec& to,
              const ConvertOptions& options);
// The smallest step, in source pixels, from an output pixel's source position to its neighbours'
// in any direction (the least singular value of the map's Jacobian, steps across a seam taken the
// short way), over the output sampled every 16 pixels (at most 257 x 257 points); infinity where
// no output pixel has a source. Returns at the first step under stop_below (e.g. 4: no scale
// would apply) without sampling the rest.
double finest_source_step(const ConversionGeometry& geometry, double stop_below = 0);
// The coarsest scale s (8, 4, 2, else 1) whose decode still holds twice the detail the view
// resolves (2 s <= finest_step) and that divides the source's sides (the 1/s frame is then the
// same field exactly: its pixel i covers pixels s i .. s i + s - 1).
int coarsest_decode_scale(const ConversionGeometry& geometry, double finest_step);

}  // namespace panoproj
