#include "io/oiio_plugin.hpp"

#include "io/formats.hpp"
#include "io/plugin_loader.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

Plugin<OiioBackend> g_plugin("libpanoproj_oiio.so", "PANOPROJ_OIIO_PLUGIN", "panoproj_oiio_abi",
                             kOiioPluginAbi, "panoproj_oiio_backend");

OiioFallback g_fallback = nullptr;
const char* g_fallback_hint = "";

}  // namespace

OiioBackend& oiio_backend(const std::string& why) {
  if (OiioBackend* b = g_plugin.get()) return *b;
  std::string why_not;
  if (g_fallback) {
    if (OiioBackend* b = g_fallback(why_not)) return *b;
    throw Error(why + " needs OpenImageIO (TIFF, EXR, HDR, metadata by name): " + g_fallback_hint +
                    ", or apt install libopenimageio2.4 (plugin " + g_plugin.file() + " " +
                    g_plugin.error() + "; " + why_not + ")",
                ErrorKind::File);
  }
  throw Error(why +
                  " needs OpenImageIO 2.4 (TIFF, EXR, HDR, metadata by name; apt install "
                  "libopenimageio2.4): plugin " +
                  g_plugin.file() + " " + g_plugin.error(),
              ErrorKind::File);
}

void set_oiio_fallback(OiioFallback get, const char* hint) { g_fallback = get, g_fallback_hint = hint; }

bool oiio_loaded() {
  return g_plugin.loaded();
}

bool oiio_available() {
  std::string why_not;
  return g_plugin.get() != nullptr || (g_fallback && g_fallback(why_not) != nullptr);
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
    .holds_alpha = false,
    .decodes_scaled = true};

}  // namespace panoproj
