#pragma once
// EXIF blocks: carried from an input to its output, and read as attributes without OpenImageIO.
#include <string>
#include <string_view>

#include "panoproj/image.hpp"
#include "panoproj/io.hpp"

namespace panoproj {

// The EXIF block (a TIFF structure, as in a JPEG's APP1 after "Exif\0\0" or a PNG's eXIf chunk)
// describing an output of `size` converted from the stored pixels: Orientation 1 (the pixels as
// stored), PixelXDimension and PixelYDimension the new size, no thumbnail (IFD1 unlinked; its
// bytes stay, unreferenced). Every offset is checked against the block; a block that is not a
// TIFF structure, or whose entries point outside it, gives "" (dropped).
std::string exif_for_output(std::string_view exif, Size size);

// The common tags of an EXIF block by OpenImageIO's names and value types (python/README.md lists
// them): IFD0's (Make, Model, Orientation, DateTime ...), the Exif IFD's ("Exif:..."; ExposureTime
// and FNumber without prefix) and GPS position ("GPS:..."). Rationals are single floats, as
// OpenImageIO keeps them; GPS coordinates are (degrees, minutes, seconds). Entries that do not fit
// the block or have another type are left out.
Metadata exif_attributes(std::string_view exif);

}  // namespace panoproj
