// The layer TIFF writer (tiff_layer.hpp). Tags per TIFF 6.0 (Adobe, 1992), ascending; Deflate is
// compression 8 (Adobe's zlib code, TIFF Technical Note 2); the Pixar tags as libtiff names them.
#include "io/tiff_layer.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <string_view>
#include <vector>

#include "base/parallel.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

enum : uint16_t { kShort = 3, kLong = 4, kRational = 5 };

struct Entry {
  uint16_t tag, type;
  uint32_t count;
  std::vector<uint32_t> values;  // shorts and longs; rationals as numerator, denominator pairs
};

void put16(std::string& s, uint16_t v) {
  s.append(reinterpret_cast<const char*>(&v), 2);
}
void put32(std::string& s, uint32_t v) {
  s.append(reinterpret_cast<const char*>(&v), 4);
}

// A position in inches as (4 p + 1) / (4 dpi): a quarter pixel past p, so that readers that
// take it as a float32 and truncate its product with the resolution (OpenImageIO, vigra) get p,
// as do those that round.
uint32_t position(int64_t p) {
  if (p < 0 || p >= (int64_t{1} << 30)) throw InternalError("a layer's position is in [0, 2^30)");
  return static_cast<uint32_t>(4 * p + 1);
}

// Rows per strip: about 256 kB of samples each.
int64_t strip_rows(const Image& im) {
  return std::max<int64_t>(1,
                           static_cast<int64_t>((256 << 10) / std::max<size_t>(im.row_bytes(), 1)));
}

}  // namespace

TiffLayerFile encode_tiff_layer(const Image& layer, const TiffPlacement& place,
                                TiffCompression compression, int threads) {
  static_assert(std::endian::native == std::endian::little,
                "the writer lays out little-endian words");
  const int ch = layer.channels();
  if (ch != 2 && ch != 4) throw InternalError("a layer has 2 or 4 channels");
  if (layer.type() == PixelType::F16)
    throw InternalError("a layer's samples are uint8, uint16 or float");
  const Size s = layer.size();
  const int64_t rows = strip_rows(layer), strips = (s.height + rows - 1) / rows;
  TiffLayerFile file;
  // Uncompressed strips are the image's rows as they are (one piece, not copied).
  std::vector<std::string_view> data(static_cast<size_t>(strips));
  if (compression == TiffCompression::Deflate) file.strips.resize(static_cast<size_t>(strips));
  parallel_tasks(strips, threads, [&](int64_t k, int) {
    const int64_t y0 = k * rows, y1 = std::min(s.height, y0 + rows);
    const auto* first = reinterpret_cast<const Bytef*>(layer.row(y0));
    const auto n = static_cast<uLong>(static_cast<size_t>(y1 - y0) * layer.row_bytes());
    if (compression == TiffCompression::None) {
      data[static_cast<size_t>(k)] = {reinterpret_cast<const char*>(first), n};
      return;
    }
    std::string& out = file.strips[static_cast<size_t>(k)];
    uLongf size = compressBound(n);
    out.resize(size);
    if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, first, n, 6) != Z_OK)
      throw Error("cannot compress a layer's strip (zlib)");
    out.resize(size);
    data[static_cast<size_t>(k)] = out;
  });
  uint64_t total = 8;
  for (const std::string_view d : data) total += d.size();
  if (total + 4096 + 8 * static_cast<uint64_t>(strips) > 0xFFFFFFFFull)
    throw Error("a layer of " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                " would pass the 4 GiB of a TIFF: give a smaller canvas or a crop");

  const uint32_t bits = static_cast<uint32_t>(bytes_of(layer.type()) * 8);
  const uint32_t format = layer.type() == PixelType::F32 ? 3 : 1;
  std::vector<uint32_t> offsets, counts;
  uint32_t at = 8;
  for (const std::string_view d : data) {
    offsets.push_back(at);
    counts.push_back(static_cast<uint32_t>(d.size()));
    at += static_cast<uint32_t>(d.size());
  }
  const auto u = [](int64_t v) { return static_cast<uint32_t>(v); };
  const std::vector<uint32_t> per_sample(static_cast<size_t>(ch), bits),
      formats(static_cast<size_t>(ch), format);
  std::vector<Entry> tags{
      {256, kLong, 1, {u(s.width)}},
      {257, kLong, 1, {u(s.height)}},
      {258, kShort, u(ch), per_sample},
      {259, kShort, 1, {compression == TiffCompression::None ? 1u : 8u}},
      {262, kShort, 1, {ch == 4 ? 2u : 1u}},  // RGB, or black is zero
      {273, kLong, u(strips), offsets},
      {277, kShort, 1, {u(ch)}},
      {278, kLong, 1, {u(rows)}},
      {279, kLong, u(strips), counts},
      {282, kRational, 1, {kLayerDpi, 1}},
      {283, kRational, 1, {kLayerDpi, 1}},
      {284, kShort, 1, {1}},  // chunky
      {286, kRational, 1, {position(place.x), 4 * kLayerDpi}},
      {287, kRational, 1, {position(place.y), 4 * kLayerDpi}},
      {296, kShort, 1, {2}},  // inches
      {338, kShort, 1, {2}},  // unassociated alpha
      {339, kShort, u(ch), formats},
      {33300, kLong, 1, {u(place.canvas.width)}},
      {33301, kLong, 1, {u(place.canvas.height)}},
  };
  // The IFD after the strips; values that do not fit its 4 bytes after it.
  const uint32_t ifd = at;
  const uint32_t extra = ifd + 2 + 12 * static_cast<uint32_t>(tags.size()) + 4;
  file.head.append("II", 2);
  put16(file.head, 42);
  put32(file.head, ifd);
  std::string& out = file.tail;
  std::string values;
  put16(out, static_cast<uint16_t>(tags.size()));
  for (const Entry& e : tags) {
    put16(out, e.tag);
    put16(out, e.type);
    put32(out, e.count);
    const uint32_t bytes = e.type == kRational ? 8 * e.count : (e.type == kShort ? 2 : 4) * e.count;
    std::string value;
    for (uint32_t v : e.values)
      e.type == kShort ? put16(value, static_cast<uint16_t>(v)) : put32(value, v);
    if (bytes <= 4) {
      value.resize(4, '\0');
      out += value;
    } else {
      put32(out, extra + static_cast<uint32_t>(values.size()));
      values += value;
      if (values.size() % 2) values += '\0';  // word boundaries
    }
  }
  put32(out, 0);  // no next IFD
  out += values;
  if (compression == TiffCompression::None)
    file.pixels = {reinterpret_cast<const char*>(layer.data()), layer.byte_size()};
  return file;
}

std::vector<std::string_view> TiffLayerFile::pieces() const {
  std::vector<std::string_view> out{head};
  if (strips.empty()) out.push_back(pixels);
  out.insert(out.end(), strips.begin(), strips.end());
  out.push_back(tail);
  return out;
}

}  // namespace panoproj
