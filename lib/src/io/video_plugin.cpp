#include "io/video_plugin.hpp"

#include "io/plugin_loader.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

Plugin<VideoBackend> g_plugin("libpanoproj_video.so", "PANOPROJ_VIDEO_PLUGIN", "panoproj_video_abi",
                              kVideoPluginAbi, "panoproj_video_backend");

}  // namespace

VideoBackend& video_backend(const std::string& why) {
  if (VideoBackend* b = g_plugin.get()) return *b;
  throw Error(why +
                  " needs FFmpeg's libraries (apt install libavformat59 libavcodec59 libswscale6): "
                  "plugin " +
                  g_plugin.file() + " " + g_plugin.error(),
              ErrorKind::File);
}

bool video_loaded() {
  return g_plugin.loaded();
}

}  // namespace panoproj
