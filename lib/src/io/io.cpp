// The image files of io.hpp: by format, the built-in codecs (codec.hpp) or the OpenImageIO plugin.
#include "panoproj/io.hpp"

#include <Imath/half.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <optional>
#include <string_view>
#include <system_error>
#include <variant>
#include <vector>

#include "base/input_check.hpp"
#include "base/parallel.hpp"
#include "io/atomic_output.hpp"
#include "io/codec.hpp"
#include "io/exif.hpp"
#include "io/formats.hpp"
#include "io/oiio_plugin.hpp"
#include "io/region_read.hpp"
#include "io/streamed_output.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/photo_sphere.hpp"

namespace panoproj {

namespace fs = std::filesystem;

void check_writable_size(const std::string& path, Size size) {
  const ImageFormat& f = format_of_path(path);
  if (size.width > f.max_side || size.height > f.max_side)
    throw Error("cannot write " + path + ": " + size_text(size) + " pixels, over the " + f.title +
                " limit of " + std::to_string(f.max_side) +
                " a side (choose a smaller size or another format)");
}

ChromaSubsampling parse_subsampling(std::string_view text) {
  if (text == "420") return ChromaSubsampling::S420;
  if (text == "422") return ChromaSubsampling::S422;
  if (text == "444") return ChromaSubsampling::S444;
  throw Error("subsampling " + std::string(text) + " (expected 420, 422 or 444)");
}

void check_write_options(const WriteOptions& options) {
  if (options.quality < 1 || options.quality > 100)
    throw Error("quality: " + std::to_string(options.quality) + " (expected 1 to 100)");
}

namespace {

// The embedded blocks as an output of `size` carries them: EXIF rewritten for it, a Photo Sphere
// packet left out (it described the input's projection).
EmbeddedMetadata carried_blocks(const WriteOptions& options, Size size) {
  EmbeddedMetadata m = options.embedded;
  if (!m.exif.empty()) m.exif = exif_for_output(m.exif, size);
  if (m.xmp.find("GPano") != std::string::npos) m.xmp.clear();
  return m;
}

// A JPEG or PNG writer's blocks: the carried ones, or those made from attributes (ICCProfile;
// EXIF through OpenImageIO when there are others); the XMP packet given.
EmbeddedMetadata blocks_for(const WriteOptions& options, Size size) {
  EmbeddedMetadata m = carried_blocks(options, size);
  bool other = false;
  for (const Attribute& a : options.metadata) {
    const auto* b = std::get_if<std::vector<uint8_t>>(&a.value);
    if (a.name == "ICCProfile" && b && m.icc.empty()) m.icc.assign(b->begin(), b->end());
    other |= a.name != "ICCProfile";
  }
  if (other && m.exif.empty()) m.exif = oiio_backend("writing EXIF attributes").encode_exif(options.metadata);
  if (!options.xmp.empty()) m.xmp = options.xmp;
  return m;
}

// The file's bytes, encoded in memory: no codec touches the disk, so none can fail there or end
// the process on a write error; OutputSet writes the bytes. Samples the format cannot hold are
// converted first: to uint8 for JPEG, to uint16 for PNG and PPM from floats.
// (A built-in encoder's buffer, OpenImageIO's, or a header before the image's own samples.)
class Encoded {
 public:
  Encoded(FileBytes b) : bytes_(std::move(b)) {}
  Encoded(std::vector<unsigned char> b) : bytes_(std::move(b)) {}
  Encoded(std::string head, std::string_view body) : bytes_(std::move(head)), body_(body) {}
  // The file: one piece, or the header and the body.
  std::vector<std::string_view> pieces() const {
    std::vector<std::string_view> p{std::visit(
        [](const auto& b) { return std::string_view(reinterpret_cast<const char*>(b.data()), b.size()); }, bytes_)};
    if (!body_.empty()) p.push_back(body_);
    return p;
  }

 private:
  std::variant<FileBytes, std::vector<unsigned char>, std::string> bytes_;
  std::string_view body_;  // held by the image written
};

void write_encoded(const Encoded& e, const std::string& path, bool overwrite) {
  OutputSet set(overwrite);
  set.add(path, e.pieces());
  set.commit();
}

Encoded encode(const Image& in, const std::string& path, const WriteOptions& options) {
  check_write_options(options);
  const ImageFormat& format = format_of_path(path);
  const PixelType type = format.stored_type(options.type.value_or(in.type()));
  Image converted;
  const Image& image = type == in.type() ? in : (converted = convert_pixels(in, type));
  check_writable_size(path, image.size());
  if (format.raw_header && &image == &in) {
    // Samples the format stores as they are need no copy: the header, then the image's rows.
    if (std::string head = format.raw_header(image); !head.empty())
      return Encoded(std::move(head), {reinterpret_cast<const char*>(image.data()),
                                       image.row_bytes() * static_cast<size_t>(image.height())});
  }
  if (format.encode) return format.encode(image, path, options, blocks_for(options, image.size()));
  OiioBackend& oiio = oiio_backend("writing " + path);
  const EmbeddedMetadata blocks = carried_blocks(options, image.size());
  return oiio.encode(image, path, options, blocks.empty() ? Metadata{} : oiio.attributes_of(blocks));
}

// An input opened for reading: a regular file of one of the six formats by its magic bytes, its
// header read by that format's reader (CMYK JPEGs: OpenImageIO's), its channels checked.
struct Opened {
  InputFile file;
  std::unique_ptr<Decoder> decoder;
  const ImageHeader& header() const { return decoder->header(); }
};

Opened open_input(const std::string& path) {
  Opened o{probe_input(path), nullptr};
  if (const ImageFormat& f = format_named(o.file.format); f.built_in())
    o.decoder = f.open(path, o.file);
  else
    o.decoder = oiio_backend("reading " + path).open(path, o.file);
  return o;
}

}  // namespace

// EncodedOutput's files (and the faces a PPM's pieces point into).
struct EncodedOutput::Files {
  explicit Files(bool o) : overwrite(o) {}
  void add(std::string path, Encoded e) { files.emplace_back(std::move(path), std::move(e)); }
  bool overwrite;
  std::vector<std::pair<std::string, Encoded>> files;
  std::vector<Image> faces;
};

EncodedOutput::EncodedOutput() = default;
EncodedOutput::~EncodedOutput() = default;
EncodedOutput::EncodedOutput(EncodedOutput&&) noexcept = default;
EncodedOutput& EncodedOutput::operator=(EncodedOutput&&) noexcept = default;
EncodedOutput::EncodedOutput(std::unique_ptr<Files> files) : files_(std::move(files)) {}

void EncodedOutput::write(const std::function<void()>& landed) const {
  if (!files_) throw InternalError("an empty EncodedOutput written");
  OutputSet set(files_->overwrite);
  for (const auto& [path, e] : files_->files) set.add(path, e.pieces());
  set.commit(landed);
}

void write_bytes(std::string_view bytes, const std::string& path, bool overwrite) {
  OutputSet set(overwrite);
  set.add(path, bytes);
  set.commit();
}

void write_text(const std::string& text, const std::string& path, bool overwrite) { write_bytes(text, path, overwrite); }

ImageInfo read_image_info(const std::string& path) {
  const Opened o = open_input(path);
  const ImageHeader& h = o.header();
  return {h.size, h.channels, h.type, o.file.format, o.decoder->scale_ok(8)};
}

Size read_image_size(const std::string& path) { return read_image_info(path).size; }

Image read_image(const std::string& path, int64_t memory_limit) {
  return read_image_region(path, 0, 0, INT64_MAX, INT64_MAX, memory_limit);
}

Metadata read_metadata(const std::string& path) {
  const InputFile file = probe_input(path);
  const bool built_in = format_named(file.format).built_in();
  const bool all = built_in && !oiio_available();
  Metadata out;
  if (!all) out = oiio_backend("reading the metadata of " + path).metadata(path, file);
  if (!built_in) return out;
  // Without OpenImageIO: the ICC profile, EXIF's common tags and the GPano fields; with it, the
  // GPano fields it left out (it reads no GPano packet laid out as panoproj writes it).
  const EmbeddedMetadata m = read_embedded_metadata(path);
  for (Attribute& a : all ? built_in_attributes(m) : photo_sphere_attributes(m.xmp))
    if (std::none_of(out.begin(), out.end(), [&](const Attribute& o) { return o.name == a.name; })) out.push_back(std::move(a));
  return out;
}

EmbeddedMetadata read_embedded_metadata(const std::string& path) { return open_input(path).decoder->embedded(); }

Metadata built_in_attributes(const EmbeddedMetadata& blocks) {
  Metadata out = exif_attributes(blocks.exif);
  if (!blocks.icc.empty()) out.push_back({"ICCProfile", std::vector<uint8_t>(blocks.icc.begin(), blocks.icc.end())});
  for (Attribute& a : photo_sphere_attributes(blocks.xmp)) out.push_back(std::move(a));
  return out;
}

RegionRead::RegionRead(const std::string& path, int64_t x0, int64_t y0, int64_t x1, int64_t y1,
                       int64_t memory_limit, uint64_t other_bytes, int scale, Image spare)
    : path_(path), scale_(scale) {
  Opened o = open_input(path);
  const ImageHeader& h = o.header();
  if (!o.decoder->scale_ok(scale))
    throw Error("cannot read " + path + " at 1/" + std::to_string(scale) + " scale (" + o.file.format +
                " files decode at full scale)");
  const Size frame = o.decoder->scaled_size(scale);
  x0 = std::clamp<int64_t>(x0, 0, frame.width), x1 = std::clamp<int64_t>(x1, x0, frame.width);
  y0 = std::clamp<int64_t>(y0, 0, frame.height), y1 = std::clamp<int64_t>(y1, y0, frame.height);
  if (x1 == x0 || y1 == y0) x0 = 0, x1 = 1, y0 = 0, y1 = 1;  // nothing needed: one pixel
  window_ = o.decoder->window({x0, y0, x1, y1}, scale);
  // Before any pixel is decoded: the file can hold what is decoded (at full scale), and it fits.
  const Size stored{std::min(h.size.width, window_.size().width * scale),
                    std::min(h.size.height, window_.size().height * scale)};
  check_plausible(path, o.file, h.size, h.channels, h.sample_bits, h.compression, stored,
                  add_bytes(image_bytes(window_.size(), h.channels, bytes_of(h.type)), other_bytes), memory_limit);
  decoder_ = std::move(o.decoder);
  image_ = window_buffer(path, *decoder_, window_, scale, std::move(spare));
}

void RegionRead::read(const RowsArrived& arrived) { decoder_->read_into(window_, scale_, image_, arrived); }

Image read_image_region(const std::string& path, int64_t x0, int64_t y0, int64_t x1, int64_t y1,
                        int64_t memory_limit, uint64_t other_bytes, int scale) {
  RegionRead r(path, x0, y0, x1, y1, memory_limit, other_bytes, scale);
  r.read();
  return std::move(r.image());
}

void write_image(const Image& image, const std::string& path, const WriteOptions& options) {
  check_output_path(path, options.overwrite);
  write_encoded(encode(image, path, options), path, options.overwrite);
}

StreamedOutput::StreamedOutput(std::string path, WriteOptions options, Size size, int channels, PixelType type)
    : path_(std::move(path)), options_(std::move(options)) {
  check_write_options(options_);
  check_writable_size(path_, size);
  // (A JPEG takes uint8 samples as they are; others are converted first, in encode.)
  if (format_of_path(path_).streams_blocks && type == PixelType::U8 &&
      options_.type.value_or(type) == type)
    jpeg_ = std::make_unique<JpegBlockEncoder>(size, channels, path_, options_, blocks_for(options_, size));
}

StreamedOutput::~StreamedOutput() = default;

void StreamedOutput::done(const Image& image, const PixelRect& r) {
  if (jpeg_) jpeg_->done(image, r);
}

EncodedOutput StreamedOutput::finish(const Image& image) {
  check_output_path(path_, options_.overwrite);
  auto files = std::make_unique<EncodedOutput::Files>(options_.overwrite);
  files->add(path_, jpeg_ ? Encoded(jpeg_->finish(image)) : encode(image, path_, options_));
  return EncodedOutput(std::move(files));
}

Image convert_pixels(const Image& in, PixelType type) {
  Image out(in.size(), in.channels(), type, in.alpha_channel());
  const size_t n = static_cast<size_t>(in.width()) * static_cast<size_t>(in.height()) *
                   static_cast<size_t>(in.channels());
  const double from_unit = unit_of(in.type()), to_unit = unit_of(type);
  const bool to_int = type == PixelType::U8 || type == PixelType::U16;
  for (size_t i = 0; i < n; ++i) {
    double v = 0;
    const unsigned char* p = in.data() + i * bytes_of(in.type());
    switch (in.type()) {
      case PixelType::U8: v = *p; break;
      case PixelType::U16: { uint16_t t; std::memcpy(&t, p, 2); v = t; break; }
      case PixelType::F16: { Imath::half t; std::memcpy(&t, p, 2); v = float(t); break; }
      case PixelType::F32: { float t; std::memcpy(&t, p, 4); v = t; break; }
    }
    v = v / from_unit * to_unit;
    // NaN has no integer: 0 (as -inf); +inf is the largest value.
    if (to_int) v = std::isnan(v) ? 0.0 : std::clamp(std::nearbyint(v), 0.0, to_unit);
    unsigned char* q = out.data() + i * bytes_of(type);
    switch (type) {
      case PixelType::U8: *q = static_cast<uint8_t>(v); break;
      case PixelType::U16: { const auto t = static_cast<uint16_t>(v); std::memcpy(q, &t, 2); break; }
      case PixelType::F16: { const Imath::half t(static_cast<float>(v)); std::memcpy(q, &t, 2); break; }
      case PixelType::F32: { const auto t = static_cast<float>(v); std::memcpy(q, &t, 4); break; }
    }
  }
  return out;
}

bool is_face_pattern(std::string_view path) {
  return path.find("{face}") != std::string_view::npos ||
         path.find("{index}") != std::string_view::npos || path.find("{axis}") != std::string_view::npos;
}

std::string face_path(std::string_view pattern, int slot, const FaceOrder& order) {
  std::string s(pattern);
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{face}", kFaceNames[order.face[slot]]},
                                   {"{index}", std::to_string(slot)},
                                   {"{axis}", kAxisNames[order.axis[slot]]}}) {
    for (size_t at; (at = s.find(key)) != std::string::npos;) s.replace(at, key.size(), value);
  }
  return s;
}

Image read_cube_faces(const std::string& pattern, int64_t memory_limit, const FaceOrder& order) {
  Image strip;
  for (int f = 0; f < 6; ++f) {
    const std::string path = face_path(pattern, f, order);
    const Image face = read_image(path, memory_limit);
    if (face.width() != face.height())
      throw Error("cube face " + path + " is " + std::to_string(face.width()) + "x" +
                  std::to_string(face.height()) + " (expected square faces)");
    if (f == 0) {
      strip = Image({6 * face.width(), face.height()}, face.channels(), face.type(),
                    face.alpha_channel());
    } else if (face.width() != strip.height() || face.channels() != strip.channels() ||
               face.type() != strip.type()) {
      throw Error("cube face " + path + " is " + std::to_string(face.width()) + "x" +
                  std::to_string(face.height()) + " " + std::to_string(face.channels()) + "ch " +
                  name_of(face.type()) + ", but " + face_path(pattern, 0, order) + " is " +
                  std::to_string(strip.height()) + "x" + std::to_string(strip.height()) + " " +
                  std::to_string(strip.channels()) + "ch " + name_of(strip.type()) +
                  " (all six faces must match)");
    }
    for (int64_t y = 0; y < face.height(); ++y)
      std::memcpy(strip.pixel(f * face.width(), y), face.row(y), face.row_bytes());
  }
  return strip;
}

Image read_strip_pair(const std::string& first, const std::string& second, int64_t memory_limit) {
  const Image a = read_image(first, memory_limit);
  const Image b = read_image(second, memory_limit);
  auto text = [](const Image& im) {
    return size_text(im.size()) + " " + std::to_string(im.channels()) + "ch " + name_of(im.type());
  };
  if (b.size() != a.size() || b.channels() != a.channels() || b.type() != a.type())
    throw Error("GoPro MAX strips: " + second + " is " + text(b) + " but " + first + " is " +
                text(a) +
                " (expected one frame of each of the two streams: equal sizes and samples)");
  Image pair({a.width(), 2 * a.height()}, a.channels(), a.type(), a.alpha_channel(),
             Image::Unfilled{});
  for (int64_t y = 0; y < a.height(); ++y) {
    std::memcpy(pair.row(y), a.row(y), a.row_bytes());
    std::memcpy(pair.row(a.height() + y), b.row(y), b.row_bytes());
  }
  return pair;
}

EncodedOutput encode_cube_faces(const Image& strip, const std::string& pattern, const WriteOptions& options,
                                const FaceOrder& order) {
  if (strip.width() != 6 * strip.height())
    throw Error("cube faces: a " + size_text(strip.size()) + " image (expected the 6x1 strip of six square faces, " +
                "6N x N pixels)");
  const int64_t f = strip.height();
  for (int i = 0; i < 6; ++i) check_output_path(face_path(pattern, i, order), options.overwrite);
  auto files = std::make_unique<EncodedOutput::Files>(options.overwrite);
  files->faces.resize(6);
  std::vector<std::optional<Encoded>> encoded(6);
  // The faces at once (PNG and OpenImageIO's formats encode on one thread each).
  parallel_tasks(6, options.threads, [&](int64_t i, int) {
    Image& face = files->faces[static_cast<size_t>(i)];
    face = Image({f, f}, strip.channels(), strip.type(), strip.alpha_channel(), Image::Unfilled{});
    for (int64_t y = 0; y < f; ++y) std::memcpy(face.row(y), strip.pixel(i * f, y), face.row_bytes());
    encoded[static_cast<size_t>(i)] = encode(face, face_path(pattern, static_cast<int>(i), order), options);
  });
  for (int i = 0; i < 6; ++i) files->add(face_path(pattern, i, order), std::move(*encoded[static_cast<size_t>(i)]));
  return EncodedOutput(std::move(files));
}

void write_cube_faces(const Image& strip, const std::string& pattern, const WriteOptions& options,
                      const FaceOrder& order) {
  encode_cube_faces(strip, pattern, options, order).write();
}

}  // namespace panoproj
