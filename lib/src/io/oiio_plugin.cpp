#include "io/oiio_plugin.hpp"

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "io/formats.hpp"
#include "panoproj/error.hpp"

#ifndef PANOPROJ_PLUGIN_DIRS
#define PANOPROJ_PLUGIN_DIRS ""
#endif

namespace panoproj {
namespace {

constexpr const char* kPluginName = "libpanoproj_oiio.so";

struct Loaded {
  OiioBackend* backend = nullptr;
  std::string error;  // why it could not be loaded (kept: every later use says the same)
};

// Where the code of this library sits: the executable, or the Python module.
std::filesystem::path own_folder() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&oiio_loaded), &info) == 0 || !info.dli_fname) return {};
  std::error_code ec;
  const auto p = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path() : p.parent_path();
}

std::vector<std::string> candidates() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("PANOPROJ_OIIO_PLUGIN"); env && *env) return {env};
  if (const auto own = own_folder(); !own.empty()) {
    out.push_back((own / kPluginName).string());
    out.push_back((own.parent_path() / "lib" / "panoproj" / kPluginName).string());  // bin/ -> lib/panoproj/
    out.push_back((own.parent_path() / "panoproj" / kPluginName).string());  // a repaired wheel's panoproj.scripts/
  }
  // The install's and the build tree's folders (':'-separated, set by CMake).
  const std::string dirs = PANOPROJ_PLUGIN_DIRS;
  for (size_t at = 0; at < dirs.size();) {
    const size_t end = std::min(dirs.find(':', at), dirs.size());
    if (end > at) out.push_back(dirs.substr(at, end - at) + "/" + kPluginName);
    at = end + 1;
  }
  return out;
}

Loaded load() {
  std::string tried;
  for (const std::string& path : candidates()) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried += (tried.empty() ? "" : ", ") + path;
      continue;
    }
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) return {nullptr, "not loadable: " + one_line(dlerror())};
    auto abi = reinterpret_cast<int (*)()>(dlsym(handle, "panoproj_oiio_abi"));
    auto make = reinterpret_cast<OiioBackend* (*)()>(dlsym(handle, "panoproj_oiio_backend"));
    if (!abi || !make || abi() != kOiioPluginAbi)
      return {nullptr, "not this panoproj's: " + path + " (rebuild or reinstall panoproj)"};
    return {make(), {}};  // never closed: OpenImageIO keeps threads and caches
  }
  return {nullptr, "not found (set PANOPROJ_OIIO_PLUGIN to its path; looked for " + tried + ")"};
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
