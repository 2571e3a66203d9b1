#pragma once
// A layer as Hugin's nona writes them for enblend (-m TIFF_m): one TIFF of an image's part of the
// canvas, RGBA or gray + alpha with unassociated alpha (ExtraSamples 2), placed by XPOSITION /
// YPOSITION (inches at XRESOLUTION / YRESOLUTION 150 dpi; a quarter pixel past the pixel, so
// readers that truncate get it) on a canvas of PIXAR_IMAGEFULLWIDTH x PIXAR_IMAGEFULLLENGTH
// (tags 33300, 33301). Baseline TIFF 6.0, little-endian, in strips.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "panoproj/image.hpp"

namespace panoproj {

enum class TiffCompression { None, Deflate };

struct TiffPlacement {
  int64_t x = 0, y = 0;  // the layer's top-left pixel on the canvas
  Size canvas;
};

// Pixels per inch of the positions (nona's).
inline constexpr int kLayerDpi = 150;

// A layer's file as pieces to write one after the other (OutputSet::add): its header, its strips
// (compressed, or the layer's own pixels, which must outlive the pieces), its IFD and values.
struct TiffLayerFile {
  std::string head, tail;
  std::vector<std::string> strips;  // compressed strips; none: the pixels below
  std::string_view pixels;          // uncompressed: the layer's own bytes
  std::vector<std::string_view> pieces() const;
};

// `layer`'s file (2 or 4 channels, the last alpha; uint8, uint16 or float); throws Error where
// it would pass 4 GiB (classic TIFF's offsets).
TiffLayerFile encode_tiff_layer(const Image& layer, const TiffPlacement& place,
                                TiffCompression compression, int threads = 0);

}  // namespace panoproj
