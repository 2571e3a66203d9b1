#pragma once
// The one exception type the library throws at its edges (spec parsing, factories, I/O).
// Messages are one line: "what: value (expected ...)". Kernels never throw.
#include <stdexcept>
#include <string>

namespace panoproj {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace panoproj
