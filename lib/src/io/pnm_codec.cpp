// Binary PGM (P5) and PPM (P6), 8 or 16 bits a sample (maxval up to 65535, big-endian; other
// maxvals are scaled to the full range). Uncompressed: a region reads only its rows, by offset;
// writing is one pass per row into the file's bytes.
#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>

#include "io/codec.hpp"
#include "io/formats.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {
namespace {

// The header's fields: magic, width, height, maxval, each after white space and comments; one
// white space character ends it.
struct PnmHeader {
  int channels = 0;
  int64_t width = 0, height = 0, maxval = 0;
  size_t data_offset = 0;
};

PnmHeader parse_header(const std::string& path, const std::string& b) {
  PnmHeader h;
  h.channels = b[1] == '5' ? 1 : 3;
  size_t at = 2;
  int64_t fields[3] = {};
  for (int64_t& v : fields) {
    for (;;) {
      while (at < b.size() && std::isspace(static_cast<unsigned char>(b[at]))) ++at;
      if (at < b.size() && b[at] == '#') {
        while (at < b.size() && b[at] != '\n' && b[at] != '\r') ++at;
        continue;
      }
      break;
    }
    if (at >= b.size() || !std::isdigit(static_cast<unsigned char>(b[at])))
      throw Error("cannot read " + path + ": a damaged PPM/PGM header (expected width, height and maxval)",
                  ErrorKind::File);
    for (; at < b.size() && std::isdigit(static_cast<unsigned char>(b[at])); ++at) {
      v = v * 10 + (b[at] - '0');
      if (v > (int64_t{1} << 31))
        throw Error("cannot read " + path + ": a PPM/PGM header value over 2^31 (a damaged header)", ErrorKind::File);
    }
  }
  if (at >= b.size() || !std::isspace(static_cast<unsigned char>(b[at])))
    throw Error("cannot read " + path + ": a damaged PPM/PGM header (no white space after maxval)", ErrorKind::File);
  h.width = fields[0], h.height = fields[1], h.maxval = fields[2];
  h.data_offset = at + 1;
  if (h.width < 1 || h.height < 1 || h.maxval < 1 || h.maxval > 65535)
    throw Error("cannot read " + path + ": " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                    " pixels, maxval " + std::to_string(h.maxval) + " (expected sizes >= 1, maxval 1 to 65535)",
                ErrorKind::File);
  return h;
}

class PnmDecoder final : public Decoder {
 public:
  PnmDecoder(const std::string& path, const InputFile& file) : path_(path), file_bytes_(file.bytes) {
    h_ = parse_header(path, read_head(path, 4096));
    header_.size = {h_.width, h_.height};
    header_.channels = h_.channels;
    header_.type = h_.maxval > 255 ? PixelType::U16 : PixelType::U8;
    header_.sample_bits = h_.maxval > 255 ? 16 : 8;
    header_.compression = "none";
  }

  PixelRect window(PixelRect need, int) const override { return need; }

  void read_into(PixelRect r, int, Image& img, const RowsArrived& arrived) override {
    const size_t sample = bytes_of(header_.type), px = sample * static_cast<size_t>(h_.channels);
    const uint64_t row_bytes = static_cast<uint64_t>(h_.width) * px;
    const uint64_t end = h_.data_offset + row_bytes * static_cast<uint64_t>(r.y1);
    if (end > file_bytes_)
      throw_damaged(path_, "the pixels end at byte " + std::to_string(file_bytes_) + ", rows up to " +
                               std::to_string(r.y1) + " need " + std::to_string(end));
    const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error("cannot read " + path_ + ": " + std::strerror(errno), ErrorKind::File);
    for (int64_t y = r.y0; y < r.y1; ++y) {
      unsigned char* dst = img.row(y - r.y0);
      size_t got = 0;
      const size_t want = img.row_bytes();
      const uint64_t offset = h_.data_offset + row_bytes * static_cast<uint64_t>(y) + static_cast<uint64_t>(r.x0) * px;
      while (got < want) {
        const ssize_t n = ::pread(fd, dst + got, want - got, static_cast<off_t>(offset + got));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
          ::close(fd);
          throw_damaged(path_, n < 0 ? std::strerror(errno) : "the file ended early");
        }
        got += static_cast<size_t>(n);
      }
      to_native(dst, static_cast<size_t>(r.x1 - r.x0) * static_cast<size_t>(h_.channels));
      rows_in(arrived, y + 1 - r.y0, r.y1 - r.y0);
    }
    ::close(fd);
  }

 private:
  // Big-endian 16-bit samples to the machine's order; maxvals other than 255 and 65535 scaled.
  void to_native(unsigned char* p, size_t n) const {
    if (header_.type == PixelType::U16) {
      auto* s = reinterpret_cast<uint16_t*>(p);
      for (size_t i = 0; i < n; ++i) s[i] = static_cast<uint16_t>((p[2 * i] << 8) | p[2 * i + 1]);
      if (h_.maxval != 65535)
        for (size_t i = 0; i < n; ++i) s[i] = static_cast<uint16_t>((s[i] * 65535u + h_.maxval / 2) / h_.maxval);
    } else if (h_.maxval != 255) {
      for (size_t i = 0; i < n; ++i) p[i] = static_cast<uint8_t>((std::min<int64_t>(p[i], h_.maxval) * 255 + h_.maxval / 2) / h_.maxval);
    }
  }

  std::string path_;
  uint64_t file_bytes_;
  PnmHeader h_;
};

}  // namespace

std::unique_ptr<Decoder> open_pnm(const std::string& path, const InputFile& file) {
  return std::make_unique<PnmDecoder>(path, file);
}

// Gray or RGB (an alpha channel, the last, left out); 8 or 16 bits (big-endian).
std::string pnm_header(const Image& image) {
  return std::string(image.channels() <= 2 ? "P5\n" : "P6\n") + std::to_string(image.width()) + " " +
         std::to_string(image.height()) + "\n" + (image.type() == PixelType::U16 ? "65535" : "255") + "\n";
}

bool pnm_as_stored(const Image& image) {
  return image.type() == PixelType::U8 && (image.channels() == 1 || image.channels() == 3);
}

FileBytes encode_pnm(const Image& image, const std::string& path) {
  const int in_channels = image.channels(), channels = in_channels <= 2 ? 1 : 3;
  const bool wide = image.type() == PixelType::U16;
  const std::string head = pnm_header(image);
  const size_t sample = wide ? 2 : 1, row = static_cast<size_t>(image.width()) * channels * sample;
  FileBytes bytes;
  try {
    bytes.resize(head.size() + row * static_cast<size_t>(image.height()));
  } catch (const std::bad_alloc&) {
    throw Error("cannot write " + path + ": " + bytes_text(head.size() + row * image.height()) +
                    " cannot be allocated",
                ErrorKind::Memory);
  }
  std::memcpy(bytes.data(), head.data(), head.size());
  for (int64_t y = 0; y < image.height(); ++y) {
    unsigned char* dst = bytes.data() + head.size() + row * static_cast<size_t>(y);
    const unsigned char* src = image.row(y);
    if (!wide && channels == in_channels) {
      std::memcpy(dst, src, row);
    } else if (!wide) {
      for (int64_t x = 0; x < image.width(); ++x)
        for (int k = 0; k < channels; ++k) dst[x * channels + k] = src[x * in_channels + k];
    } else {
      const auto* s = reinterpret_cast<const uint16_t*>(src);
      for (int64_t x = 0; x < image.width(); ++x)
        for (int k = 0; k < channels; ++k) {
          const uint16_t v = s[x * in_channels + k];
          dst[2 * (x * channels + k)] = static_cast<unsigned char>(v >> 8);
          dst[2 * (x * channels + k) + 1] = static_cast<unsigned char>(v & 0xFF);
        }
    }
  }
  return bytes;
}

// Binary PPM and PGM (P6, P5): samples stored as they are, no metadata.
const ImageFormat kPnmFormat{
    .name = "pnm",
    .title = "PPM/PGM",
    .extensions = {".ppm", ".pgm", ".pnm"},
    .sniff =
        [](const std::string& head, InputFile&) {
          return head.size() >= 3 && head[0] == 'P' && (head[1] == '5' || head[1] == '6') &&
                 std::isspace(static_cast<unsigned char>(head[2]));
        },
    .most_stored = most_stored_by_compression,
    .deepest = PixelType::U16,
    .holds_metadata = false,
    .holds_alpha = false,
    .open = open_pnm,
    .encode = [](const Image& image, const std::string& path, const WriteOptions&,
                 const EmbeddedMetadata&) { return encode_pnm(image, path); },
    .raw_header =
        [](const Image& image) {
          return pnm_as_stored(image) ? pnm_header(image) : std::string();
        }};

}  // namespace panoproj
