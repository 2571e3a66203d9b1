#pragma once
// The installed library's version, for a consumer to check at run time what it loaded (the
// package's panoprojConfigVersion.cmake checks it at build time).

namespace panoproj {

// CMake's project version of libpanoproj.so, e.g. "0.1.0".
const char* version();

}  // namespace panoproj
