#pragma once
// The CLI's file jobs (and later Python's): convert (read, infer the source projection, plan,
// remap, write atomically) and maps (plan, build the source-coordinate map, write). Rules:
//   - no --from: an input path with {face}/{index}/{axis} is a cubemap in files; a 2:1 image is a
//     full equirect; anything else is an error asking for --from.
//   - the output must not be an input (same file by path or inode), and an existing output is
//     replaced only with overwrite; nothing is written when anything fails.
//   - several inputs (a batch, video frames): all of one size, an output pattern with {stem}
//     (the input's file name without extension) and/or {n} (its position, from 0); every input
//     header and output path is checked before the first conversion; the map is built once.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "panoproj/convert.hpp"
#include "panoproj/io.hpp"
#include "panoproj/maps.hpp"
#include "panoproj/photo_sphere.hpp"

namespace panoproj {

// Largest map the file jobs keep in memory (about 30 Mpx of output).
inline constexpr int64_t kMapCacheBudget = int64_t{512} << 20;

struct ConvertJob {
  std::vector<std::string> inputs;  // one image or face pattern, or several images (a batch)
  std::string output;               // a path, a face pattern, or a batch pattern
  std::optional<std::string> from;  // spec text; see the rules above when absent
  std::string to;
  ConvertOptions options;
  WriteOptions write;
  // Each output carries its input's metadata (EXIF, ICC profile, XMP ... where OpenImageIO reads
  // and the output format holds them), less what describes the old pixels: their orientation,
  // dimensions and thumbnail.
  bool keep_metadata = true;
};

struct ConvertReport {
  std::string input, output;
  std::string from, to;  // canonical specs used
  Size input_size, output_size;  // one face's size where input/output_faces
  bool input_faces = false, output_faces = false;
  double seconds = 0;    // map (first input of a batch) and remap, with the source's decoding and the
                         // JPEG blocks encoded as they are made (which they overlap); not the rest of the write,
                         // nor in a pipelined batch the decoding (done ahead, on other threads)
  double read_fraction = 1;  // share of the source's pixels read (only what the view needs)
  std::string source_format;  // jpeg, png, pnm, tiff, openexr, hdr ("" for face sets)
  int decode_scale = 1;       // the source decoded at 1/decode_scale (JPEG DCT scaling)
  std::string stereo;         // "" (mono), else how the eyes went, e.g. "stereo tb -> sbs, eyes 2048x1024 -> 1024x1024"
};

// Converts every input; on_frame (if given) is called after each one is written, progress with
// the overall fraction done (from the calling thread).
std::vector<ConvertReport> run_convert(const ConvertJob& job,
                                       const std::function<void(const ConvertReport&)>& on_frame = {},
                                       const std::function<void(double)>& progress = {});

struct MapsJob {
  std::string output;  // a float format: .exr or .tif
  std::string from, to;
  Size source_size;
  ConvertOptions options;  // size, rotation, threads (interp and engine do not apply)
  MapConvention convention = MapConvention::OpenCV;
  WriteOptions write;
};

// Writes the 2-channel float map (channels x, y; see maps.hpp); returns the output size.
Size run_maps(const MapsJob& job);

// The source spec to use for an image of this size (rules above); photo_sphere: the input's
// packet (read_photo_sphere), if any.
ProjectionSpec infer_source_spec(const std::optional<std::string>& from, const std::string& input, Size size,
                                 const std::optional<PhotoSphere>& photo_sphere);

// A Photo Sphere taken tilted is levelled by its pose (read_photo_sphere; none when --from
// overrides the metadata): geometry's rotation turned; returns from_text with the pose named.
std::string level_by_pose(ConversionGeometry& geometry, const std::optional<PhotoSphere>& ps, std::string from_text);

}  // namespace panoproj
