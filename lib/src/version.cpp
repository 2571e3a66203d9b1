#include "panoproj/version.hpp"

namespace panoproj {

const char* version() {
  return PANOPROJ_LIBRARY_VERSION;
}

}  // namespace panoproj
