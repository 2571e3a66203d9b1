#include "io/formats.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

#include <Imath/half.h>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {

PixelType ImageFormat::stored_type(PixelType wanted) const {
  if (deepest == PixelType::U8) return PixelType::U8;
  if (floats_only) return PixelType::F32;
  if (deepest == PixelType::U16 && (wanted == PixelType::F16 || wanted == PixelType::F32))
    return PixelType::U16;
  return wanted;
}

namespace {

// Float samples outside 0..1 or NaN: what an integer output clips (alpha included).
int64_t clipped_samples(const Image& image) {
  int64_t n = 0;
  const size_t row = static_cast<size_t>(image.width()) * static_cast<size_t>(image.channels());
  for (int64_t y = 0; y < image.height(); ++y) {
    const unsigned char* p = image.row(y);
    for (size_t i = 0; i < row; ++i) {
      float v;
      if (image.type() == PixelType::F32) {
        std::memcpy(&v, p + 4 * i, 4);
      } else {
        Imath::half h;
        std::memcpy(&h, p + 2 * i, 2);
        v = float(h);
      }
      n += !(v >= 0.0f && v <= 1.0f);
    }
  }
  return n;
}

}  // namespace

std::vector<std::string> write_warnings(const std::string& path, const Image& image,
                                        const WriteOptions& options, bool count_clipped) {
  const ImageFormat& format = format_of_path(path);
  std::vector<std::string> lost;
  const PixelType wanted = options.type.value_or(image.type());
  const PixelType stored = format.stored_type(wanted);
  if (image.alpha_channel() >= 0 && !format.holds_alpha)
    lost.push_back("alpha dropped: " + path + ": " + format.title +
                   " holds no alpha, so transparent pixels show their colour (write PNG, TIFF or "
                   "EXR to keep it)");
  if (options.type && stored != *options.type)
    lost.push_back("depth lowered: " + path + ": " + format.title + " holds " + name_of(stored) +
                   " samples, not " + name_of(*options.type) +
                   " (PNG holds uint16; TIFF and EXR hold half and float)");
  const bool to_integer = stored == PixelType::U8 || stored == PixelType::U16;
  if (count_clipped && to_integer &&
      (image.type() == PixelType::F16 || image.type() == PixelType::F32)) {
    if (const int64_t n = clipped_samples(image); n > 0) {
      const double all = static_cast<double>(image.width()) * static_cast<double>(image.height()) *
                         image.channels();
      char share[32];
      std::snprintf(share, sizeof share, "%.3g%%", 100.0 * static_cast<double>(n) / all);
      lost.push_back("samples clipped: " + path + ": " + std::to_string(n) + " samples (" + share +
                     ") outside 0..1 clipped to " + name_of(stored) +
                     " (write EXR, TIFF or HDR to keep them, or scale the image first)");
    }
  }
  if (!format.holds_metadata && (!options.metadata.empty() || !options.embedded.empty()))
    lost.push_back("metadata dropped: " + path + ": " + format.title +
                   " holds no metadata: the EXIF, ICC profile and XMP given are not written");
  return lost;
}

const std::vector<const ImageFormat*>& image_formats() {
#define PANOPROJ_FORMAT_ADDRESS_(Name) &k##Name##Format,
  static const std::vector<const ImageFormat*> formats{
      PANOPROJ_IMAGE_FORMATS(PANOPROJ_FORMAT_ADDRESS_)};
#undef PANOPROJ_FORMAT_ADDRESS_
  return formats;
}

const ImageFormat& format_named(std::string_view name) {
  for (const ImageFormat* f : image_formats())
    if (name == f->name) return *f;
  throw InternalError("no image format named " + std::string(name));
}

const ImageFormat* format_of_extension(std::string_view extension) {
  std::string ext(extension);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const ImageFormat* f : image_formats())
    if (std::find(f->extensions.begin(), f->extensions.end(), ext) != f->extensions.end()) return f;
  return nullptr;
}

const ImageFormat& format_of_path(const std::string& path) {
  const size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
  const bool has = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  if (const ImageFormat* f =
          has ? format_of_extension(std::string_view(path).substr(dot)) : nullptr)
    return *f;
  throw Error("cannot write " + path + ": no image format for its extension (use " +
                  format_extensions() + ")",
              ErrorKind::File);
}

const ImageFormat& scaled_format_for(PixelType type) {
  std::string which;
  for (const ImageFormat* f : image_formats()) {
    if (!f->decodes_scaled) continue;
    if (f->stored_type(type) == type) return *f;
    which +=
        (which.empty() ? "" : ", ") + std::string(f->title) + ": " + name_of(f->stored_type(type));
  }
  throw Error(std::string("no file format decodes ") + name_of(type) +
              " samples at 1/2 to 1/8 scale (" + which + ")");
}

const ImageFormat& web_format(const std::string& value, std::string_view option) {
  std::string names;
  for (const ImageFormat* f : image_formats()) {
    if (!f->web) continue;
    if (f->extensions[0].substr(1) == value) return *f;
    names += (names.empty() ? "" : " or ") + std::string(f->extensions[0].substr(1));
  }
  throw Error(option_text(option, value) + " is not a format web viewers show (use " + names + ")");
}

std::string format_titles() {
  std::string t;
  const auto& all = image_formats();
  for (size_t i = 0; i < all.size(); ++i)
    t += (i == 0 ? "" : i + 1 == all.size() ? " or " : ", ") + std::string(all[i]->title);
  return t;
}

std::string format_extensions() {
  std::string t;
  for (const ImageFormat* f : image_formats())
    for (std::string_view e : f->extensions) t += (t.empty() ? "" : " ") + std::string(e);
  return t;
}

InputFile probe_input(const std::string& path) {
  InputFile f;
  const int fd = open_regular(path, f.bytes);
  // The header segments of a JPEG (for its SOF marker): EXIF and ICC come first, 256 kB suffice.
  const std::string head = read_fd(fd, 256 * 1024);
  ::close(fd);
  if (head.empty())
    throw Error("cannot read " + path + ": the file is empty (expected an image file)",
                ErrorKind::File);
  for (const ImageFormat* format : image_formats())
    if (format->sniff(head, f)) {
      f.format = format->name;
      return f;
    }
  throw Error("cannot read " + path + ": not a " + format_titles() + " image (by its first bytes)",
              ErrorKind::File);
}

double most_stored_by_compression(const InputFile& file, Size, const std::string& compression) {
  double ratio = 10000;
  if (compression == "zip" || compression == "deflate" || compression == "zips" ||
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
  return static_cast<double>(file.bytes) * ratio + 65536;
}

void check_plausible(const std::string& path, const InputFile& f, Size size, int channels,
                     int sample_bits, const std::string& compression, Size window,
                     uint64_t decoded_bytes, int64_t memory_limit) {
  const int bits = f.bits_per_pixel > 0 ? f.bits_per_pixel : channels * sample_bits;
  const uint64_t stored = image_bytes(window, 1, static_cast<uint64_t>(bits)) / 8;
  if (static_cast<double>(stored) > format_named(f.format).most_stored(f, window, compression))
    throw Error("cannot read " + path + ": its header declares " + size_text(size) + " pixels of " +
                    std::to_string(channels) + " channels (" + bytes_text(stored) +
                    (window == size ? "" : " in the part needed") + ") but the file has " +
                    bytes_text(f.bytes) + ", too few to hold them (a damaged or forged header)",
                ErrorKind::File);
  require_memory("reading " + path + " (" + size_text(size) + ")", decoded_bytes, memory_limit);
}

}  // namespace panoproj
