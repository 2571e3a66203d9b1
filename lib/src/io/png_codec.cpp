// PNG through libpng: rows are decoded in order and only up to the region's last (an interlaced
// PNG: all of it), each cut to the region's columns; an encoder into memory. libpng reports
// errors by longjmp to `guarded` (never exiting the process).
#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "io/codec.hpp"
#include "io/formats.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

struct PngFailure {
  std::string message;
};

void on_png_error(png_structp png, png_const_charp message) {
  static_cast<PngFailure*>(png_get_error_ptr(png))->message = message;
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

// Runs fn (libpng calls and trivial locals only: a longjmp skips its frames); false on an error.
template <class F>
bool guarded(png_structp png, F&& fn) {
  if (setjmp(png_jmpbuf(png))) return false;
  fn();
  return true;
}

constexpr char kXmpKeyword[] = "XML:com.adobe.xmp";

class PngDecoder final : public Decoder {
 public:
  explicit PngDecoder(const std::string& path) : path_(path) {
    try {
      open(path);
    } catch (...) {  // (a throwing constructor runs no destructor)
      release();
      throw;
    }
  }
  ~PngDecoder() override { release(); }
  PngDecoder(const PngDecoder&) = delete;
  PngDecoder& operator=(const PngDecoder&) = delete;

 private:
  void open(const std::string& path) {
    file_ = std::fopen(path.c_str(), "rbe");
    if (!file_) throw Error("cannot read " + path + ": " + std::strerror(errno), ErrorKind::File);
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &fail_, on_png_error, on_png_warning);
    if (png_) info_ = png_create_info_struct(png_);
    if (!png_ || !info_) throw Error("cannot read " + path + ": out of memory", ErrorKind::Memory);
    const bool ok = guarded(png_, [&] {
      png_init_io(png_, file_);
      png_read_info(png_, info_);
      // 8 or 16 bits a sample, gray or RGB, with alpha where the file has any (tRNS too).
      const int type = png_get_color_type(png_, info_), depth = png_get_bit_depth(png_, info_);
      if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png_);
      if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png_);
      if (png_get_valid(png_, info_, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png_);
      if (depth == 16) png_set_swap(png_);  // big-endian in the file
      passes_ = png_set_interlace_handling(png_);
      png_read_update_info(png_, info_);
    });
    if (!ok) throw_damaged(path, fail_.message);
    header_.size = {static_cast<int64_t>(png_get_image_width(png_, info_)),
                    static_cast<int64_t>(png_get_image_height(png_, info_))};
    header_.channels = png_get_channels(png_, info_);
    header_.sample_bits = png_get_bit_depth(png_, info_);
    header_.type = header_.sample_bits == 16 ? PixelType::U16 : PixelType::U8;
    header_.alpha_channel = header_.channels == 2 ? 1 : header_.channels == 4 ? 3 : -1;
    header_.compression = "zip";
    read_chunks();
  }
  void release() {
    if (png_) png_destroy_read_struct(&png_, info_ ? &info_ : nullptr, nullptr);
    png_ = nullptr, info_ = nullptr;
    if (file_) std::fclose(file_), file_ = nullptr;
  }

 public:
  // Rows 0 .. need.y1 - 1 are decoded (the others never); an interlaced PNG decodes whole.
  PixelRect window(PixelRect need, int) const override {
    return passes_ > 1 ? PixelRect{0, 0, header_.size.width, header_.size.height} : need;
  }

  void read_into(PixelRect r, int, Image& img, const RowsArrived& arrived) override {
    // Buffers made here: nothing is allocated under the longjmp.
    const bool direct = r.x0 == 0 && r.x1 == header_.size.width;
    std::vector<unsigned char> row(png_get_rowbytes(png_, info_));
    std::vector<png_bytep> rows(passes_ > 1 ? static_cast<size_t>(r.y1) : 0);
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = img.row(static_cast<int64_t>(y));  // r is the frame
    const bool ok = guarded(png_, [&] {
      if (passes_ > 1) return png_read_image(png_, rows.data());
      for (int64_t y = 0; y < r.y1; ++y) {
        const bool keep = y >= r.y0;
        png_read_row(png_, direct && keep ? img.row(y - r.y0) : row.data(), nullptr);
        if (!direct && keep) std::memcpy(img.row(y - r.y0), row.data() + r.x0 * img.pixel_bytes(), img.row_bytes());
        if (keep) rows_in(arrived, y + 1 - r.y0, r.y1 - r.y0);
      }
    });
    if (!ok) throw_damaged(path_, fail_.message);
    if (arrived && passes_ > 1) arrived(r.y1 - r.y0);
  }

  EmbeddedMetadata embedded() const override { return embedded_; }

 private:
  // The ICC profile, EXIF and XMP chunks before the pixels.
  void read_chunks() {
    png_charp name = nullptr;
    int compression = 0;
    png_bytep profile = nullptr;
    png_uint_32 length = 0;
    if (png_get_iCCP(png_, info_, &name, &compression, &profile, &length) && profile)
      embedded_.icc.assign(reinterpret_cast<const char*>(profile), length);
    png_bytep exif = nullptr;
    png_uint_32 exif_length = 0;
    if (png_get_eXIf_1(png_, info_, &exif_length, &exif) && exif)
      embedded_.exif.assign(reinterpret_cast<const char*>(exif), exif_length);
    png_textp text = nullptr;
    int n = 0;
    png_get_text(png_, info_, &text, &n);
    for (int i = 0; i < n; ++i)
      if (std::strcmp(text[i].key, kXmpKeyword) == 0 && text[i].text)
        embedded_.xmp.assign(text[i].text, text[i].compression >= PNG_ITXT_COMPRESSION_NONE ? text[i].itxt_length
                                                                                             : text[i].text_length);
  }

  std::string path_;
  FILE* file_ = nullptr;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  PngFailure fail_;
  int passes_ = 1;
  EmbeddedMetadata embedded_;
};

void append(png_structp png, png_bytep data, png_size_t n) {
  auto* out = static_cast<FileBytes*>(png_get_io_ptr(png));
  try {
    out->insert(out->end(), data, data + n);
  } catch (const std::bad_alloc&) {
    png_error(png, "out of memory");
  }
}

void flush(png_structp) {}

}  // namespace

std::unique_ptr<Decoder> open_png(const std::string& path, const InputFile&) { return std::make_unique<PngDecoder>(path); }

FileBytes encode_png(const Image& image, const std::string& path, const WriteOptions&,
                     const EmbeddedMetadata& meta) {
  FileBytes bytes;
  bytes.reserve(std::min<size_t>(image.byte_size() / 2, size_t{256} << 20) + 65536);
  PngFailure fail;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &fail, on_png_error, on_png_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, nullptr);
    throw Error("cannot write " + path + ": out of memory", ErrorKind::Memory);
  }
  png_text xmp{};
  std::string xmp_text = meta.xmp;
  const bool ok = guarded(png, [&] {
    png_set_write_fn(png, &bytes, append, flush);
    png_set_benign_errors(png, 1);  // a malformed ICC profile carried from an input is left out, not fatal
    png_set_user_limits(png, 0x7FFFFFFF, 0x7FFFFFFF);  // the format's sides, not libpng's default 10^6
    static const int kTypes[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                  PNG_COLOR_TYPE_RGB_ALPHA};
    const int depth = image.type() == PixelType::U16 ? 16 : 8;
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width()), static_cast<png_uint_32>(image.height()), depth,
                 kTypes[image.channels()], PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 6);  // zlib's default (as OpenImageIO wrote; level 1: 2.5x faster, 3% larger)
    if (!meta.icc.empty())
      png_set_iCCP(png, info, "ICC Profile", PNG_COMPRESSION_TYPE_BASE,
                   reinterpret_cast<png_const_bytep>(meta.icc.data()), static_cast<png_uint_32>(meta.icc.size()));
    if (!meta.exif.empty())
      png_set_eXIf_1(png, info, static_cast<png_uint_32>(meta.exif.size()),
                     reinterpret_cast<png_bytep>(const_cast<char*>(meta.exif.data())));
    if (!xmp_text.empty()) {
      xmp.compression = PNG_ITXT_COMPRESSION_NONE;
      xmp.key = const_cast<char*>(kXmpKeyword);
      xmp.text = xmp_text.data();
      xmp.itxt_length = xmp_text.size();
      png_set_text(png, info, &xmp, 1);
    }
    png_write_info(png, info);
    if (depth == 16) png_set_swap(png);
    for (int64_t y = 0; y < image.height(); ++y) png_write_row(png, image.row(y));
    png_write_end(png, info);
  });
  png_destroy_write_struct(&png, &info);
  if (!ok) throw Error("cannot write " + path + ": " + one_line(fail.message), ErrorKind::File);
  return bytes;
}

// Deflate expands at most about 1032:1. A palette image decodes to 3 or 4 channels, so the bits a
// pixel that deflate compressed come from IHDR (bit depth and colour type: gray, -, RGB, palette,
// gray + alpha, -, RGBA).
const ImageFormat kPngFormat{.name = "png",
                             .title = "PNG",
                             .extensions = {".png"},
                             .sniff =
                                 [](const std::string& head, InputFile& file) {
                                   if (head.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)) != 0)
                                     return false;
                                   if (head.size() >= 26) {
                                     static const int kSamples[7] = {1, 0, 3, 1, 2, 0, 4};
                                     const int depth = static_cast<unsigned char>(head[24]),
                                               type = static_cast<unsigned char>(head[25]);
                                     if (type < 7 && kSamples[type])
                                       file.bits_per_pixel = depth * kSamples[type];
                                   }
                                   return true;
                                 },
                             .most_stored =
                                 [](const InputFile& file, Size, const std::string&) {
                                   return static_cast<double>(file.bytes) * 1040 + 65536;
                                 },
                             .deepest = PixelType::U16,
                             .embedded_metadata = true,
                             .web = true,
                             .open = open_png,
                             .encode = encode_png};

}  // namespace panoproj
