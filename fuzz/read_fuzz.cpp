// Fuzzes the image-reading path (panoproj's input checks, then its JPEG, PNG and PPM codecs or
// OpenImageIO through the plugin, and panoproj's own Photo Sphere XMP reader, EXIF editor and EXIF
// attribute reader):
// any bytes as a file, whole, as a region and at 1/8 scale.
// Only panoproj::Error may leave it. Reads run under a 64 MB memory limit, so a header declaring
// more is refused by panoproj's own budget (the path under test), never by libFuzzer's malloc
// limit.
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/photo_sphere.hpp"
#include "io/exif.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = "/tmp/panoproj_read_fuzz_" + std::to_string(::getpid());
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  constexpr int64_t kLimit = int64_t{64} << 20;
  try {
    // The Photo Sphere XMP parser walks the JPEG's segments itself (photo_sphere.cpp).
    if (const auto ps = panoproj::read_photo_sphere(path)) (void)panoproj::photo_sphere_spec(*ps, {4096, 2048});
  } catch (const panoproj::Error&) {
  }
  try {
    const panoproj::Image im = panoproj::read_image(path, kLimit);
    (void)panoproj::read_image_region(path, 1, 1, std::max<int64_t>(2, im.width() / 2),
                                      std::max<int64_t>(2, im.height() / 2), kLimit);
  } catch (const panoproj::Error&) {
  }
  try {
    (void)panoproj::read_image_region(path, 0, 1, 3, 5, kLimit, 0, 8);
  } catch (const panoproj::Error&) {
  }
  try {
    const panoproj::EmbeddedMetadata m = panoproj::read_embedded_metadata(path);
    (void)panoproj::exif_for_output(m.exif, {100, 50});
    (void)panoproj::exif_attributes(m.exif);
  } catch (const panoproj::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}
