#pragma once
// A layer as Hugin's nona writes them for enblend (-m TIFF_m): one TIFF of an image's part of the
// canvas, RGBA or gray + alpha with unassociated alpha (ExtraSamples 2), placed by XPOSITION /
// YPOSITION (inches at XRESOLUTION / YRESOLUTION 150 dpi; a quarter pixel past the pixel, so
// readers that truncate get it) on a canvas of PIXAR_IMAGEFULLWIDTH x
// PIXAR_IMAGEFULLLENGTH (tags 33300, 33301). Baseline TIFF 6.0, little-endian, in strips.
#include <cstdint>
#include <string>

#include "panoproj/image.hpp"

namespace panoproj {

enum class TiffCompression { None, Deflate };

struct TiffPlacement {
  int64_t x = 0, y = 0;  // the layer's top-left pixel on the canvas
  Size canvas;
};

// Pixels per inch of the positions (nona's).
inline constexpr int kLayerDpi = 150;

// The file's bytes for `layer` (2 or 4 channels, the last alpha; uint8, uint16 or float);
// throws Error where it would pass 4 GiB (classic TIFF's offsets).
std::string encode_tiff_layer(const Image& layer, const TiffPlacement& place,
                              TiffCompression compression, int threads = 0);

}  // namespace panoproj
