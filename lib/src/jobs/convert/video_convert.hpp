#pragma once
// The convert job on a video: one plan for the whole clip, its frames decoded, converted plane by
// plane in their own format (video_planes.hpp) and encoded, on three threads at once with two
// frames in flight per stage (memory flat in the clip's length). Rules:
//   - the video stream's frames (those whose time is in [start, start + duration), the times then
//     counted from start; every n-th of them, or at most fps a second, the first taken), each
//     output frame's pts the input's (same time base);
//     its audio and subtitle streams copied packet for packet, GoPro's gpmd telemetry into MP4
//     and MOV, a start timecode made again; other streams dropped with a warning naming each.
//   - the output's size must hold whole chroma samples (refused otherwise, naming the nearest
//     sizes that do); the pixel format, range, matrix, primaries, transfer and chroma siting are
//     the input's (an encoder that lacks the format gets its nearest, with a warning).
//   - a GoPro MAX .360 (the extension, or --from gopro-max): its two strip streams, found by
//     their size, decoded in step and converted as one frame (gopro_max.hpp); the other streams
//     as above, the second strip neither copied nor named.
//   - written through a temporary, renamed at the end: a failure, Ctrl-C or SIGTERM leaves none.
//   - frames to images (an output pattern with {n}): decoded as RGB (the stream's matrix, range
//     and siting), converted and written one by one as a batch's images are; images to a video:
//     RGB made BT.709 limited-range 4:2:0 for the encoder, at --fps (default 25).
#include <optional>
#include <string>
#include <vector>

#include "jobs/convert/convert_plan.hpp"
#include "jobs/frame_selection.hpp"
#include "panoproj/jobs.hpp"

namespace panoproj {

struct VideoRequest {
  // The paths, specs and options as for images: inputs a video, or images (all of one size) to
  // make one; output a video, or a pattern with {n} for the frames as images; write: overwrite,
  // and for images their quality and depth.
  ConvertRequest files;
  FrameSelection frames;       // the stream and its frames taken (images to a video: fps
                               // their rate, default 25)
  std::string codec;           // "" : the container's default
  std::optional<int64_t> crf;  // the encoder's default if none
  std::string bitrate;         // "8M", "2500k", "" : by crf
  std::string preset;          // "" : the encoder's default
  int64_t gop = 0;             // 0: the encoder's default
};

// Whether a convert with these paths is a video's: the input's extension or first bytes are a
// video container's, or the output's extension is (images to a video).
bool is_video_job(const std::string& input, const std::string& output);

class VideoWriter;
// Throws Error naming the value at the first refusal; nothing is written then. sink: the
// converted frames go there instead of an encoder and the output (benchmarks: decode and convert
// alone; request.output names the container all the same).
Report convert_video(const VideoRequest& request, const JobEvents& events,
                     VideoWriter* sink = nullptr);

}  // namespace panoproj
