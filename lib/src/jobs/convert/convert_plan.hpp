#pragma once
// The convert job's plan: everything checked and decided before the first pixel is read (the
// paths, every header, the geometry, the decode scale, the memory), which convert_job.cpp then
// runs. Rules:
//   - no --from: infer_source_spec (file_source.hpp).
//   - the output must not be an input (same file by path or inode), and an existing output is
//     replaced only with overwrite; nothing is written when anything fails.
//   - several inputs (a batch): all of one size, an output pattern with {stem} (the input's file
//     name without extension) and/or {n} (its position, from 0); every input header and output
//     path is checked before the first conversion; the map is built once.
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "panoproj/convert.hpp"
#include "panoproj/io.hpp"
#include "panoproj/projections/cubemap.hpp"

namespace panoproj {

struct ConvertRequest {
  std::vector<std::string> inputs;  // one image or face pattern, or several images (a batch)
  std::string output;               // a path, a face pattern, or a batch pattern
  std::optional<std::string> from;  // spec text
  std::string to;
  ConvertOptions options;
  WriteOptions write;
  // Each output carries its input's metadata (EXIF, ICC profile, XMP ... where OpenImageIO reads
  // and the output format holds them), less what describes the old pixels: their orientation,
  // dimensions and thumbnail.
  bool keep_metadata = true;
};

// The bytes the job holds, each named once.
struct ConvertMemory {
  uint64_t map = 0;        // the kept map (0: over kMapCacheBudget, made per use instead)
  uint64_t converted = 0;  // an output converted to the written sample type (0: written as made)
  uint64_t output = 0;     // one output as made
  uint64_t written = 0;    // one output as written (an encoded one counted at that size)
  uint64_t window = 0;     // the source's part one frame reads
  uint64_t corrected = 0;  // its photometric correction's copy (photometric keys), or 0
  // A frame at a time, besides its window: the map, the output, its converted copy and the
  // window's corrected copy.
  uint64_t job() const;
  // A pipelined batch: `readers` windows decoding, 2 outputs converting and 2 being written.
  uint64_t pipeline(int readers) const;
};

struct ConvertPlan {
  ConvertRequest request;
  ConvertOptions options;              // the request's, with a face set's size made the strip's
  std::vector<std::string> outputs;    // one per input (a strip pair's one)
  std::vector<std::string> files_out;  // every file written (face patterns expanded)
  bool batch = false, in_faces = false, out_faces = false;
  bool in_pair = false;  // a GoPro MAX's two strips (--from gopro-max and two inputs)
  bool held() const { return in_faces || in_pair; }  // pixels read with the headers (faces)
  FaceOrder in_order = kDefaultFaceOrder, out_order = kDefaultFaceOrder;
  std::vector<ImageInfo> infos;  // each input's header (none for a face set)
  std::optional<Image>
      faces;  // a face set's pixels (a strip pair's, stacked), read with its headers
  std::optional<ProjectionSpec> from;
  std::optional<ProjectionSpec> to;
  std::string from_text;  // the source spec used (a Photo Sphere's pose named)
  Size frame;             // the source's size as stored
  int channels = 0;
  PixelType type = PixelType::U8;
  std::optional<ConversionGeometry> geometry;  // on the decoded frame (at the decode scale)
  int scale = 1;                               // the decode scale
  std::optional<Converter> converter;          // keeping its maps while they fit the memory
  PixelRect need;                              // the source pixels a frame reads (at the scale)
  double map_seconds = 0;                      // building the converter and its footprint
  ConvertMemory memory;
};

// Throws Error naming the value at the first refusal; reads headers, no pixels (but a face set's).
ConvertPlan plan_convert(ConvertRequest request);

}  // namespace panoproj
