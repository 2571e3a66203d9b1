#pragma once
// The CLI's file jobs (and later Python's): convert (read, infer the source projection, plan,
// remap, write atomically) and maps (plan, build the source-coordinate map, write). Rules:
//   - no --from: an input path with {face}/{index} is a cubemap in files; a 2:1 image is a
//     full equirect; anything else is an error asking for --from.
//   - the output must not be an input (same file by path or inode), and an existing output is
//     replaced only with overwrite; nothing is written when anything fails.
#include <optional>
#include <string>

#include "panoproj/convert.hpp"
#include "panoproj/io.hpp"
#include "panoproj/maps.hpp"

namespace panoproj {

struct ConvertJob {
  std::string input, output;
  std::optional<std::string> from;  // spec text; see convert_job.hpp rules when absent
  std::string to;
  ConvertOptions options;
  WriteOptions write;
};

struct ConvertReport {
  std::string from, to;  // canonical specs used
  Size input_size, output_size;  // one face's size where input/output_faces
  bool input_faces = false, output_faces = false;
  double seconds = 0;    // remap only
};

ConvertReport run_convert(const ConvertJob& job);

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

// The source spec to use for an image of this size (rules above).
ProjectionSpec infer_source_spec(const std::optional<std::string>& from, const std::string& input,
                                 Size size);

}  // namespace panoproj
