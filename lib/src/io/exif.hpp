#pragma once
// EXIF blocks carried from an input to its output.
#include <string>
#include <string_view>

#include "panoproj/image.hpp"

namespace panoproj {

// The EXIF block (a TIFF structure, as in a JPEG's APP1 after "Exif\0\0" or a PNG's eXIf chunk)
// describing an output of `size` converted from the stored pixels: Orientation 1 (the pixels as
// stored), PixelXDimension and PixelYDimension the new size, no thumbnail (IFD1 unlinked; its
// bytes stay, unreferenced). Every offset is checked against the block; a block that is not a
// TIFF structure, or whose entries point outside it, gives "" (dropped).
std::string exif_for_output(std::string_view exif, Size size);

}  // namespace panoproj
