// JPEG through libjpeg-turbo: region decodes (jpeg_crop_scanline, jpeg_skip_scanlines), DCT-scaled
// decodes (1/2, 1/4, 1/8), and an encoder into memory. libjpeg reports errors through an error
// manager that longjmps back to `guarded` (it must never exit the process); corrupt data it would
// paper over with grey (a warning) is an error too.
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
// clang-format off
#include <jpeglib.h>
#include <jerror.h>
// clang-format on

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <new>
#include <thread>

#include "base/parallel.hpp"
#include "io/codec.hpp"
#include "io/formats.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

struct JpegFailure {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
};

[[noreturn]] void on_error(j_common_ptr c) {
  auto* f = reinterpret_cast<JpegFailure*>(c->err);
  c->err->format_message(c, f->message);
  std::longjmp(f->jump, 1);
}

// Warnings that mean the data is corrupt or missing end the decode (libjpeg would fill in grey and
// go on); others (extraneous bytes before a marker, an odd progression) leave the image intact.
void on_decode_message(j_common_ptr c, int level) {
  if (level >= 0) return;  // traces
  switch (c->err->msg_code) {
    case JWRN_JPEG_EOF: case JWRN_HIT_MARKER: case JWRN_HUFF_BAD_CODE: case JWRN_MUST_RESYNC:
    case JWRN_NOT_SEQUENTIAL: case JWRN_ARITH_BAD_CODE:
      on_error(c);
    default: break;
  }
}

void on_encode_message(j_common_ptr, int) {}

// Runs fn (libjpeg calls and trivial locals only: a longjmp skips its frames); false on an error.
template <class F>
bool guarded(JpegFailure& f, F&& fn) {
  if (setjmp(f.jump)) return false;
  fn();
  return true;
}

constexpr char kExifHeader[] = "Exif\0";  // + the terminating NUL: 6 bytes
constexpr char kXmpHeader[] = "http://ns.adobe.com/xap/1.0/";  // + NUL: 29 bytes

bool starts_with(const jpeg_marker_struct* m, const char* header, size_t n) {
  return m->data_length >= n && std::memcmp(m->data, header, n) == 0;
}

class JpegDecoder final : public Decoder {
 public:
  explicit JpegDecoder(const std::string& path) : path_(path) {
    try {
      open(path);
    } catch (...) {  // (a throwing constructor runs no destructor)
      release();
      throw;
    }
  }
  ~JpegDecoder() override { release(); }
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;

  // CMYK and YCCK (Adobe) JPEGs go to OpenImageIO, which converts them to RGB.
  bool supported() const { return c_.num_components == 1 || c_.num_components == 3; }

 private:
  void open(const std::string& path) {
    file_ = std::fopen(path.c_str(), "rbe");
    if (!file_) throw Error("cannot read " + path + ": " + std::strerror(errno), ErrorKind::File);
    // libjpeg reads 4 kB at a time: one system call per 256 kB (glibc ignores the size given
    // without a buffer).
    buffer_ = std::make_unique<char[]>(kReadBuffer);
    std::setvbuf(file_, buffer_.get(), _IOFBF, kReadBuffer);
    c_.err = jpeg_std_error(&fail_.mgr);
    fail_.mgr.error_exit = on_error;
    fail_.mgr.emit_message = on_decode_message;
    if (!guarded(fail_, [&] { jpeg_create_decompress(&c_); })) throw_damaged(path, fail_.message);
    created_ = true;
    const bool ok = guarded(fail_, [&] {
      jpeg_stdio_src(&c_, file_);
      jpeg_save_markers(&c_, JPEG_APP0 + 1, 0xFFFF);
      jpeg_save_markers(&c_, JPEG_APP0 + 2, 0xFFFF);
      jpeg_read_header(&c_, TRUE);
    });
    if (!ok) throw_damaged(path, fail_.message);
    header_.size = {static_cast<int64_t>(c_.image_width), static_cast<int64_t>(c_.image_height)};
    header_.channels = c_.num_components == 1 ? 1 : 3;
    header_.compression = "jpeg";
    for (const jpeg_marker_struct* m = c_.marker_list; m; m = m->next) {
      const auto* d = reinterpret_cast<const char*>(m->data);
      if (m->marker == JPEG_APP0 + 1 && starts_with(m, kExifHeader, sizeof kExifHeader) && embedded_.exif.empty())
        embedded_.exif.assign(d + sizeof kExifHeader, m->data_length - sizeof kExifHeader);
      else if (m->marker == JPEG_APP0 + 1 && starts_with(m, kXmpHeader, sizeof kXmpHeader) && embedded_.xmp.empty())
        embedded_.xmp.assign(d + sizeof kXmpHeader, m->data_length - sizeof kXmpHeader);
    }
    JOCTET* icc = nullptr;
    unsigned int icc_bytes = 0;
    if (guarded(fail_, [&] { jpeg_read_icc_profile(&c_, &icc, &icc_bytes); }) && icc)
      embedded_.icc.assign(reinterpret_cast<const char*>(icc), icc_bytes);
    std::free(icc);
  }
  void release() {
    if (created_) jpeg_destroy_decompress(&c_), created_ = false;
    if (file_) std::fclose(file_), file_ = nullptr;
  }

 public:
  // libjpeg's output size at scale_num / scale_denom: ceil(size / scale).
  Size scaled_size(int scale) const override {
    if (scale != 1 && scale != 2 && scale != 4 && scale != 8) return {};
    return {(header_.size.width + scale - 1) / scale, (header_.size.height + scale - 1) / scale};
  }

  PixelRect window(PixelRect need, int) const override { return need; }

  // Without arrived, a baseline JPEG's large region decodes in two bands at once: a second
  // decoder skips to the lower band (entropy decoding only: kSkipCost of a decoded row) while
  // this one decodes the upper; the split balances the two. (A progressive JPEG would read every
  // scan twice.)
  void read_into(PixelRect r, int scale, Image& img, const RowsArrived& arrived) override {
    const int64_t rows = r.y1 - r.y0;
    const bool split = !arrived && !c_.progressive_mode && rows >= 64 && r.size().width * rows >= (int64_t{1} << 20) &&
                       std::thread::hardware_concurrency() > 1;
    constexpr double kSkipCost = 0.55;  // measured: skipping a row costs about half of decoding it
    const int64_t mid = split ? std::clamp<int64_t>(static_cast<int64_t>((static_cast<double>(r.y1) + (1 - kSkipCost) * static_cast<double>(r.y0)) / (2 - kSkipCost)), r.y0 + 16, r.y1 - 16)
                              : r.y1;
    std::string lower_error;
    bool ok = true;
    parallel_tasks(split ? 2 : 1, 2, [&](int64_t band, int) {
      std::vector<unsigned char> buffer;
      if (band == 0) {
        ok = guarded(fail_, [&] { decode({r.x0, r.y0, r.x1, mid}, scale, img, r.y0, buffer, arrived); });
        return;
      }
      JpegDecoder other(path_);
      if (!guarded(other.fail_, [&] { other.decode({r.x0, mid, r.x1, r.y1}, scale, img, r.y0, buffer, {}); }))
        lower_error = other.fail_.message;
    });
    if (!ok) throw_damaged(path_, fail_.message);
    if (!lower_error.empty()) throw_damaged(path_, lower_error);
  }

  EmbeddedMetadata embedded() const override { return embedded_; }

 private:
  // Decodes rows r.y0 .. r.y1 - 1 (columns r.x0 .. r.x1 - 1) into img's rows from y_base on,
  // starting one iMCU above and to the left and ending one to the right, so that the chroma
  // upsampling at the region's edges sees the neighbours it sees in a whole decode; what lies
  // outside r is decoded and dropped.
  void decode(PixelRect r, int scale, Image& img, int64_t y_base, std::vector<unsigned char>& row,
              const RowsArrived& arrived) {
    c_.scale_num = 1;
    c_.scale_denom = static_cast<unsigned int>(scale);
    c_.out_color_space = c_.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_start_decompress(&c_);
    const auto width = static_cast<int64_t>(c_.output_width);
    const int64_t imcu_w = int64_t{c_.max_h_samp_factor} * c_.min_DCT_scaled_size;
    const int64_t imcu_h = int64_t{c_.max_v_samp_factor} * c_.min_DCT_scaled_size;
    auto x0 = static_cast<JDIMENSION>(std::max<int64_t>(0, r.x0 - imcu_w));
    auto cols = static_cast<JDIMENSION>(std::min(width, r.x1 + imcu_w) - x0);
    if (x0 > 0 || cols < width) jpeg_crop_scanline(&c_, &x0, &cols);  // x0 down to an iMCU boundary
    const auto y_start = static_cast<JDIMENSION>(std::max<int64_t>(0, r.y0 - imcu_h));
    if (y_start > 0) jpeg_skip_scanlines(&c_, y_start);
    const size_t px = static_cast<size_t>(c_.output_components);
    const bool direct = x0 == r.x0 && cols == r.x1 - r.x0;  // rows land in img as they are
    row.resize(size_t{cols} * px);
    while (c_.output_scanline < r.y1) {
      const int64_t y = c_.output_scanline;
      JSAMPROW dst = direct && y >= r.y0 ? img.row(y - y_base) : row.data();
      jpeg_read_scanlines(&c_, &dst, 1);
      if (!direct && y >= r.y0) std::memcpy(img.row(y - y_base), row.data() + (r.x0 - x0) * px, img.row_bytes());
      if (y >= r.y0) rows_in(arrived, y + 1 - y_base, r.y1 - y_base);
    }
    jpeg_abort_decompress(&c_);  // the rows below are never decoded
  }

  std::string path_;
  static constexpr size_t kReadBuffer = size_t{1} << 18;
  std::unique_ptr<char[]> buffer_;  // file_'s (declared first: outlives the FILE)
  FILE* file_ = nullptr;
  jpeg_decompress_struct c_{};
  JpegFailure fail_;
  bool created_ = false;
  EmbeddedMetadata embedded_;
};

// Appends the encoded bytes to a buffer (doubling it as it fills).
struct VectorDestination {
  jpeg_destination_mgr mgr;
  FileBytes* out;
};

void grow(j_compress_ptr c, size_t to) {
  auto* d = reinterpret_cast<VectorDestination*>(c->dest);
  const size_t used = d->out->size() - d->mgr.free_in_buffer;
  try {
    d->out->resize(to);
  } catch (const std::bad_alloc&) {
    ERREXIT(c, JERR_OUT_OF_MEMORY);
  }
  d->mgr.next_output_byte = d->out->data() + used;
  d->mgr.free_in_buffer = d->out->size() - used;
}

void init_destination(j_compress_ptr c) {
  auto* d = reinterpret_cast<VectorDestination*>(c->dest);
  d->out->clear();
  d->mgr.free_in_buffer = 0;
  grow(c, std::max<size_t>(d->out->capacity(), 65536));
}

boolean empty_output_buffer(j_compress_ptr c) {
  auto* d = reinterpret_cast<VectorDestination*>(c->dest);
  d->mgr.free_in_buffer = 0;  // libjpeg calls this with the buffer full
  grow(c, 2 * d->out->size());
  return TRUE;
}

void term_destination(j_compress_ptr c) {
  auto* d = reinterpret_cast<VectorDestination*>(c->dest);
  d->out->resize(d->out->size() - d->mgr.free_in_buffer);
}

}  // namespace

std::unique_ptr<Decoder> open_jpeg(const std::string& path, const InputFile&) {
  auto d = std::make_unique<JpegDecoder>(path);
  if (!d->supported()) return nullptr;
  return d;
}

namespace {

// Pixels r of image as a whole JPEG file, a restart marker every `interval` MCUs (0: none); false
// with fail.message on an error.
bool encode_part(const Image& image, const PixelRect& r, const WriteOptions& options, const EmbeddedMetadata& meta,
                 unsigned interval, FileBytes& bytes, JpegFailure& fail) {
  // Gray or RGB; an alpha channel (the last) is left out.
  const int in_channels = image.channels(), channels = in_channels <= 2 ? 1 : 3;
  const int64_t width = r.x1 - r.x0;
  std::vector<unsigned char> row;
  bytes.reserve(static_cast<size_t>(width * (r.y1 - r.y0) * channels / 6) + 65536);  // (kept when reused)
  if (in_channels != channels) row.resize(static_cast<size_t>(width * channels));
  jpeg_compress_struct c{};
  c.err = jpeg_std_error(&fail.mgr);
  fail.mgr.error_exit = on_error;
  fail.mgr.emit_message = on_encode_message;
  VectorDestination dest{{}, &bytes};
  dest.mgr.init_destination = init_destination;
  dest.mgr.empty_output_buffer = empty_output_buffer;
  dest.mgr.term_destination = term_destination;
  bool created = false;
  const bool ok = guarded(fail, [&] {
    jpeg_create_compress(&c);
    created = true;
    c.dest = &dest.mgr;
    c.image_width = static_cast<JDIMENSION>(width);
    c.image_height = static_cast<JDIMENSION>(r.y1 - r.y0);
    c.input_components = channels;
    c.in_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, options.quality, TRUE);
    c.restart_interval = interval;
    if (channels == 3) {
      const int h = options.subsampling == ChromaSubsampling::S444 ? 1 : 2;
      const int v = options.subsampling == ChromaSubsampling::S420 ? 2 : 1;
      c.comp_info[0].h_samp_factor = h, c.comp_info[0].v_samp_factor = v;
      for (int k = 1; k < 3; ++k) c.comp_info[k].h_samp_factor = c.comp_info[k].v_samp_factor = 1;
    }
    jpeg_start_compress(&c, TRUE);
    // EXIF (APP1) first after JFIF, then XMP (APP1), then the ICC profile (APP2, in chunks).
    if (!meta.exif.empty() && meta.exif.size() + sizeof kExifHeader <= 65533) {
      std::string seg(kExifHeader, sizeof kExifHeader);
      seg += meta.exif;
      jpeg_write_marker(&c, JPEG_APP0 + 1, reinterpret_cast<const JOCTET*>(seg.data()),
                        static_cast<unsigned int>(seg.size()));
    }
    if (!meta.xmp.empty() && meta.xmp.size() + sizeof kXmpHeader <= 65533) {
      std::string seg(kXmpHeader, sizeof kXmpHeader);
      seg += meta.xmp;
      jpeg_write_marker(&c, JPEG_APP0 + 1, reinterpret_cast<const JOCTET*>(seg.data()),
                        static_cast<unsigned int>(seg.size()));
    }
    if (!meta.icc.empty())
      jpeg_write_icc_profile(&c, reinterpret_cast<const JOCTET*>(meta.icc.data()),
                             static_cast<unsigned int>(meta.icc.size()));
    for (int64_t y = r.y0; y < r.y1; ++y) {
      auto* src = const_cast<unsigned char*>(image.pixel(r.x0, y));
      JSAMPROW p = src;
      if (!row.empty()) {
        for (int64_t x = 0; x < width; ++x)
          for (int k = 0; k < channels; ++k) row[static_cast<size_t>(x * channels + k)] = src[x * in_channels + k];
        p = row.data();
      }
      jpeg_write_scanlines(&c, &p, 1);
    }
    jpeg_finish_compress(&c);
  });
  if (created) jpeg_destroy_compress(&c);
  return ok;
}

// Where a JPEG file's entropy-coded data starts (after its SOS segment), and its SOF's height
// field (the width follows it); libjpeg's own output, so well formed.
void locate(const unsigned char* b, size_t size, size_t& sof_height, size_t& data) {
  for (size_t at = 2; at + 4 <= size;) {
    const unsigned marker = b[at + 1], length = b[at + 2] << 8 | b[at + 3];
    if (marker == 0xC0 || marker == 0xC1) sof_height = at + 5;
    if (marker == 0xDA) {
      data = at + 2 + length;
      return;
    }
    at += 2 + length;
  }
  throw InternalError("libjpeg's output has no scan");
}

void put16(unsigned char* p, int64_t v) {
  p[0] = static_cast<unsigned char>(v >> 8), p[1] = static_cast<unsigned char>(v & 0xFF);
}

constexpr int64_t kBlockWidth = 1024;  // columns of blocks at least this wide (where they divide the MCU row)
constexpr int64_t kBandHeight = 128;   // rows of blocks (pixels)

}  // namespace

struct JpegBlockEncoder::Block {
  PixelRect r;
  std::atomic<int64_t> left{0};  // pixels not yet final
  bool encoded = false;
  const unsigned char* scan = nullptr;  // its entropy-coded data: in the arena, or in own
  FileBytes own;
  std::vector<size_t> cuts;  // segment k: scan[cuts[2k] .. cuts[2k + 1])
};

JpegBlockEncoder::JpegBlockEncoder(Size size, int channels, std::string path, WriteOptions options,
                                   EmbeddedMetadata meta)
    : size_(size), path_(std::move(path)), options_(std::move(options)), meta_(std::move(meta)) {
  const bool colour = channels > 2;
  mcu_w_ = colour && options_.subsampling != ChromaSubsampling::S444 ? 16 : 8;
  mcu_h_ = colour && options_.subsampling == ChromaSubsampling::S420 ? 16 : 8;
  const int64_t per_row = (size.width + mcu_w_ - 1) / mcu_w_, mcu_rows = (size.height + mcu_h_ - 1) / mcu_h_;
  if (resolve_threads(options_.threads) > 1 && size.width * size.height >= (int64_t{1} << 20)) {
    // The most columns of at least kBlockWidth that divide the MCU row (the restart interval is
    // one block's row, the same for all).
    for (int64_t d = 2; d <= per_row; ++d)
      if (per_row % d == 0 && per_row / d * mcu_w_ >= kBlockWidth) cols_ = d;
    band_rows_ = std::max<int64_t>(1, kBandHeight / mcu_h_);
    interval_ = static_cast<unsigned>(per_row / cols_);
  } else {
    band_rows_ = mcu_rows;  // one block, no restarts
  }
  const int64_t bands = (mcu_rows + band_rows_ - 1) / band_rows_;
  const int64_t block_w = per_row / cols_ * mcu_w_, band_h = band_rows_ * mcu_h_;
  n_blocks_ = bands * cols_;
  blocks_ = std::make_unique<Block[]>(static_cast<size_t>(n_blocks_));
  for (int64_t b = 0; b < n_blocks_; ++b) {
    Block& k = blocks_[static_cast<size_t>(b)];
    const int64_t x0 = b % cols_ * block_w, y0 = b / cols_ * band_h;
    k.r = {x0, y0, std::min(size.width, x0 + block_w), std::min(size.height, y0 + band_h)};
    k.left = (k.r.x1 - k.r.x0) * (k.r.y1 - k.r.y0);
  }
  // The blocks' scans go side by side into one buffer (a quarter of the samples, at most 256 MB:
  // a block that finds it full, or none, keeps its own), untouched until written: few fresh
  // pages, huge ones when large.
  if (n_blocks_ > 1) {
    try {
      arena_.resize(std::min<size_t>(static_cast<size_t>(size.width * size.height * (colour ? 3 : 1) / 4), size_t{256} << 20));
    } catch (const std::bad_alloc&) {
      arena_ = {};
    }
  }
}

JpegBlockEncoder::~JpegBlockEncoder() = default;

void JpegBlockEncoder::encode(const Image& image, int64_t b) {
  Block& k = blocks_[static_cast<size_t>(b)];
  JpegFailure fail;
  if (n_blocks_ == 1) {  // the file itself
    if (!encode_part(image, k.r, options_, meta_, 0, k.own, fail))
      throw Error("cannot write " + path_ + ": " + one_line(fail.message), ErrorKind::File);
    k.encoded = true;
    return;
  }
  // Encoded into a buffer reused across blocks (its pages touched once).
  FileBytes bytes;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!spare_.empty()) bytes = std::move(spare_.back()), spare_.pop_back();
  }
  const bool ok = encode_part(image, k.r, options_, b == 0 ? meta_ : EmbeddedMetadata{}, interval_, bytes, fail);
  const auto give_back = [&] {
    const std::lock_guard<std::mutex> lock(mutex_);
    spare_.push_back(std::move(bytes));
  };
  if (!ok) {
    give_back();
    throw Error("cannot write " + path_ + ": " + one_line(fail.message), ErrorKind::File);
  }
  size_t sof = 0, start = 0;
  locate(bytes.data(), bytes.size(), sof, start);
  if (b == 0) header_.assign(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(start)), sof_ = sof;
  const size_t n = bytes.size() - 2 - start;  // the scan (its EOI left out)
  const size_t at = arena_used_.fetch_add(n);
  unsigned char* scan = nullptr;
  if (at + n <= arena_.size()) scan = arena_.data() + at;
  else k.own.resize(n), scan = k.own.data();
  std::memcpy(scan, bytes.data() + start, n);
  give_back();
  // Its segments, one per MCU row, between its restart markers (0xFF 0xD0-0xD7; a 0xFF in the
  // data is followed by 0x00).
  k.cuts.push_back(0);
  for (size_t i = 0; i + 1 < n; ++i) {
    const void* p = std::memchr(scan + i, 0xFF, n - 1 - i);
    if (!p) break;
    i = static_cast<size_t>(static_cast<const unsigned char*>(p) - scan);
    if (scan[i + 1] >= 0xD0 && scan[i + 1] <= 0xD7) k.cuts.push_back(i), k.cuts.push_back(i + 2), ++i;
  }
  k.cuts.push_back(n);
  if (static_cast<int64_t>(k.cuts.size()) != 2 * ((k.r.y1 - k.r.y0 + mcu_h_ - 1) / mcu_h_))
    throw InternalError("a JPEG block's restart markers do not match its MCU rows");
  k.scan = scan;
  k.encoded = true;
}

void JpegBlockEncoder::done(const Image& image, const PixelRect& r) {
  const int64_t block_w = blocks_[0].r.x1, band_h = band_rows_ * mcu_h_;
  for (int64_t by = r.y0 / band_h; by * band_h < r.y1; ++by)
    for (int64_t bx = r.x0 / block_w; bx * block_w < r.x1 && bx < cols_; ++bx) {
      const int64_t b = by * cols_ + bx;
      Block& k = blocks_[static_cast<size_t>(b)];
      const int64_t part = (std::min(r.x1, k.r.x1) - std::max(r.x0, k.r.x0)) * (std::min(r.y1, k.r.y1) - std::max(r.y0, k.r.y0));
      if (part > 0 && k.left.fetch_sub(part) == part) encode(image, b);
    }
}

FileBytes JpegBlockEncoder::finish(const Image& image) {
  std::vector<int64_t> rest;
  for (int64_t b = 0; b < n_blocks_; ++b)
    if (!blocks_[static_cast<size_t>(b)].encoded) rest.push_back(b);
  parallel_tasks(static_cast<int64_t>(rest.size()), options_.threads,
                 [&](int64_t t, int) { encode(image, rest[static_cast<size_t>(t)]); });
  if (n_blocks_ == 1) return std::move(blocks_[0].own);
  // Block 0's headers, the whole size in its SOF; then for each MCU row, the blocks across it in
  // turn, restart markers numbered on (RSTm before interval i: m = (i - 1) mod 8); one EOI.
  const int64_t mcu_rows = (size_.height + mcu_h_ - 1) / mcu_h_;
  size_t total = header_.size() + 2 * static_cast<size_t>(mcu_rows * cols_) + 2;
  for (int64_t b = 0; b < n_blocks_; ++b) total += blocks_[static_cast<size_t>(b)].cuts.back();
  FileBytes bytes(total);
  unsigned char* out = bytes.data();
  out = std::copy(header_.begin(), header_.end(), out);
  put16(bytes.data() + sof_, size_.height), put16(bytes.data() + sof_ + 2, size_.width);
  for (int64_t row = 0, i = 0; row < mcu_rows; ++row)
    for (int64_t c = 0; c < cols_; ++c, ++i) {
      const Block& k = blocks_[static_cast<size_t>(row / band_rows_ * cols_ + c)];
      const size_t s = static_cast<size_t>(row % band_rows_);
      if (i > 0) *out++ = 0xFF, *out++ = static_cast<unsigned char>(0xD0 + (i - 1) % 8);
      out = std::copy(k.scan + k.cuts[2 * s], k.scan + k.cuts[2 * s + 1], out);
    }
  *out++ = 0xFF, *out++ = 0xD9;
  bytes.resize(static_cast<size_t>(out - bytes.data()));
  return bytes;
}

FileBytes encode_jpeg(const Image& image, const std::string& path, const WriteOptions& options,
                      const EmbeddedMetadata& meta) {
  return JpegBlockEncoder(image.size(), image.channels(), path, options, meta).finish(image);
}

namespace {

// Whether a JPEG's frame header (SOFn before the first scan) is arithmetic-coded: SOF9..11, 13..15.
bool arithmetic_jpeg(const std::string& b) {
  for (size_t i = 2; i + 4 <= b.size() && static_cast<unsigned char>(b[i]) == 0xFF;) {
    const auto m = static_cast<unsigned char>(b[i + 1]);
    if (m == 0xDA || m == 0xD9) break;
    if (m >= 0xC9 && m <= 0xCF && m != 0xCC) return true;
    const size_t len =
        (static_cast<unsigned char>(b[i + 2]) << 8) | static_cast<unsigned char>(b[i + 3]);
    if (len < 2) break;
    i += 2 + len;
  }
  return false;
}

}  // namespace

// A Huffman-coded JPEG spends at least one bit per 8x8 luma block (its DC code); arithmetic
// coding can spend far less on flat areas (1/512 bit allowed). Sides up to libjpeg's 65500.
const ImageFormat kJpegFormat{
    .name = "jpeg",
    .title = "JPEG",
    .extensions = {".jpg", ".jpeg"},
    .sniff =
        [](const std::string& head, InputFile& file) {
          if (head.compare(0, 3, "\xFF\xD8\xFF") != 0) return false;
          file.arithmetic = arithmetic_jpeg(head);
          return true;
        },
    .most_stored =
        [](const InputFile& file, Size window, const std::string&) {
          const double blocks = static_cast<double>((window.width + 7) / 8) *
                                static_cast<double>((window.height + 7) / 8);
          return static_cast<double>(file.bytes) * 8.0 * (file.arithmetic ? 512.0 : 1.0) >= blocks
                     ? HUGE_VAL
                     : 0.0;
        },
    .max_side = 65500,
    .deepest = PixelType::U8,
    .embedded_metadata = true,
    .holds_alpha = false,
    .decodes_scaled = true,
    .streams_blocks = true,
    .web = true,
    .open = open_jpeg,
    .encode = encode_jpeg};

}  // namespace panoproj
