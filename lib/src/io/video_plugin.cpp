#include "io/video_plugin.hpp"

#include <atomic>
#include <mutex>

#include "io/plugin_loader.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

constexpr const char* kPluginName = "libpanoproj_video.so";

struct Loaded {
  VideoBackend* backend = nullptr;
  std::string error;  // why it could not be loaded (kept: every later use says the same)
};

Loaded g_loaded;
std::once_flag g_once;
std::atomic<bool> g_ready{false};

}  // namespace

VideoBackend& video_backend(const std::string& why) {
  std::call_once(g_once, [] {
    if (void* make = load_plugin(kPluginName, "PANOPROJ_VIDEO_PLUGIN", "panoproj_video_abi",
                                 kVideoPluginAbi, "panoproj_video_backend", g_loaded.error))
      g_loaded.backend = reinterpret_cast<VideoBackend* (*)()>(make)();
    g_ready = g_loaded.backend != nullptr;
  });
  if (g_loaded.backend) return *g_loaded.backend;
  throw Error(why +
                  " needs FFmpeg's libraries (apt install libavformat59 libavcodec59 libswscale6): "
                  "plugin " +
                  kPluginName + " " + g_loaded.error,
              ErrorKind::File);
}

bool video_loaded() {
  return g_ready;
}

}  // namespace panoproj
