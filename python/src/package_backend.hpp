#pragma once
// A backend served by a Python package where a plugin cannot load (oiio_package.cpp: the
// openimageio package; pyav_package.cpp: PyAV): the package imported once, on first use.
#include <pybind11/pybind11.h>

#include <mutex>
#include <string>

#include "panoproj/error.hpp"

namespace panoproj {

// The one `Backend` where `import` (run once, holding the GIL) succeeds; else nullptr, and
// `why_not` says `what` and the import's error in one line (every later call the same).
template <class Backend>
Backend* package_backend(const char* what, void (*import)(), std::string& why_not) {
  static std::once_flag once;
  static std::string missing;  // ("": imported)
  std::call_once(once, [&] {
    pybind11::gil_scoped_acquire gil;
    try {
      import();
    } catch (const pybind11::error_already_set& e) {
      missing = std::string(what) + ": " + one_line(e.what());
    }
  });
  if (!missing.empty()) {
    why_not = missing;
    return nullptr;
  }
  static Backend backend;
  return &backend;
}

}  // namespace panoproj
