#pragma once
// Multires cube tile pyramids for web viewers (Pannellum, Marzipano), rendered straight from the
// source: each tile is a region of a 90-degree cube face at its level's size, a pinhole view
// whose principal point is shifted to the region, antialiased from the source by the
// conversion's kernel (auto: the footprint kernel). No face is made whole, no level is made by
// halving another.
//
// Faces (both viewers' letters) f r b l u d: front (the source's centre, after the rotation
// options), right, back, left, up, down; sides upright, up seen by pitching up from the front
// (its lower edge meets the front's upper edge), down by pitching down.
//
// Layouts:
//   pannellum: OUT/<l>/<face><row>_<col>.<ext>, l = 1 .. maxLevel; level l's faces are
//     floor(cubeResolution / 2^(maxLevel - l)) px (generate.py's repeated halving, floored);
//     cubeResolution defaults to generate.py's 8 * floor(2 d / 8) (d: the source's pixels per
//     radian at its centre; W / pi for an equirect), maxLevel to ceil(log2(cube / tile)) + 1;
//     fallback faces OUT/fallback/<face>.<ext>; OUT/config.json as generate.py writes it.
//   marzipano: OUT/tiles/<z>/<face>/<row>/<col>.<ext>, z = 1 .. N over sizes tile * 2^k (its
//     viewer throws unless each size is a multiple of its tile size and of its parent's); z = 0 is
//     the preview level, OUT/tiles/preview.<ext>, six faces stacked in Marzipano's order bdflru.
//   Both: OUT/index.html opening the result with the viewer's script (script_url), and
//   OUT/panoproj-output.json, the marker of a folder panoproj made.
// Partial panoramas: tiles without any source pixel are not written (the viewer is limited to the
// source's yaw and pitch range), the others flattened over black at the field's (soft) edge.
//
// The output folder lands whole: everything is written into a temporary folder beside it, synced
// once and renamed into place (an existing one replaced only with overwrite, and only one
// panoproj made: its panoproj-output.json at the root; io/atomic_output.hpp).
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "panoproj/image.hpp"
#include "panoproj/io.hpp"
#include "panoproj/options.hpp"

namespace panoproj {

enum class Viewer { Pannellum, Marzipano };
Viewer parse_viewer(std::string_view name);  // throws panoproj::Error
const char* name_of(Viewer v);

struct TilesJob {
  std::string input;                 // the panorama (any readable form: --from, Photo Sphere, 2:1)
  std::string output;                // the folder to make
  std::optional<std::string> from;   // source spec; default as convert infers it
  Viewer viewer = Viewer::Pannellum;
  int tile = 512;                    // tile size in pixels
  int levels = 0;                    // levels kept from the top; 0: down to one tile a face
  int64_t cube_size = 0;             // the top level's face size; 0: from the source's resolution
  std::string format = "jpg";        // jpg | png
  int preview = 0;                   // fallback (pannellum, 1024) or preview (marzipano, <= 256) face size; 0: default
  std::string script_url;            // where index.html loads the viewer from; "": the package on jsDelivr
  ConvertOptions options;            // interp, antialias, rotation (which way is front), threads, memory
  WriteOptions write;                // quality, overwrite (the folder)
};

// One level of the pyramid.
struct TileLevel {
  int name = 0;       // Pannellum's level number or Marzipano's z
  int64_t size = 0;   // face size in pixels
  int64_t tiles = 0;  // tiles across a face: ceil(size / tile)
};

struct TilePyramid {
  Viewer viewer = Viewer::Pannellum;
  int64_t tile = 0;                // tile size (Pannellum: min(tile, cube size))
  std::vector<TileLevel> levels;   // coarsest first
  int64_t preview = 0;             // fallback / preview face size
  std::string extension;           // "jpg" | "png"
  int64_t tile_count() const;      // sum over levels of 6 * tiles^2
  // A tile's path within the output folder.
  std::string tile_path(size_t level, int face, int64_t row, int64_t col) const;
};

// The layout for this job and source (read from the input's header; checks the job's values).
TilePyramid tile_pyramid(const TilesJob& job);

// Rows of tiles of one face at one level: a unit of work.
struct TileBand {
  size_t level = 0;  // index into TilePyramid::levels
  int face = 0;      // 0..5: f r b l u d
  int64_t row0 = 0, row1 = 0;
};

struct TilesReport {
  TilePyramid pyramid;
  std::string from;              // the source spec used
  Size source_size;
  int64_t written = 0, empty = 0;  // tiles written; tiles without a source pixel (not written)
  double seconds = 0;
  std::vector<std::string> notes;  // e.g. the source range a partial panorama limits the view to
};

// Renders the whole pyramid locally (the source decoded once per scale its levels need).
TilesReport run_tiles(const TilesJob& job, const std::function<void(double)>& progress = {});

// The same in parts, for a scheduler (Python's client=): begin checks everything and creates the
// temporary folder; render_tiles writes the tiles of `rows` into it (reading only the source
// region and scale they need; any process, any order: each tile's bytes depend only on the job);
// finish writes the rest (config, index.html, preview) and lands the folder; abandon removes it.
struct TilesStaging {
  StagedFolder folder;  // the temporary folder
  std::vector<TileBand> work;  // every face's rows, in bands of at most band_pixels output pixels
};
TilesStaging begin_tiles(const TilesJob& job, int64_t band_pixels = int64_t{1} << 24);
// Returns {tiles written, empty tiles}.
std::array<int64_t, 2> render_tiles(const TilesJob& job, const StagedFolder& folder,
                                    const std::vector<TileBand>& rows);
TilesReport finish_tiles(const TilesJob& job, const StagedFolder& folder, std::array<int64_t, 2> counts);
void abandon_tiles(const StagedFolder& folder);

}  // namespace panoproj
