#pragma once
// Which of a video's frames a job takes (convert, views): the rows are declared here once.
// Rules: the frames of the chosen video stream whose time is in [start, start + duration), their
// times then counted from start; every n-th of them, or at most fps a second (the first taken,
// the next one due 1 / fps after it, so that a late frame does not crowd the next); frames are
// dropped, never repeated.
#include <cmath>
#include <cstdint>
#include <vector>

#include "io/video_plugin.hpp"
#include "panoproj/jobs.hpp"

namespace panoproj {

struct FrameSelection {
  int stream = -1;    // among the video streams; -1: the first
  VideoRange range;   // seconds
  double fps = 0;     // at most this many a second; 0: no limit (images to a video: their rate)
  int64_t every = 0;  // 0 or 1: every frame

  // Every frame of the stream.
  bool whole() const { return range.start == 0 && std::isinf(range.end) && fps == 0 && every <= 1; }
  // The spacing of the frames taken from a stream of `rate` frames a second (0: unknown).
  double step(double rate) const;
  // How many frames are taken of the stream (0: unknown), for progress.
  double expected(const VideoInfo& info) const;
};

// The rows: stream, start, duration, fps, every.
const std::vector<OptionDef>& frame_selection_rows();
// The rows' values; throws Error naming a value out of range.
FrameSelection frame_selection_of(const Arguments& a);
// Whether any of the rows was given other than its default (an image job refuses them).
bool frame_selection_given(const FrameSelection& s);

// Reads a stream's frames, in presentation order, passing over those not taken.
class FramePicker {
 public:
  FramePicker(const FrameSelection& selection, const VideoInfo& info)
      : s_(selection), tb_(static_cast<double>(info.time_base[0]) / info.time_base[1]) {}
  // The next frame taken of reader's into f; false at the end.
  bool next(VideoReader& reader, VideoFrame& f) {
    while (reader.read(f))
      if (take(f.pts)) return true;
    return false;
  }

 private:
  bool take(int64_t pts);
  FrameSelection s_;
  double tb_;
  int64_t read_ = 0;  // frames read (taken or not)
  double due_ = 0;    // the time the next frame is due (fps)
};

}  // namespace panoproj
