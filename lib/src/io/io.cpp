// OpenImageIO is included only here (compile-time hot spot; keep it out of public headers).
#include "panoproj/io.hpp"

#include <Imath/half.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <system_error>
#include <vector>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/photo_sphere.hpp"
#include "io/atomic_output.hpp"
#include "base/input_check.hpp"

namespace panoproj {

const char* const kFaceNames[6] = {"front", "right", "back", "left", "up", "down"};

namespace fs = std::filesystem;
namespace {

OIIO::TypeDesc oiio_type(PixelType t) {
  switch (t) {
    case PixelType::U8: return OIIO::TypeDesc::UINT8;
    case PixelType::U16: return OIIO::TypeDesc::UINT16;
    case PixelType::F16: return OIIO::TypeDesc::HALF;
    case PixelType::F32: return OIIO::TypeDesc::FLOAT;
  }
  return OIIO::TypeDesc::UINT8;
}

// Closest panoproj type that holds the file's samples without loss (others go to float).
PixelType from_oiio(OIIO::TypeDesc t) {
  if (t == OIIO::TypeDesc::UINT8) return PixelType::U8;
  if (t == OIIO::TypeDesc::UINT16) return PixelType::U16;
  if (t == OIIO::TypeDesc::HALF) return PixelType::F16;
  return PixelType::F32;
}

// Largest side each format's writer takes (libjpeg ends the process beyond 65500; the others
// store sides as 32-bit integers).
int64_t max_side(const std::string& lower_ext) {
  return lower_ext == ".jpg" || lower_ext == ".jpeg" ? 65500 : INT_MAX;
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

void check_writable_size(const std::string& path, Size size) {
  const std::string ext = lower_extension(path);
  if (size.width > max_side(ext) || size.height > max_side(ext))
    throw Error("cannot write " + path + ": " + size_text(size) + " pixels, over the " +
                (ext == ".jpg" || ext == ".jpeg" ? "JPEG" : "format") + " limit of " + std::to_string(max_side(ext)) +
                " a side (choose a smaller size or another format)");
}

namespace {

// The file's bytes, encoded in memory (OpenImageIO writing to an IOProxy): no codec touches the
// disk, so none can fail there or end the process on a write error; OutputSet writes the bytes.
std::vector<unsigned char> encode(const Image& in, const std::string& path, const WriteOptions& options) {
  const Image* image = &in;
  Image converted;
  if (options.type && *options.type != in.type()) {
    converted = convert_pixels(in, *options.type);
    image = &converted;
  }
  const std::string ext = lower_extension(path);
  check_writable_size(path, image->size());
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->supports("ioproxy"))
    throw Error("cannot write " + path + ": no image format for its extension (use .jpg .png .tif .exr .hdr)",
                ErrorKind::File);
  int nch = image->channels();
  int alpha = image->alpha_channel();
  // Formats without alpha (JPEG, HDR) get the colour channels only.
  if (alpha >= 0 && !out->supports("alpha") && alpha == nch - 1) {
    --nch;
    alpha = -1;
  }
  OIIO::ImageSpec spec(static_cast<int>(image->width()), static_cast<int>(image->height()), nch,
                       oiio_type(image->type()));
  spec.alpha_channel = alpha;
  spec.attribute("oiio:UnassociatedAlpha", 1);  // colours are straight, as read
  if (static_cast<int>(options.channel_names.size()) == nch) spec.channelnames = options.channel_names;
  for (const Attribute& a : options.metadata) {
    if (const auto* i = std::get_if<int64_t>(&a.value)) {
      spec.attribute(a.name, static_cast<int>(std::clamp<int64_t>(*i, INT32_MIN, INT32_MAX)));
    } else if (const auto* d = std::get_if<double>(&a.value)) {
      spec.attribute(a.name, static_cast<float>(*d));
    } else if (const auto* t = std::get_if<std::string>(&a.value)) {
      spec.attribute(a.name, *t);
    } else if (const auto* v = std::get_if<std::vector<double>>(&a.value)) {
      const std::vector<float> f(v->begin(), v->end());
      spec.attribute(a.name, OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, static_cast<int>(f.size())), f.data());
    } else if (const auto* b = std::get_if<std::vector<uint8_t>>(&a.value)) {
      spec.attribute(a.name, OIIO::TypeDesc(OIIO::TypeDesc::UINT8, static_cast<int>(b->size())), b->data());
    }
  }
  if (ext == ".jpg" || ext == ".jpeg") spec.attribute("Compression", "jpeg:95");
  // Room for a quarter of the samples up front: fewer regrowths, each a copy into fresh pages.
  std::vector<unsigned char> bytes;
  bytes.reserve(std::min<size_t>(image->byte_size() / 4, size_t{256} << 20) + 65536);
  OIIO::Filesystem::IOVecOutput sink(bytes);
  bool ok = out->set_ioproxy(&sink) && out->open(path, spec);
  if (ok) {
    const auto stride = static_cast<OIIO::stride_t>(image->pixel_bytes());
    ok = out->write_image(oiio_type(image->type()), image->data(), stride);
  }
  ok = out->close() && ok;
  if (!ok) throw Error("cannot write " + path + ": " + one_line(out->geterror()), ErrorKind::File);
  if (!options.xmp.empty() && (ext == ".jpg" || ext == ".jpeg" || ext == ".png")) {
    const XmpInsertion x =
        xmp_insertion(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), options.xmp);
    bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(x.offset), x.bytes.begin(), x.bytes.end());
  }
  return bytes;
}

}  // namespace

namespace {

// An input opened for reading (samples as stored: no premultiplication): a regular file of one of
// the five formats by its magic bytes, read by that format's reader alone, its channels checked.
struct Opened {
  InputFile file;
  std::unique_ptr<OIIO::ImageInput> in;
};

Opened open_input(const std::string& path) {
  Opened o{probe_input(path), nullptr};
  // Samples exactly as stored: no conversion of straight (PNG, TIFF) alpha to premultiplied.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  o.in = OIIO::ImageInput::create(o.file.format, false, &config);
  OIIO::ImageSpec spec;
  if (!o.in || !o.in->open(path, spec, config)) {
    const std::string why = o.in ? o.in->geterror() : OIIO::geterror();
    throw Error("cannot read " + path + ": " + one_line(why) + " (the file is damaged or not an image)",
                ErrorKind::File);
  }
  const OIIO::ImageSpec& s = o.in->spec();
  if (s.nchannels < 1 || s.nchannels > 4)
    throw Error("input " + path + " has " + std::to_string(s.nchannels) + " channels (expected 1 to 4)",
                ErrorKind::File);
  if (s.width < 1 || s.height < 1)
    throw Error("input " + path + " declares " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                    " pixels (a damaged header)",
                ErrorKind::File);
  return o;
}

// Checks, before any pixel is decoded, that the file can hold what its header declares and that
// `window` pixels of it fit the memory budget.
void check_input(const std::string& path, const Opened& o, Size window, int64_t memory_limit, uint64_t other_bytes = 0) {
  const OIIO::ImageSpec& s = o.in->spec();
  const int bits = s.get_int_attribute("oiio:BitsPerSample", static_cast<int>(s.format.size() * 8));
  check_plausible(path, o.file, {s.width, s.height}, s.nchannels, bits, s.get_string_attribute("compression"),
                  window, add_bytes(image_bytes(window, s.nchannels, bytes_of(from_oiio(s.format))), other_bytes),
                  memory_limit);
}

// The buffer for `size` pixels of the file's layout.
Image allocate_for(const std::string& path, Size size, const OIIO::ImageSpec& spec, PixelType type) {
  const int alpha = spec.alpha_channel >= 0 && spec.alpha_channel < spec.nchannels ? spec.alpha_channel : -1;
  try {
    return Image(size, spec.nchannels, type, alpha);
  } catch (const std::bad_alloc&) {
    throw Error("cannot read " + path + ": " + size_text(size) + " pixels (" +
                    bytes_text(image_bytes(size, spec.nchannels, bytes_of(type))) + ") cannot be allocated",
                ErrorKind::Memory);
  }
}

[[noreturn]] void damaged(const std::string& path, OIIO::ImageInput& in) {
  throw Error("cannot read " + path + ": " + one_line(in.geterror()) + " (the file is damaged or truncated)",
              ErrorKind::File);
}

}  // namespace

void write_bytes(std::string_view bytes, const std::string& path, bool overwrite) {
  OutputSet set(overwrite);
  set.add(path, bytes);
  set.commit();
}

void write_text(const std::string& text, const std::string& path, bool overwrite) { write_bytes(text, path, overwrite); }

ImageInfo read_image_info(const std::string& path) {
  const Opened o = open_input(path);
  const OIIO::ImageSpec& s = o.in->spec();
  return {{s.width, s.height}, s.nchannels, from_oiio(s.format)};
}

Size read_image_size(const std::string& path) { return read_image_info(path).size; }

namespace {
// The whole image of an opened input, checked first.
Image decode_whole(const std::string& path, Opened& o, int64_t memory_limit, uint64_t other_bytes) {
  const OIIO::ImageSpec& spec = o.in->spec();
  check_input(path, o, {spec.width, spec.height}, memory_limit, other_bytes);
  const PixelType type = from_oiio(spec.format);
  Image image = allocate_for(path, {spec.width, spec.height}, spec, type);
  const bool ok = o.in->read_image(0, 0, 0, spec.nchannels, oiio_type(type), image.data());
  if (!ok || o.in->has_error()) damaged(path, *o.in);
  return image;
}
}  // namespace

Image read_image(const std::string& path, int64_t memory_limit) {
  Opened o = open_input(path);
  return decode_whole(path, o, memory_limit, 0);
}

Metadata read_metadata(const std::string& path) {
  const Opened o = open_input(path);
  Metadata out;
  for (const OIIO::ParamValue& p : o.in->spec().extra_attribs) {
    const std::string name = p.name().string();
    if (name.rfind("oiio:", 0) == 0) continue;
    const OIIO::TypeDesc t = p.type();
    const int n = p.nvalues() * static_cast<int>(t.aggregate) * std::max(1, t.arraylen);
    if (t.basetype == OIIO::TypeDesc::STRING && n == 1) {
      out.push_back({name, p.get_string()});
    } else if (t.basetype == OIIO::TypeDesc::UINT8 && n > 1) {
      const auto* b = static_cast<const uint8_t*>(p.data());
      out.push_back({name, std::vector<uint8_t>(b, b + n)});
    } else if (t.basetype == OIIO::TypeDesc::STRING || t.basetype == OIIO::TypeDesc::PTR) {
      continue;  // string arrays and pointers: no portable value
    } else if (t == OIIO::TypeRational) {
      out.push_back({name, static_cast<double>(p.get_float())});  // numerator / denominator
    } else if (n == 1 && t.is_floating_point()) {
      out.push_back({name, static_cast<double>(p.get_float())});
    } else if (n == 1) {
      out.push_back({name, static_cast<int64_t>(p.get_int())});
    } else if (t.vecsemantics == OIIO::TypeDesc::RATIONAL && t.aggregate == OIIO::TypeDesc::VEC2 &&
               (t.basetype == OIIO::TypeDesc::INT32 || t.basetype == OIIO::TypeDesc::UINT32)) {
      // Arrays of rationals (GPS coordinates): pairs of 32-bit numerators and denominators.
      std::vector<double> v(static_cast<size_t>(n / 2));
      for (int i = 0; i < n / 2; ++i) {
        const double num = t.basetype == OIIO::TypeDesc::INT32 ? static_cast<const int32_t*>(p.data())[2 * i]
                                                                : static_cast<const uint32_t*>(p.data())[2 * i];
        const double den = t.basetype == OIIO::TypeDesc::INT32 ? static_cast<const int32_t*>(p.data())[2 * i + 1]
                                                                : static_cast<const uint32_t*>(p.data())[2 * i + 1];
        v[static_cast<size_t>(i)] = den != 0 ? num / den : 0.0;
      }
      out.push_back({name, std::move(v)});
    } else {
      std::vector<double> v(static_cast<size_t>(n));
      for (int i = 0; i < n; ++i) v[static_cast<size_t>(i)] = p.get_float_indexed(i);  // (get_float's argument is a default)
      out.push_back({name, std::move(v)});
    }
  }
  return out;
}

Image read_image_region(const std::string& path, int64_t x0, int64_t y0, int64_t x1, int64_t y1,
                        int64_t memory_limit, uint64_t other_bytes) {
  Opened o = open_input(path);
  auto& in = o.in;
  const OIIO::ImageSpec& spec = in->spec();
  const int64_t w = spec.width, h = spec.height;
  x0 = std::clamp<int64_t>(x0, 0, w), x1 = std::clamp<int64_t>(x1, x0, w);
  y0 = std::clamp<int64_t>(y0, 0, h), y1 = std::clamp<int64_t>(y1, y0, h);
  if (x1 == x0 || y1 == y0) x0 = 0, x1 = 1, y0 = 0, y1 = 1;  // nothing needed: one pixel
  const bool whole = x0 == 0 && y0 == 0 && x1 == w && y1 == h;
  // (One open only: a progressive JPEG's open reads all its scans.)
  if (whole || spec.x != 0 || spec.y != 0 || spec.depth > 1) return decode_whole(path, o, memory_limit, other_bytes);
  const PixelType type = from_oiio(spec.format);
  Image win;
  bool ok;
  // Each branch checks what it decodes before allocating: tile-aligned bounds; whole rows (a JPEG
  // decodes the rows above the region too).
  if (spec.tile_width > 0) {
    // Tile-aligned bounds (or the frame's edge), as read_tiles requires.
    const int64_t tw = spec.tile_width, th = spec.tile_height;
    const int64_t tx0 = x0 / tw * tw, ty0 = y0 / th * th;
    const int64_t tx1 = std::min(w, (x1 + tw - 1) / tw * tw), ty1 = std::min(h, (y1 + th - 1) / th * th);
    check_input(path, o, {tx1 - tx0, ty1 - ty0}, memory_limit, other_bytes);
    win = allocate_for(path, {tx1 - tx0, ty1 - ty0}, spec, type);
    ok = in->read_tiles(0, 0, static_cast<int>(tx0), static_cast<int>(tx1), static_cast<int>(ty0),
                        static_cast<int>(ty1), 0, 1, 0, spec.nchannels, oiio_type(type), win.data(),
                        static_cast<OIIO::stride_t>(win.pixel_bytes()), static_cast<OIIO::stride_t>(win.row_bytes()));
    win.set_window(tx0, ty0, {w, h});
  } else {
    check_input(path, o, {w, o.file.format == "jpeg" ? y1 : y1 - y0}, memory_limit, other_bytes);
    win = allocate_for(path, {w, y1 - y0}, spec, type);
    ok = in->read_scanlines(0, 0, static_cast<int>(y0), static_cast<int>(y1), 0, 0, spec.nchannels,
                            oiio_type(type), win.data(), static_cast<OIIO::stride_t>(win.pixel_bytes()),
                            static_cast<OIIO::stride_t>(win.row_bytes()));
    win.set_window(0, y0, {w, h});
  }
  if (!ok || in->has_error()) damaged(path, *in);
  return win;
}

void write_image(const Image& image, const std::string& path, const WriteOptions& options) {
  check_output_path(path, options.overwrite);
  const std::vector<unsigned char> bytes = encode(image, path, options);
  write_bytes({reinterpret_cast<const char*>(bytes.data()), bytes.size()}, path, options.overwrite);
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
         path.find("{index}") != std::string_view::npos;
}

std::string face_path(std::string_view pattern, int face) {
  std::string s(pattern);
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{face}", kFaceNames[face]},
                                   {"{index}", std::to_string(face)}}) {
    for (size_t at; (at = s.find(key)) != std::string::npos;) s.replace(at, key.size(), value);
  }
  return s;
}

Image read_cube_faces(const std::string& pattern, int64_t memory_limit) {
  Image strip;
  for (int f = 0; f < 6; ++f) {
    const std::string path = face_path(pattern, f);
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
                  name_of(face.type()) + ", but " + face_path(pattern, 0) + " is " +
                  std::to_string(strip.height()) + "x" + std::to_string(strip.height()) + " " +
                  std::to_string(strip.channels()) + "ch " + name_of(strip.type()) +
                  " (all six faces must match)");
    }
    for (int64_t y = 0; y < face.height(); ++y)
      std::memcpy(strip.pixel(f * face.width(), y), face.row(y), face.row_bytes());
  }
  return strip;
}

void write_cube_faces(const Image& strip, const std::string& pattern, const WriteOptions& options) {
  if (strip.width() != 6 * strip.height())
    throw Error("cube faces: a " + size_text(strip.size()) + " image (expected the 6x1 strip of six square faces, " +
                "6N x N pixels)");
  const int64_t f = strip.height();
  for (int i = 0; i < 6; ++i) check_output_path(face_path(pattern, i), options.overwrite);
  OutputSet set(options.overwrite);
  for (int i = 0; i < 6; ++i) {
    Image face({f, f}, strip.channels(), strip.type(), strip.alpha_channel(), Image::Unfilled{});
    for (int64_t y = 0; y < f; ++y) std::memcpy(face.row(y), strip.pixel(i * f, y), face.row_bytes());
    const std::string path = face_path(pattern, i);
    const std::vector<unsigned char> bytes = encode(face, path, options);
    set.add(path, {reinterpret_cast<const char*>(bytes.data()), bytes.size()});
  }
  set.commit();
}

}  // namespace panoproj
