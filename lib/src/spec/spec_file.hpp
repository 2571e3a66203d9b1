#pragma once
// The spec text of a spec file's contents (spec.hpp's spec_from_file reads the file, then this):
// JSON or YAML spec keys, OCamCalib's calib_results.txt, or the camera `camera` of Kalibr's
// camchain.yaml ("" when it holds one). `path` names the file in messages. Throws
// panoproj::Error.
#include <string>

#include "panoproj/spec.hpp"

namespace panoproj {

std::string spec_from_text(std::string text, const std::string& path, const std::string& camera);

}  // namespace panoproj
