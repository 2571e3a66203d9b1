#pragma once
// The video containers, one row each: how a file is recognised (its extension, or its first
// bytes), the codec an output gets by default, and the codecs a user names (--codec) with the
// encoders FFmpeg's libraries call them. Reading and writing are the video plugin's
// (video_plugin.hpp); libavformat decides what a container takes.
#include <string>
#include <string_view>
#include <vector>

namespace panoproj {

struct VideoContainer {
  const char* name;  // what reports say ("mp4")
  std::vector<std::string_view> extensions;
  const char* codec;  // the default --codec
};

const std::vector<VideoContainer>& video_containers();
// The container of a path's extension (any case); null if none.
const VideoContainer* video_container_of(const std::string& path);
// Whether a path names a video: its extension is a container's, or it is a regular file whose
// first bytes sniff as one.
bool is_video_file(const std::string& path);
// Whether a file's first bytes are a video container's (ISO BMFF with a video brand, Matroska,
// AVI, MPEG-TS).
bool sniffs_as_video(const std::string& head);

struct VideoCodec {
  const char* name;     // --codec's ("h264")
  const char* encoder;  // FFmpeg's encoder ("libx264")
};
const std::vector<VideoCodec>& video_codecs();
// The codec `name` names; throws Error listing them.
const VideoCodec& video_codec(const std::string& name);

}  // namespace panoproj
