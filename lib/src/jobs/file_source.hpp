#pragma once
// A panorama file as the folder jobs (tiles, views) see it: its header, the source on its frame
// (rotation: the options' and a Photo Sphere's pose, levelled), the spec used, and whether it
// covers less than the whole sphere. Internal to the jobs.
#include <optional>
#include <string>

#include "panoproj/convert.hpp"
#include "panoproj/io.hpp"

namespace panoproj {

struct FileSource {
  ImageInfo info;
  ConversionGeometry base;  // target: a placeholder, replaced per part
  std::string from_text;    // the source spec used (with a Photo Sphere's pose named)
  bool partial = false;     // not the whole sphere: alpha (coverage), empty parts, masks
};

// Reads the header (and Photo Sphere XMP unless `from` is given); `what` names the job in a
// refusal (e.g. of a stereo source).
FileSource open_file_source(const std::string& input, const std::optional<std::string>& from, const ConvertOptions& options,
                            const char* what);

}  // namespace panoproj
