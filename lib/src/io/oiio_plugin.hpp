#pragma once
// OpenImageIO behind a plugin: libpanoproj_oiio.so (oiio/backend.cpp) links it; the library does
// not. Debian's OpenImageIO pulls in about 260 shared libraries (0.2-0.4 s and ~130 MB at start),
// so it is opened on first use: TIFF, OpenEXR and Radiance HDR files, the metadata of any file by
// OpenImageIO's names, metadata carried between a built-in format and one of those, the labels of
// accuracy plots. Both sides are built together (kOiioPluginAbi guards against a stale plugin).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "panoproj/image.hpp"
#include "panoproj/io.hpp"
#include "base/input_check.hpp"
#include "io/codec.hpp"

namespace panoproj {

class OiioBackend {
 public:
  virtual ~OiioBackend() = default;
  virtual std::unique_ptr<Decoder> open(const std::string& path, const InputFile& file) = 0;
  // The file's attributes (OpenImageIO's "oiio:*" bookkeeping left out).
  virtual Metadata metadata(const std::string& path, const InputFile& file) = 0;
  // TIFF, OpenEXR, HDR by the path's extension; `extra` is added to options.metadata.
  virtual std::vector<unsigned char> encode(const Image& image, const std::string& path, const WriteOptions& options,
                                            const Metadata& extra) = 0;
  // A JPEG's or PNG's blocks as attributes (EXIF, XMP, ICCProfile); attributes as an EXIF block.
  virtual Metadata attributes_of(const EmbeddedMetadata& blocks) = 0;
  virtual std::string encode_exif(const Metadata& metadata) = 0;
  // Draws text into a 3-channel float image (no font found: nothing).
  virtual void draw_text(Image& rgb, int x, int y, const std::string& text, int size, const float colour[3]) = 0;
};

// The plugin, loaded on first use: $PANOPROJ_OIIO_PLUGIN, else beside the executable or Python
// module holding this code, or in ../lib/panoproj/ (a bin/ folder's: an install, pip's scripts)
// or ../panoproj/ (a repaired wheel's panoproj.scripts/) from there, else the install's and the
// build's library folders. Throws Error
// saying what is missing and which formats need it, naming `why` ("reading a.tif").
OiioBackend& oiio_backend(const std::string& why);
// Whether it has been loaded in this process (tests: the lean paths never load it).
bool oiio_loaded();
// Whether a backend can be had (the plugin loaded if it can be; no error when none).
bool oiio_available();

// A second backend for where the plugin is missing, tried after it: the Python module's, through
// the `openimageio` package (python/src/oiio_package.cpp). `get` gives it, or nullptr and why not;
// `hint` says how to install it.
using OiioFallback = OiioBackend* (*)(std::string& why_not);
void set_oiio_fallback(OiioFallback get, const char* hint);

constexpr int kOiioPluginAbi = 1;

}  // namespace panoproj

// The plugin's entry points.
extern "C" int panoproj_oiio_abi();
extern "C" panoproj::OiioBackend* panoproj_oiio_backend();
