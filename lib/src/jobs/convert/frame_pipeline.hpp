#pragma once
// A batch's (or a video's) frames through three stages at once, each stage taking the frames in
// order: read (decode) on threads of their own, convert on the calling thread, write (files synced
// and renamed) on a thread of its own. So one core decodes the next frame, or two decode the next
// two, while the frame before is converted and the one before that is written. Internal.
#include <cstddef>
#include <cstdint>
#include <functional>

namespace panoproj {

struct FrameStages {
  // Each runs once per frame i, in order within its stage. The caller keeps frame i's data:
  // read(i) may reuse what read(i - slots) filled, where slots = readers + 1 (convert(i - slots)
  // has returned); convert(i) may reuse what convert(i - 2) made (write(i - 2) has returned).
  // read(i) returns false where there is no frame i (a video's end: frames 0 .. i - 1 are all).
  std::function<bool(size_t)> read;
  std::function<void(size_t)> convert, write;
  // After write(i) returns, on the calling thread, in order (reports, progress).
  std::function<void(size_t)> written;
};

// Frames 0 .. n-1 (kUnknownFrames: until read says there are no more) through the stages, with
// `readers` frames decoding at once (each read(i) on reader i % readers). The first failure in any
// stage ends the batch as one frame after another would: the frames before it are written, none
// after it (the stages stop taking frames), and its exception is rethrown once every thread has
// stopped (of several, the earliest frame's).
inline constexpr size_t kUnknownFrames = SIZE_MAX;
void run_frame_pipeline(size_t n, int readers, const FrameStages& stages);

}  // namespace panoproj
