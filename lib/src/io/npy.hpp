#pragma once
// NumPy's .npy format (format version 1.0: magic, header dict, then the C-order samples), for
// maps any NumPy reads with np.load and hands to cv2.remap as they are (CV_32FC2).
#include <string>

#include "panoproj/image.hpp"

namespace panoproj {

// A float32 image as a .npy file's bytes: shape (height, width, channels), little-endian.
std::string npy_bytes(const Image& image);

}  // namespace panoproj
