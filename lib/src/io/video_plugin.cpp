#include "io/video_plugin.hpp"

#include "io/plugin_loader.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

Plugin<VideoBackend> g_plugin("libpanoproj_video.so", "PANOPROJ_VIDEO_PLUGIN", "panoproj_video_abi",
                              kVideoPluginAbi, "panoproj_video_backend");

VideoFallback g_fallback = nullptr;
const char* g_fallback_hint = "";

}  // namespace

VideoBackend& video_backend(const std::string& why) {
  if (VideoBackend* b = g_plugin.get()) return *b;
  if (g_fallback) {
    std::string why_not;
    if (VideoBackend* b = g_fallback(why_not)) return *b;
    throw Error(
        why + " needs FFmpeg's libraries (apt install libavformat59 libavcodec59 libswscale6) or " +
            g_fallback_hint + " (plugin " + g_plugin.file() + " " + g_plugin.error() + "; " +
            why_not + ")",
        ErrorKind::File);
  }
  throw Error(why +
                  " needs FFmpeg's libraries (apt install libavformat59 libavcodec59 libswscale6): "
                  "plugin " +
                  g_plugin.file() + " " + g_plugin.error(),
              ErrorKind::File);
}

void set_video_fallback(VideoFallback get, const char* hint) {
  g_fallback = get, g_fallback_hint = hint;
}

bool video_loaded() {
  return g_plugin.loaded();
}

}  // namespace panoproj
