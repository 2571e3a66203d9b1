#pragma once
// A panorama file as the folder jobs (tiles, views) see it: its header, the source on its frame
// (rotation: the options' and a Photo Sphere's pose, levelled), the spec used, and whether it
// covers less than the whole sphere. Internal to the jobs.
#include <optional>
#include <string>

#include "panoproj/convert.hpp"
#include "panoproj/io.hpp"
#include "panoproj/photo_sphere.hpp"

namespace panoproj {

// The source spec of an image of this size: `from` if given; else an input path with
// {face}/{index}/{axis} is a cubemap in files, a Photo Sphere (photo_sphere: the input's packet,
// read_photo_sphere) its own, a 2:1 image a full equirect; anything else is an error asking for
// --from.
ProjectionSpec infer_source_spec(const std::optional<std::string>& from, const std::string& input,
                                 Size size, const std::optional<PhotoSphere>& photo_sphere);

// Whether a video input is read as a GoPro MAX's strips (VideoBackend::open_pair): --from
// gopro-max, or no --from and the extension .360.
bool gopro_max_video(const std::string& input, const std::optional<std::string>& from);

// A Photo Sphere taken tilted is levelled by its pose (none when --from overrides the metadata):
// geometry's rotation turned; returns from_text with the pose named.
std::string level_by_pose(ConversionGeometry& geometry, const std::optional<PhotoSphere>& ps,
                          std::string from_text);

struct FileSource {
  ImageInfo info;
  ConversionGeometry base;  // target: a placeholder, replaced per part
  std::string from_text;    // the source spec used (with a Photo Sphere's pose named)
  bool partial = false;     // not the whole sphere: alpha (coverage), empty parts, masks
};

// Reads the header (and Photo Sphere XMP unless `from` is given); `what` names the job in a
// refusal (e.g. of a stereo source).
FileSource open_file_source(const std::string& input, const std::optional<std::string>& from,
                            const ConvertOptions& options, const char* what);
// The same of a header already read (a video's frames: info from its stream, no Photo Sphere).
FileSource source_of(const ImageInfo& info, const std::string& input,
                     const std::optional<std::string>& from, const std::optional<PhotoSphere>& ps,
                     const ConvertOptions& options, const char* what);

}  // namespace panoproj
