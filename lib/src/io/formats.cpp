#include "io/formats.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>

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
