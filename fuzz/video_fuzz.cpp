// Fuzzes the video demuxing and decoding path: any bytes as a file, opened through the video
// plugin (libavformat's probing and demuxers, libavcodec's decoders, panoproj's planes), its
// first frames read, the copied streams' packets queued; the same bytes as a GoPro MAX .360 (its
// two strip streams, open_pair); its spherical metadata made a source spec
// (jobs/video_spherical.hpp); and panoproj's own reader of MP4's spherical boxes and Matroska's
// elements, and writer of the boxes (io/container_spherical.hpp): what it writes it reads back.
// Only panoproj::Error may leave it.
#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "io/container_spherical.hpp"
#include "io/video_plugin.hpp"
#include "jobs/video_spherical.hpp"
#include "panoproj/error.hpp"
#include "panoproj/spec.hpp"

// panoproj's box reader on the file, then its writer into it and the reader again.
void own_boxes(const std::string& path) {
  using panoproj::SphericalVideo;
  try {
    (void)panoproj::read_matroska_spherical(path, 0, path);
  } catch (const panoproj::Error&) {
  }
  try {
    const std::string moov = panoproj::read_moov(path);
    if (moov.empty()) return;
    (void)panoproj::spherical_of_moov(moov, 0, path);
    SphericalVideo v;
    v.kind = SphericalVideo::Kind::Equirect, v.top = 0.25, v.left = 0.125, v.yaw = -30;
    v.stereo = SphericalVideo::Stereo::LeftRight;
    const int fd = ::open(path.c_str(), O_WRONLY);
    if (fd < 0) return;
    try {
      panoproj::write_mp4_spherical(fd, path, v);
    } catch (const panoproj::Error&) {
      ::close(fd);
      return;
    }
    ::close(fd);
    const SphericalVideo back = panoproj::spherical_of_moov(panoproj::read_moov(path), 0, path);
    if (back.kind != v.kind || back.left != std::floor(v.left * 4294967295.0) / 4294967295.0 ||
        back.yaw != v.yaw || back.stereo != v.stereo)
      __builtin_trap();  // (what was written is not what is read)
  } catch (const panoproj::Error&) {
  }
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = "/tmp/panoproj_video_fuzz_" + std::to_string(::getpid()) + ".mp4";
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  for (const bool rgb : {false, true}) {
    try {
      auto reader = panoproj::video_backend("fuzzing").open(path, -1, !rgb, {}, rgb);
      const panoproj::VideoInfo& info = reader->info();
      if (!rgb && info.spherical.any())
        (void)panoproj::parse_spec(
            panoproj::spherical_source_spec(info.spherical, info.size, path));
      panoproj::VideoFrame frame;
      for (int n = 0; n < 8 && reader->read(frame); ++n) {
      }
    } catch (const panoproj::Error&) {
    }
  }
  // As a GoPro MAX .360: its two strip streams found by size, decoded in step.
  try {
    auto pair = panoproj::video_backend("fuzzing").open_pair(path, true);
    panoproj::VideoFrame frame;
    for (int n = 0; n < 8 && pair->read(frame); ++n) {
    }
  } catch (const panoproj::Error&) {
  }
  own_boxes(path);
  std::remove(path.c_str());
  return 0;
}
