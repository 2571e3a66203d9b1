// Fuzzes the projection spec parser and the factory: any text, any size; and, for text after "@@",
// the spec files' readers (JSON/YAML keys, OCamCalib's calib_results.txt, Kalibr's
// camchain.yaml) on that text as a file's contents. Only panoproj::Error may leave them (a bad
// spec's one-line message); a crash, a sanitizer report or another exception is a bug.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "panoproj/error.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"
#include "spec/photometric_keys.hpp"
#include "spec/spec_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // First 4 bytes: the size (two 16-bit numbers, 0 included); the rest: the spec text.
  if (size < 4) return 0;
  uint16_t w, h;
  std::memcpy(&w, data, 2);
  std::memcpy(&h, data + 2, 2);
  std::string text(reinterpret_cast<const char*>(data + 4), size - 4);
  try {
    // "@@contents": the spec files' readers on the contents (a Kalibr camera named by the size's
    // low bit). Any other "@path" reads a file (spec_file.cpp, tested in spec_test): not the
    // parser's input, and a path like /dev/stdin would block the run.
    if (text.compare(0, 2, "@@") == 0)
      text = panoproj::spec_from_text(text.substr(2), "fuzz", w & 1 ? "cam1" : "");
    if (const auto first = text.find_first_not_of(" \t");
        first != std::string::npos && text[first] == '@')
      return 0;
    const panoproj::ProjectionSpec spec = panoproj::parse_spec(text);
    (void)spec.str();
    for (int lens : {0, 1}) (void)panoproj::photometric_keys(spec, lens);
    const panoproj::Projection p = panoproj::make_projection(spec, {w, h});
    // A few rays through the frame and back: must not crash on whatever was accepted.
    for (double y : {0.0, 0.5 * h, static_cast<double>(h)})
      for (double x : {0.0, 0.5 * w, static_cast<double>(w)}) {
        panoproj::Ray d;
        double px, py;
        if (panoproj::to_ray(p, x, y, d)) (void)panoproj::to_pixel(p, d.normalized(), px, py);
      }
  } catch (const panoproj::Error&) {
  }
  return 0;
}
