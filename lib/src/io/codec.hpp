#pragma once
// One image file format's reader and writer, behind io.hpp. JPEG (libjpeg-turbo), PNG (libpng)
// and PPM/PGM are built in; TIFF, OpenEXR and Radiance HDR go through OpenImageIO, loaded as a
// plugin on first use (oiio_plugin.hpp), so that nothing else loads it.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "panoproj/image.hpp"
#include "panoproj/io.hpp"
#include "base/input_check.hpp"

namespace panoproj {

// What a file's header says.
struct ImageHeader {
  Size size;
  int channels = 0;
  PixelType type = PixelType::U8;
  int alpha_channel = -1;
  int sample_bits = 8;        // as stored
  std::string compression;    // OpenImageIO's name ("none", "zip", "jpeg" ...), for check_plausible
};

// An input file opened for reading: its header is read, no pixel yet. read() is called once.
class Decoder {
 public:
  virtual ~Decoder() = default;
  const ImageHeader& header() const { return header_; }
  // The frame's size when decoded at 1/scale (scale 1, 2, 4 or 8; scale_ok says which).
  virtual Size scaled_size(int scale) const { return scale == 1 ? header_.size : Size{}; }
  bool scale_ok(int scale) const { return scaled_size(scale).width > 0; }
  // The part of the (scaled) frame that read() decodes and keeps for `need`, which it covers:
  // whole tiles, whole rows, the frame.
  virtual PixelRect window(PixelRect need, int scale) const = 0;
  // Decodes window(need, scale) into img, the window's buffer (window_buffer). With arrived, rows are decoded from
  // the top and arrived(k) is called as rows [0, k) of the window come in (once, at the end, where
  // the format cannot tell sooner: interlaced PNG, OpenImageIO's); without, in any order (a large
  // baseline JPEG: two bands at once).
  virtual void read_into(PixelRect window, int scale, Image& img, const RowsArrived& arrived) = 0;
  // The metadata blocks as stored, where the format has them (JPEG, PNG); empty elsewhere.
  virtual EmbeddedMetadata embedded() const { return {}; }

 protected:
  ImageHeader header_;
};

std::unique_ptr<Decoder> open_jpeg(const std::string& path, const InputFile& file);
std::unique_ptr<Decoder> open_png(const std::string& path, const InputFile& file);
std::unique_ptr<Decoder> open_pnm(const std::string& path, const InputFile& file);

// An encoded file in memory: not zero-filled as it grows (encoders write every byte they keep),
// on huge pages when large (PixelAllocator, image.hpp).
using FileBytes = std::vector<unsigned char, PixelAllocator<unsigned char>>;

// A JPEG encoded in blocks, so that the parts of an image final early encode while the rest is
// still being made, and the others on several threads. Blocks are a grid of MCU-aligned parts
// (columns of at least 1024 px where they divide the MCU row, bands of 128 rows), each encoded
// alone as a JPEG whose scan restarts at each of its MCU rows; the scans are then interleaved into
// one (each MCU row takes the blocks across it in turn, restart markers numbered on). The file
// decodes to the pixels of a single encode: a restart resets only the DC predictions, and every
// block edge falls on an MCU boundary or the image's own (padded alike); chroma is downsampled
// within MCUs. Small images (under 2^20 pixels) and one thread: one block, no restart markers.
class JpegBlockEncoder {
 public:
  // image (given to done and finish) is size x channels, uint8.
  JpegBlockEncoder(Size size, int channels, std::string path, WriteOptions options, EmbeddedMetadata meta);
  ~JpegBlockEncoder();
  JpegBlockEncoder(const JpegBlockEncoder&) = delete;
  JpegBlockEncoder& operator=(const JpegBlockEncoder&) = delete;
  // Pixels r of image are final (each pixel reported once; from any thread): the blocks this
  // completes are encoded in the calling thread. Throws Error ("cannot write PATH: ...").
  void done(const Image& image, const PixelRect& r);
  // Encodes the blocks not yet encoded (on options.threads) and joins all into the file's bytes.
  FileBytes finish(const Image& image);

 private:
  struct Block;
  void encode(const Image& image, int64_t block);
  Size size_;
  std::string path_;
  WriteOptions options_;
  EmbeddedMetadata meta_;
  int64_t mcu_w_ = 8, mcu_h_ = 8, cols_ = 1, band_rows_ = 1, n_blocks_ = 1;
  unsigned interval_ = 0;  // MCUs per restart interval (0: none)
  std::unique_ptr<Block[]> blocks_;
  std::vector<unsigned char> header_;  // block 0's, up to its scan
  size_t sof_ = 0;                     // its SOF's height field
  FileBytes arena_;                    // the blocks' scans
  std::atomic<size_t> arena_used_{0};
  std::mutex mutex_;
  std::vector<FileBytes> spare_;  // encoding buffers not in use
};

// Encoded file bytes. `image` has the samples the format takes (see encode() in io.cpp).
FileBytes encode_jpeg(const Image& image, const std::string& path, const WriteOptions& options,
                      const EmbeddedMetadata& meta);
FileBytes encode_png(const Image& image, const std::string& path, const WriteOptions& options,
                     const EmbeddedMetadata& meta);
FileBytes encode_pnm(const Image& image, const std::string& path);
// A PPM/PGM file is pnm_header(image) and then, where pnm_as_stored(image) (8-bit gray or RGB),
// the image's samples as they are.
std::string pnm_header(const Image& image);
bool pnm_as_stored(const Image& image);

// Tells arrived (if any) that rows [0, k) of a window of `rows` are in, every 16 rows and at the
// last (a call takes a lock: not one per row).
inline void rows_in(const RowsArrived& arrived, int64_t k, int64_t rows) {
  if (arrived && (k % 16 == 0 || k == rows)) arrived(k);
}

// The buffer for window of the frame decoded at 1/scale, unfilled (read_into writes every pixel),
// its frame set (a one-line Error when it cannot be allocated); spare's when it has the window's
// size and layout (a batch's frames: no new memory, which the system would zero, per frame).
Image window_buffer(const std::string& path, const Decoder& d, PixelRect window, int scale, Image spare = {});
// "cannot read PATH: WHY (the file is damaged or truncated)"
[[noreturn]] void throw_damaged(const std::string& path, const std::string& why);

}  // namespace panoproj
