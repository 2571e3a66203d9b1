#include "io/oiio_plugin.hpp"

#include <atomic>
#include <mutex>

#include "io/formats.hpp"
#include "io/plugin_loader.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

constexpr const char* kPluginName = "libpanoproj_oiio.so";

struct Loaded {
  OiioBackend* backend = nullptr;
  std::string error;  // why it could not be loaded (kept: every later use says the same)
};

Loaded load() {
  Loaded l;
  if (void* make = load_plugin(kPluginName, "PANOPROJ_OIIO_PLUGIN", "panoproj_oiio_abi",
                               kOiioPluginAbi, "panoproj_oiio_backend", l.error))
    l.backend = reinterpret_cast<OiioBackend* (*)()>(make)();
  return l;
}

Loaded g_loaded;
std::once_flag g_once;
std::atomic<bool> g_ready{false};

OiioFallback g_fallback = nullptr;
const char* g_fallback_hint = "";

const Loaded& loaded() {
  std::call_once(g_once, [] { g_loaded = load(), g_ready = g_loaded.backend != nullptr; });
  return g_loaded;
}

}  // namespace

OiioBackend& oiio_backend(const std::string& why) {
  const Loaded& l = loaded();
  if (l.backend) return *l.backend;
  std::string why_not;
  if (g_fallback) {
    if (OiioBackend* b = g_fallback(why_not)) return *b;
    throw Error(why + " needs OpenImageIO (TIFF, EXR, HDR, metadata by name): " + g_fallback_hint +
                    ", or apt install libopenimageio2.4 (plugin " + kPluginName + " " + l.error + "; " + why_not + ")",
                ErrorKind::File);
  }
  throw Error(why + " needs OpenImageIO 2.4 (TIFF, EXR, HDR, metadata by name; apt install libopenimageio2.4): plugin " +
                  kPluginName + " " + l.error,
              ErrorKind::File);
}

void set_oiio_fallback(OiioFallback get, const char* hint) { g_fallback = get, g_fallback_hint = hint; }

bool oiio_loaded() { return g_ready; }

bool oiio_available() {
  std::string why_not;
  return loaded().backend != nullptr || (g_fallback && g_fallback(why_not) != nullptr);
}

// The formats read and written through OpenImageIO: floats in any channels for TIFF and OpenEXR,
// RGB for Radiance HDR (whose run-length coding expands at most 256:1: runs of 127 in 2 bytes a
// channel, against 12 bytes of float RGB; its reader decodes scaled by block means).
const ImageFormat kTiffFormat{
    .name = "tiff",
    .title = "TIFF",
    .extensions = {".tif", ".tiff"},
    .sniff =
        [](const std::string& head, InputFile&) {
          const std::string_view h(head.data(), std::min<size_t>(head.size(), 4));
          return h == std::string_view("II*\0", 4) || h == std::string_view("MM\0*", 4) ||
                 h == std::string_view("II+\0", 4) || h == std::string_view("MM\0+", 4);
        },
    .most_stored = most_stored_by_compression,
    .float_channels = true};

const ImageFormat kOpenExrFormat{
    .name = "openexr",
    .title = "OpenEXR",
    .extensions = {".exr"},
    .sniff = [](const std::string& head,
                InputFile&) { return head.compare(0, 4, "\x76\x2f\x31\x01") == 0; },
    .most_stored = most_stored_by_compression,
    .float_channels = true};

const ImageFormat kHdrFormat{
    .name = "hdr",
    .title = "Radiance HDR",
    .extensions = {".hdr"},
    .sniff = [](const std::string& head, InputFile&) { return head.compare(0, 2, "#?") == 0; },
    .most_stored = [](const InputFile& file, Size,
                      const std::string&) { return static_cast<double>(file.bytes) * 256 + 65536; },
    .floats_only = true,
    .decodes_scaled = true};

}  // namespace panoproj
