// Fuzzes the rig parsers: views' (views.hpp: cube, rings, sums and inline YAML) and stitch's rigs
// of lenses (lens_rig.hpp: YAML or JSON), any text. Only panoproj::Error may leave them (a bad
// rig's one-line message); whatever they accept must hold valid views and lenses.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "jobs/stitch/lens_rig.hpp"
#include "jobs/views/views.hpp"
#include "panoproj/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // "@path" reads a file (tested in views_test): not the parser's input, and a FIFO would block.
  if (const auto first = text.find_first_not_of(" \t");
      first != std::string::npos && text[first] == '@')
    return 0;
  try {
    for (const panoproj::RigLens& l : panoproj::parse_lens_rig(text, "fuzz.yaml").lenses)
      if (l.spec.empty() || l.input.empty() || !(std::abs(l.yaw) <= 360) ||
          (l.rect && l.rect->x1 <= l.rect->x0))
        std::abort();
  } catch (const panoproj::Error&) {
  }
  try {
    for (const panoproj::ViewSpec& v : panoproj::parse_rig(text))
      if (v.name.empty() || !(v.hfov > 0 && v.hfov <= 179) || !std::isfinite(v.yaw) ||
          v.width < 0 || v.height < 0)
        std::abort();
  } catch (const panoproj::Error&) {
  }
  return 0;
}
