// Fuzzes the Photo Sphere XMP reader's field parser (and the GPano attributes read from a packet): the input is the XMP packet, wrapped in a
// JPEG's APP1 segment (so every input reaches the parser, not the segment walk), then read back
// and turned into a spec. Only panoproj::Error may leave it.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "panoproj/error.hpp"
#include "panoproj/photo_sphere.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 60000) return 0;  // one APP1 segment
  const std::string jpeg = std::string("\xFF\xD8\xFF\xD9", 4);
  std::string file;
  (void)panoproj::photo_sphere_attributes(std::string(reinterpret_cast<const char*>(data), size));
  try {
    file = panoproj::with_xmp(jpeg, std::string(reinterpret_cast<const char*>(data), size));
  } catch (const panoproj::Error&) {
    return 0;
  }
  const std::string path = "/tmp/panoproj_xmp_fuzz_" + std::to_string(::getpid()) + ".jpg";
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(file.data(), 1, file.size(), f);
    std::fclose(f);
  }
  try {
    if (const auto ps = panoproj::read_photo_sphere(path)) {
      (void)panoproj::photo_sphere_spec(*ps, {4096, 2048});
      (void)panoproj::photo_sphere_pose(*ps);
    }
  } catch (const panoproj::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}
