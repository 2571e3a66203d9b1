#include "base/input_check.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {
namespace {

const char* kind_of(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISCHR(m) || S_ISBLK(m)) return "a device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

// Opens a regular file without blocking on a FIFO; returns the descriptor and its size. `what`
// names the file in messages ("input", "the spec file"), `expected` what it should be.
int open_regular(const std::string& path, uint64_t& bytes, const char* what = "input",
                 const char* expected = "an image file") {
  const std::string name = std::string(what) + " " + path;
  const std::string shown = std::string(what) == "input" ? path : name;  // "cannot read a.jpg: ..."
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR)
      throw Error(name + " does not exist (check the path)", ErrorKind::Missing);
    throw Error("cannot read " + shown + ": " + std::strerror(err), ErrorKind::File);
  }
  if (!S_ISREG(st.st_mode))
    throw Error("cannot read " + shown + ": " + kind_of(st.st_mode) + " (expected " + expected + ")", ErrorKind::File);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw Error("cannot read " + shown + ": " + std::strerror(errno), ErrorKind::File);
  struct stat fst {};
  if (::fstat(fd, &fst) != 0 || !S_ISREG(fst.st_mode)) {  // swapped between the two looks
    ::close(fd);
    throw Error("cannot read " + shown + ": not a regular file (expected " + expected + ")", ErrorKind::File);
  }
  bytes = static_cast<uint64_t>(fst.st_size);
  return fd;
}

std::string read_fd(int fd, size_t most) {
  std::string b(most, '\0');
  size_t got = 0;
  while (got < most) {
    const ssize_t n = ::read(fd, b.data() + got, most - got);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<size_t>(n);
  }
  b.resize(got);
  return b;
}

bool starts(const std::string& b, const char* magic, size_t n) { return b.size() >= n && b.compare(0, n, magic, n) == 0; }

// Whether a JPEG's frame header (SOFn before the first scan) is arithmetic-coded: SOF9..11, 13..15.
bool arithmetic_jpeg(const std::string& b) {
  for (size_t i = 2; i + 4 <= b.size() && static_cast<unsigned char>(b[i]) == 0xFF;) {
    const auto m = static_cast<unsigned char>(b[i + 1]);
    if (m == 0xDA || m == 0xD9) break;
    if (m >= 0xC9 && m <= 0xCF && m != 0xCC) return true;
    const size_t len = (static_cast<unsigned char>(b[i + 2]) << 8) | static_cast<unsigned char>(b[i + 3]);
    if (len < 2) break;
    i += 2 + len;
  }
  return false;
}

}  // namespace

std::string read_head(const std::string& path, size_t most, const char* what, const char* expected) {
  uint64_t bytes = 0;
  const int fd = open_regular(path, bytes, what, expected);
  std::string b = read_fd(fd, most);
  ::close(fd);
  return b;
}

InputFile probe_input(const std::string& path) {
  InputFile f;
  const int fd = open_regular(path, f.bytes);
  // The header segments of a JPEG (for its SOF marker): EXIF and ICC come first, 256 kB suffice.
  const std::string b = read_fd(fd, 256 * 1024);
  ::close(fd);
  if (b.empty()) throw Error("cannot read " + path + ": the file is empty (expected an image file)", ErrorKind::File);
  if (starts(b, "\xFF\xD8\xFF", 3)) {
    f.format = "jpeg";
    f.arithmetic = arithmetic_jpeg(b);
  } else if (starts(b, "\x89PNG\r\n\x1a\n", 8)) {
    f.format = "png";
    // IHDR: bit depth and colour type (gray, -, RGB, palette, gray + alpha, -, RGBA) give the
    // bits per pixel that deflate compressed (a palette image decodes to 3 or 4 channels).
    if (b.size() >= 26) {
      static const int kSamples[7] = {1, 0, 3, 1, 2, 0, 4};
      const int depth = static_cast<unsigned char>(b[24]), type = static_cast<unsigned char>(b[25]);
      if (type < 7 && kSamples[type]) f.bits_per_pixel = depth * kSamples[type];
    }
  } else if (starts(b, "II*\0", 4) || starts(b, "MM\0*", 4) || starts(b, "II+\0", 4) || starts(b, "MM\0+", 4)) {
    f.format = "tiff";
  } else if (starts(b, "\x76\x2f\x31\x01", 4)) {
    f.format = "openexr";
  } else if (starts(b, "#?", 2)) {
    f.format = "hdr";
  } else if (b.size() >= 3 && b[0] == 'P' && (b[1] == '5' || b[1] == '6') && std::isspace(static_cast<unsigned char>(b[2]))) {
    f.format = "pnm";
  } else {
    throw Error("cannot read " + path + ": not a JPEG, PNG, PPM/PGM, TIFF, OpenEXR or Radiance HDR image (by its first bytes)",
                ErrorKind::File);
  }
  return f;
}

void check_plausible(const std::string& path, const InputFile& f, Size size, int channels, int sample_bits,
                     const std::string& compression, Size window, uint64_t decoded_bytes, int64_t memory_limit) {
  const int bits = f.bits_per_pixel > 0 ? f.bits_per_pixel : channels * sample_bits;
  const uint64_t stored = image_bytes(window, 1, static_cast<uint64_t>(bits)) / 8;
  // The most a file of f.bytes can hold, by its coding; unknown codings get 10000:1.
  double most = 0;
  if (f.format == "jpeg") {
    // A Huffman-coded JPEG spends at least one bit per 8x8 luma block (its DC code); arithmetic
    // coding can spend far less on flat areas (1/512 bit allowed).
    const double blocks = static_cast<double>((window.width + 7) / 8) * static_cast<double>((window.height + 7) / 8);
    const double bits = static_cast<double>(f.bytes) * 8.0 * (f.arithmetic ? 512.0 : 1.0);
    most = bits >= blocks ? static_cast<double>(stored) : 0;
  } else {
    double ratio = 10000;
    if (f.format == "hdr")
      ratio = 256;  // RLE: runs of 127 in 2 bytes per channel, against 12 bytes of float RGB
    else if (f.format == "png" || compression == "zip" || compression == "deflate" || compression == "zips" ||
             compression == "pxr24")
      ratio = 1040;
    else if (compression == "none" || compression.empty())
      ratio = 1.01;
    else if (compression == "packbits" || compression == "rle")
      ratio = 130;
    else if (compression == "lzw")
      ratio = 2000;
    else if (compression == "b44" || compression == "b44a")
      ratio = 16;
    most = static_cast<double>(f.bytes) * ratio + 65536;
  }
  if (static_cast<double>(stored) > most)
    throw Error("cannot read " + path + ": its header declares " + size_text(size) + " pixels of " +
                    std::to_string(channels) + " channels (" + bytes_text(stored) +
                    (window == size ? "" : " in the part needed") + ") but the file has " +
                    bytes_text(f.bytes) + ", too few to hold them (a damaged or forged header)",
                ErrorKind::File);
  require_memory("reading " + path + " (" + size_text(size) + ")", decoded_bytes, memory_limit);
}

}  // namespace panoproj
