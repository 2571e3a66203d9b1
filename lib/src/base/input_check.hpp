#pragma once
// The checks an input file passes before any reader sees it: a regular file (a FIFO would block, a
// device never end), read in full or in part. (Image files are then recognised by their first
// bytes and their headers checked against their size: io/formats.hpp.)
#include <cstdint>
#include <string>

namespace panoproj {

// An image file as its first bytes tell (io/formats.hpp: probe_input).
struct InputFile {
  std::string format;  // its format's name (ImageFormat::name, OpenImageIO's)
  uint64_t bytes = 0;  // the file's size
  bool arithmetic = false;  // a JPEG with arithmetic coding (SOF9 .. SOF15)
  int bits_per_pixel = 0;   // as stored, where the header says (PNG); 0: channels x sample bits
};

// Opens a regular file without blocking on a FIFO; returns the descriptor and sets its size.
// Throws Error naming the file as `what` ("input", "the spec file") that should be `expected`:
// missing (ErrorKind::Missing), unreadable or not a regular file.
int open_regular(const std::string& path, uint64_t& bytes, const char* what = "input",
                 const char* expected = "an image file");
// Up to `most` bytes from fd's position (fewer at its end).
std::string read_fd(int fd, size_t most);

// The first `most` bytes of a regular file (fewer if it is shorter); throws like open_regular,
// naming the file as `what` ("input", "the spec file") that should be `expected`.
std::string read_head(const std::string& path, size_t most, const char* what = "input",
                      const char* expected = "an image file");

}  // namespace panoproj
