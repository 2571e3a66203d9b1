#pragma once
// The checks an input file passes before any image library sees it: a regular file (a FIFO would
// block, a device never end), one of the six formats by its magic bytes (no reader probes
// garbage), and, once its header is read, dimensions that the file's size can hold (a hostile
// header must not make a decoder allocate gigabytes before it finds the data missing).
#include <cstdint>
#include <string>

#include "panoproj/projections/frame.hpp"

namespace panoproj {

struct InputFile {
  std::string format;  // OpenImageIO's name: jpeg, png, pnm (binary PPM/PGM), tiff, openexr, hdr
  uint64_t bytes = 0;  // the file's size
  bool arithmetic = false;  // a JPEG with arithmetic coding (SOF9 .. SOF15)
  int bits_per_pixel = 0;   // as stored, where the header says (PNG); 0: channels x sample bits
};

// Throws Error naming the path: missing (ErrorKind::Missing), not a regular file, empty, or not
// a JPEG, PNG, PPM/PGM, TIFF, OpenEXR or Radiance HDR file.
InputFile probe_input(const std::string& path);

// The first `most` bytes of a regular file (fewer if it is shorter); throws like probe_input,
// naming the file as `what` ("input", "the spec file") that should be `expected`.
std::string read_head(const std::string& path, size_t most, const char* what = "input",
                      const char* expected = "an image file");

// Throws Error unless a file of f.bytes can hold the `window` (of an image of `size`) to be
// decoded, channels x sample_bits bits a pixel stored with `compression` (OpenImageIO's name): the
// most each coding expands (deflate 1032:1, LZW ~1500:1, PackBits 64:1, none 1:1, others 10000:1;
// a Huffman-coded JPEG spends at least one bit per 8x8 block), and unless the decoded samples
// (decoded_bytes) fit the memory budget.
void check_plausible(const std::string& path, const InputFile& f, Size size, int channels, int sample_bits,
                     const std::string& compression, Size window, uint64_t decoded_bytes, int64_t memory_limit);

}  // namespace panoproj
