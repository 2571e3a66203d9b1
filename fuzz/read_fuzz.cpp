// Fuzzes the image-reading path (OpenImageIO through panoproj's reader, and panoproj's own Photo
// Sphere XMP reader): any bytes as a file of each format panoproj reads, whole and as a region. Only panoproj::Error may leave it (and
// std::bad_alloc from inside OpenImageIO). Files whose header declares more than 64 MB of pixels
// are skipped: a plain allocation that big is no bug, but libFuzzer's malloc limit (set by
// scripts/fuzz.sh) would end the run on it. (read_image's own answer to a header declaring more
// than memory holds is tested in io_test.)
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <new>
#include <string>

#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/photo_sphere.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  // First byte: the extension, which selects the decoder.
  static const char* kExt[] = {".png", ".jpg", ".tif", ".exr", ".hdr"};
  const std::string path = "/tmp/panoproj_read_fuzz_" + std::to_string(::getpid()) + kExt[data[0] % 5];
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
  }
  if (const auto in = OIIO::ImageInput::open(path)) {
    if (in->spec().image_bytes() > (size_t{64} << 20)) {
      std::remove(path.c_str());
      return 0;
    }
  } else {
    (void)OIIO::geterror();  // leave no pending message for panoproj's own open
  }
  try {
    // The Photo Sphere XMP parser walks the JPEG's segments itself (photo_sphere.cpp).
    if (const auto ps = panoproj::read_photo_sphere(path)) (void)panoproj::photo_sphere_spec(*ps, {4096, 2048});
  } catch (const panoproj::Error&) {
  }
  try {
    const panoproj::Image im = panoproj::read_image(path);
    (void)panoproj::read_image_region(path, 1, 1, std::max<int64_t>(2, im.width() / 2), std::max<int64_t>(2, im.height() / 2));
  } catch (const panoproj::Error&) {
  } catch (const std::bad_alloc&) {  // a header declaring more pixels than the memory limit
  }
  std::remove(path.c_str());
  return 0;
}
