#pragma once
// A rig of lenses for stitch (panoproj stitch rig.yaml pano.jpg): a YAML or JSON list of lenses
// (mapping_list.hpp), optionally under "lenses:", each a mapping of
//   spec     its projection: a panoproj spec or @calibration-file (relative to the rig's folder),
//            at its image's size (required)
//   input    its image file, relative to the rig's folder (required); lenses that share a frame
//            name the same file, each with its rect
//   rect     WxH+X+Y: the rectangle of the input that is this lens's image (default: the whole)
//   crop     WxH+X+Y: the part of its image it keeps (default: the whole image), or
//   circle   CX CY R: the circle of its image it keeps (centre and radius in pixels, the image's
//            top-left corner at 0 0)
//   yaw, pitch, roll   its pose in the rig, degrees (rotation.hpp's, as convert's --yaw: a lens at
//            yaw 180 looks back)
//   name     its name in messages (default: "lens N", from 1)
//   flat_field   a flat-field image of its image's size (relative to the rig's folder), divided
//            out in place of its spec's vignetting polynomial (photometric.hpp)
// A fisheye spec's own image circle (its fov) bounds it too. Errors name the file and line.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "panoproj/image.hpp"

namespace panoproj {

struct RigLens {
  int line = 0;
  std::string name;
  std::string spec;        // as written
  std::string input;       // as written
  std::string flat_field;  // as written, or empty
  std::optional<PixelRect> rect, crop;
  std::optional<std::array<double, 3>> circle;  // cx, cy, r
  double yaw = 0, pitch = 0, roll = 0;
};

struct LensRig {
  std::string path;
  std::vector<RigLens> lenses;
};

inline constexpr size_t kMaxRigLenses = 256;

// Whether a stitch input names a rig file (.yaml, .yml, .json) rather than a Hugin project.
bool is_rig_path(const std::string& path);
// Parses `text` (the file at `path`, named in errors); throws Error.
LensRig parse_lens_rig(const std::string& text, const std::string& path);
// Reads and parses the file (a regular file of at most 1 MiB).
LensRig read_lens_rig(const std::string& path);

}  // namespace panoproj
