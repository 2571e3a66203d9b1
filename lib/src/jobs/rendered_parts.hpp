#pragma once
// Rendered pieces of a folder job (tiles, views) made into files: a partial source's part
// flattened over black by its coverage (alpha), and the part encoded as the job's format.
#include <string>

#include "io/formats.hpp"
#include "panoproj/image.hpp"
#include "panoproj/io.hpp"

namespace panoproj {

// Pixels [x0, x0 + w) x [y0, y0 + h) of `part` without its alpha: colour x coverage (over black)
// when `partial`, else copied; empty: no pixel has any coverage (image left empty).
struct Flat {
  Image image;
  bool empty = false;
};
Flat flatten(const Image& part, int64_t x0, int64_t y0, int64_t w, int64_t h, bool partial);

// The file bytes of `image` in `format` (a built-in one), its samples converted to what it stores;
// `path` names the file in errors.
std::string encoded(const Image& image, const ImageFormat& format, const WriteOptions& write,
                    const std::string& path);

// A view's mask from its alpha: 255 where wholly covered, else 0 (COLMAP's and nerfstudio's
// masks: features and rays are taken where it is not 0).
Image mask_of(const Image& view);

}  // namespace panoproj
