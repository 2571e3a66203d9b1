// Fuzzes the video demuxing and decoding path: any bytes as a file, opened through the video
// plugin (libavformat's probing and demuxers, libavcodec's decoders, panoproj's planes), its
// first frames read, the copied streams' packets queued; its spherical metadata made a source
// spec (jobs/video_spherical.hpp). Only panoproj::Error may leave it.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "io/video_plugin.hpp"
#include "jobs/video_spherical.hpp"
#include "panoproj/error.hpp"
#include "panoproj/spec.hpp"

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
  std::remove(path.c_str());
  return 0;
}
