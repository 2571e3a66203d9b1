// Fuzzes the image-reading path (OpenImageIO through panoproj's reader): any bytes as a file of
// each format panoproj reads, whole and as a region. Only panoproj::Error may leave it (and
// std::bad_alloc for a header declaring more pixels than scripts/fuzz.sh's memory limit).
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <new>
#include <string>

#include "panoproj/error.hpp"
#include "panoproj/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  // First byte: the extension, which selects the decoder.
  static const char* kExt[] = {".png", ".jpg", ".tif", ".exr", ".hdr"};
  const std::string path = "/tmp/panoproj_read_fuzz_" + std::to_string(::getpid()) + kExt[data[0] % 5];
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
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
