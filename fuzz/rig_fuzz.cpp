// Fuzzes the rig parser (views.hpp): cube, rings, sums and inline YAML, any text. Only
// panoproj::Error may leave it (a bad rig's one-line message); whatever it accepts must hold
// valid views.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "jobs/views/views.hpp"
#include "panoproj/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // "@path" reads a file (tested in views_test): not the parser's input, and a FIFO would block.
  if (const auto first = text.find_first_not_of(" \t"); first != std::string::npos && text[first] == '@') return 0;
  try {
    for (const panoproj::ViewSpec& v : panoproj::parse_rig(text))
      if (v.name.empty() || !(v.hfov > 0 && v.hfov <= 179) || !std::isfinite(v.yaw) || v.width < 0 || v.height < 0) std::abort();
  } catch (const panoproj::Error&) {
  }
  return 0;
}
