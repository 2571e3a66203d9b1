#pragma once
// Video through PyAV (`pip install av`): the module's backend for video where the plugin (the
// system's FFmpeg libraries) is missing; the decoding, muxing and encoding are panoproj/_pyav.py's.
#include <pybind11/pybind11.h>

#include "io/video_plugin.hpp"

namespace panoproj {

// Registers it (video_plugin.hpp set_video_fallback); PyAV is imported on first use.
void use_pyav_package();

// A frame's pixels as panoproj/_pyav.py describes them (pixels()): VideoPixels' fields by name.
VideoPixels video_pixels(const pybind11::dict& d);
pybind11::dict video_pixels_dict(const VideoPixels& v);

}  // namespace panoproj
