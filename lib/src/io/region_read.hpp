#pragma once
// read_image_region in two steps, so that a conversion can start on the rows as they come: a
// file's region opened, checked against the file and the memory budget before any pixel is
// decoded, its buffer allocated; then decoded. Internal.
#include <cstdint>
#include <memory>
#include <string>

#include "io/codec.hpp"
#include "panoproj/image.hpp"

namespace panoproj {

class RegionRead {
 public:
  // The frame (at 1/scale) pixels [x0, x1) x [y0, y1) of path, clamped to the frame; other_bytes:
  // what the job holds besides, counted against memory_limit; spare: a buffer to reuse when it
  // fits (window_buffer, codec.hpp).
  RegionRead(const std::string& path, int64_t x0, int64_t y0, int64_t x1, int64_t y1, int64_t memory_limit,
             uint64_t other_bytes, int scale, Image spare = {});
  // The window's buffer, its frame set: its pixels once read() has returned.
  Image& image() { return image_; }
  // Decodes it (once); arrived: Decoder::read_into's.
  void read(const RowsArrived& arrived = {});

 private:
  std::string path_;
  std::unique_ptr<Decoder> decoder_;
  PixelRect window_;
  int scale_;
  Image image_;
};

}  // namespace panoproj
