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
// panoproj made: its panoproj-output.json at the root; io/atomic_output.hpp). Staged parts
// (jobs.hpp) are bands of tile rows of at most band_pixels output pixels each.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "panoproj/jobs.hpp"

namespace panoproj {

enum class Viewer { Pannellum, Marzipano };
Viewer parse_viewer(std::string_view name);  // throws panoproj::Error
const char* name_of(Viewer v);

// The pyramid's shape as the job's arguments ask for it (tile_layouts.cpp checks the values).
struct TileSettings {
  Viewer viewer = Viewer::Pannellum;
  int64_t tile = 0;       // tile size in pixels
  int64_t levels = 0;     // levels kept from the top; 0: down to one tile a face
  int64_t cube_size = 0;  // the top level's face size; 0: from the source's resolution
  std::string format;     // a web format's name (formats.hpp)
  int64_t preview =
      0;  // fallback (pannellum, 1024) or preview (marzipano, <= 256) face size; 0: default
  std::string script_url;  // where index.html loads the viewer from; "": the package on jsDelivr
};

// One level of the pyramid.
struct TileLevel {
  int name = 0;       // Pannellum's level number or Marzipano's z
  int64_t size = 0;   // face size in pixels
  int64_t tiles = 0;  // tiles across a face: ceil(size / tile)
};

struct TilePyramid {
  Viewer viewer = Viewer::Pannellum;
  int64_t tile = 0;               // tile size (Pannellum: min(tile, cube size))
  std::vector<TileLevel> levels;  // coarsest first
  int64_t preview = 0;            // fallback / preview face size
  std::string extension;          // the tiles' file extension
  int64_t tile_count() const;     // sum over levels of 6 * tiles^2
  // A tile's path within the output folder.
  std::string tile_path(size_t level, int face, int64_t row, int64_t col) const;
};

// The layout for the tiles job's arguments and source (read from the input's header).
TilePyramid tile_pyramid(const Arguments& args);

// Rows of tiles of one face at one level: a staged part.
struct TileBand {
  size_t level = 0;  // index into TilePyramid::levels
  int face = 0;      // 0..5: f r b l u d
  int64_t row0 = 0, row1 = 0;
};

}  // namespace panoproj
