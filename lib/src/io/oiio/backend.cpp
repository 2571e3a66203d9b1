// The OpenImageIO plugin (libpanoproj_oiio.so, oiio_plugin.hpp): TIFF, OpenEXR and Radiance HDR
// reading and writing, metadata by OpenImageIO's names, EXIF blocks, text for plots. The only
// code that includes OpenImageIO.
#include <Imath/half.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

// From OpenImageIO/tiffutils.h, which includes libtiff's tiff.h (no libtiff-dev needed here).
OIIO_NAMESPACE_BEGIN
OIIO_API bool decode_exif(string_view exif, ImageSpec& spec);
OIIO_API void encode_exif(const ImageSpec& spec, std::vector<char>& blob);
OIIO_API bool decode_xmp(string_view xml, ImageSpec& spec);
OIIO_NAMESPACE_END

#include <algorithm>
#include <climits>

#include "panoproj/error.hpp"
#include "io/oiio_plugin.hpp"

namespace panoproj {
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

// An input read by OpenImageIO (samples as stored: no premultiplication), by its format's reader
// alone (InputFile::format, from the magic bytes).
class OiioDecoder final : public Decoder {
 public:
  OiioDecoder(const std::string& path, const InputFile& file) : path_(path) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // straight (PNG, TIFF) alpha kept straight
    in_ = OIIO::ImageInput::create(file.format, false, &config);
    OIIO::ImageSpec spec;
    if (!in_ || !in_->open(path, spec, config)) {
      const std::string why = in_ ? in_->geterror() : OIIO::geterror();
      throw Error("cannot read " + path + ": " + one_line(why) + " (the file is damaged or not an image)",
                  ErrorKind::File);
    }
    const OIIO::ImageSpec& s = in_->spec();
    if (s.nchannels < 1 || s.nchannels > 4)
      throw Error("input " + path + " has " + std::to_string(s.nchannels) + " channels (expected 1 to 4)",
                  ErrorKind::File);
    if (s.width < 1 || s.height < 1)
      throw Error("input " + path + " declares " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                      " pixels (a damaged header)",
                  ErrorKind::File);
    header_.size = {s.width, s.height};
    header_.channels = s.nchannels;
    header_.type = from_oiio(s.format);
    header_.alpha_channel = s.alpha_channel >= 0 && s.alpha_channel < s.nchannels ? s.alpha_channel : -1;
    header_.sample_bits = s.get_int_attribute("oiio:BitsPerSample", static_cast<int>(s.format.size() * 8));
    header_.compression = s.get_string_attribute("compression");
    banded_ = file.format == "hdr" && s.tile_width == 0 && s.x == 0 && s.y == 0 && s.depth <= 1 &&
              header_.type == PixelType::F32;
  }

  // Radiance HDR (run-length rows: none read without those above it) decodes at 1/2, 1/4 and 1/8
  // too: each pixel the mean of its scale x scale block (fewer at the frame's right and bottom
  // edges), rows read in bands of `scale`, so a small view of a large file never holds it whole.
  Size scaled_size(int scale) const override {
    if (scale == 1) return header_.size;
    if (!banded_ || (scale != 2 && scale != 4 && scale != 8)) return {};
    return {(header_.size.width + scale - 1) / scale, (header_.size.height + scale - 1) / scale};
  }

  // Tiled files: the tiles `need` touches; scanline files: whole rows (TIFF and EXR strips read
  // directly); a frame with an offset or depth: all of it.
  PixelRect window(PixelRect need, int scale) const override {
    if (scale > 1) return {0, need.y0, scaled_size(scale).width, need.y1};
    const OIIO::ImageSpec& s = in_->spec();
    const int64_t w = s.width, h = s.height;
    if (s.x != 0 || s.y != 0 || s.depth > 1) return {0, 0, w, h};
    if (s.tile_width > 0) {
      const int64_t tw = s.tile_width, th = s.tile_height;
      return {need.x0 / tw * tw, need.y0 / th * th, std::min(w, (need.x1 + tw - 1) / tw * tw),
              std::min(h, (need.y1 + th - 1) / th * th)};
    }
    return {0, need.y0, w, need.y1};
  }

  void read_into(PixelRect r, int scale, Image& win, const RowsArrived& arrived) override {
    if (scale > 1) return read_banded(r, scale, win, arrived);
    const OIIO::ImageSpec& s = in_->spec();
    const auto px = static_cast<OIIO::stride_t>(win.pixel_bytes()), row = static_cast<OIIO::stride_t>(win.row_bytes());
    bool ok;
    if (r == PixelRect{0, 0, s.width, s.height}) {
      ok = in_->read_image(0, 0, 0, s.nchannels, oiio_type(header_.type), win.data());
    } else if (s.tile_width > 0) {
      ok = in_->read_tiles(0, 0, static_cast<int>(r.x0), static_cast<int>(r.x1), static_cast<int>(r.y0),
                           static_cast<int>(r.y1), 0, 1, 0, s.nchannels, oiio_type(header_.type), win.data(), px,
                           row);
    } else {
      ok = in_->read_scanlines(0, 0, static_cast<int>(r.y0), static_cast<int>(r.y1), 0, 0, s.nchannels,
                               oiio_type(header_.type), win.data(), px, row);
    }
    if (!ok || in_->has_error()) throw_damaged(path_, in_->geterror());
    if (arrived) arrived(r.y1 - r.y0);
  }

  const OIIO::ImageSpec& spec() const { return in_->spec(); }

 private:
  void read_banded(PixelRect r, int scale, Image& win, const RowsArrived& arrived) {
    const int64_t w = header_.size.width, h = header_.size.height, c = header_.channels;
    std::vector<float> band(static_cast<size_t>(scale * w * c));
    for (int64_t oy = r.y0; oy < r.y1; ++oy) {
      const int64_t y0 = oy * scale, y1 = std::min(h, y0 + scale);
      if (!in_->read_scanlines(0, 0, static_cast<int>(y0), static_cast<int>(y1), 0, 0, static_cast<int>(c),
                               OIIO::TypeDesc::FLOAT, band.data()) ||
          in_->has_error())
        throw_damaged(path_, in_->geterror());
      auto* out = reinterpret_cast<float*>(win.row(oy - r.y0));
      for (int64_t ox = 0; ox < r.x1; ++ox) {
        const int64_t x0 = ox * scale, x1 = std::min(w, x0 + scale);
        const double n = static_cast<double>((x1 - x0) * (y1 - y0));
        for (int64_t k = 0; k < c; ++k) {
          double sum = 0;
          for (int64_t y = 0; y < y1 - y0; ++y)
            for (int64_t x = x0; x < x1; ++x) sum += band[static_cast<size_t>((y * w + x) * c + k)];
          out[ox * c + k] = static_cast<float>(sum / n);
        }
      }
      if (arrived) arrived(oy - r.y0 + 1);
    }
  }

  std::string path_;
  std::unique_ptr<OIIO::ImageInput> in_;
  bool banded_ = false;
};

// Element i of an array of basetype `base` as a number; known false for other types.
double stored_value(unsigned char base, const void* data, int i, bool& known) {
  switch (base) {
    case OIIO::TypeDesc::UINT8: return static_cast<const uint8_t*>(data)[i];
    case OIIO::TypeDesc::INT8: return static_cast<const int8_t*>(data)[i];
    case OIIO::TypeDesc::UINT16: return static_cast<const uint16_t*>(data)[i];
    case OIIO::TypeDesc::INT16: return static_cast<const int16_t*>(data)[i];
    case OIIO::TypeDesc::UINT32: return static_cast<const uint32_t*>(data)[i];
    case OIIO::TypeDesc::INT32: return static_cast<const int32_t*>(data)[i];
    case OIIO::TypeDesc::UINT64: return static_cast<double>(static_cast<const uint64_t*>(data)[i]);
    case OIIO::TypeDesc::INT64: return static_cast<double>(static_cast<const int64_t*>(data)[i]);
    case OIIO::TypeDesc::HALF: return static_cast<float>(static_cast<const Imath::half*>(data)[i]);
    case OIIO::TypeDesc::FLOAT: return static_cast<const float*>(data)[i];
    case OIIO::TypeDesc::DOUBLE: return static_cast<const double*>(data)[i];
    default: known = false; return 0;
  }
}

Metadata to_metadata(const OIIO::ImageSpec& spec) {
  Metadata out;
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
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
      // The values as stored, not normalized (get_float_indexed gives 0 past the first element of
      // an array type such as float[2] or GPS:VersionID's int[4]).
      std::vector<double> v(static_cast<size_t>(n));
      bool known = true;
      for (int i = 0; i < n && known; ++i) v[static_cast<size_t>(i)] = stored_value(t.basetype, p.data(), i, known);
      if (known) out.push_back({name, std::move(v)});
    }
  }
  return out;
}

void set_attributes(OIIO::ImageSpec& spec, const Metadata& metadata) {
  for (const Attribute& a : metadata) {
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
}

class Backend final : public OiioBackend {
 public:
  std::unique_ptr<Decoder> open(const std::string& path, const InputFile& file) override {
    return std::make_unique<OiioDecoder>(path, file);
  }

  Metadata metadata(const std::string& path, const InputFile& file) override {
    return to_metadata(OiioDecoder(path, file).spec());
  }

  // Encoded in memory (an IOProxy): no codec touches the disk, so none can fail there or end the
  // process on a write error; OutputSet writes the bytes.
  std::vector<unsigned char> encode(const Image& image, const std::string& path, const WriteOptions& options,
                                    const Metadata& extra) override {
    auto out = OIIO::ImageOutput::create(path);
    if (!out || !out->supports("ioproxy"))
      throw Error("cannot write " + path + ": no image format for its extension (use .jpg .png .ppm .tif .exr .hdr)",
                  ErrorKind::File);
    int nch = image.channels();
    int alpha = image.alpha_channel();
    // Formats without alpha (HDR) get the colour channels only.
    if (alpha >= 0 && !out->supports("alpha") && alpha == nch - 1) --nch, alpha = -1;
    OIIO::ImageSpec spec(static_cast<int>(image.width()), static_cast<int>(image.height()), nch,
                         oiio_type(image.type()));
    spec.alpha_channel = alpha;
    spec.attribute("oiio:UnassociatedAlpha", 1);  // colours are straight, as read
    if (static_cast<int>(options.channel_names.size()) == nch) spec.channelnames = options.channel_names;
    set_attributes(spec, options.metadata);
    set_attributes(spec, extra);
    // Room for a quarter of the samples up front: fewer regrowths, each a copy into fresh pages.
    std::vector<unsigned char> bytes;
    bytes.reserve(std::min<size_t>(image.byte_size() / 4, size_t{256} << 20) + 65536);
    OIIO::Filesystem::IOVecOutput sink(bytes);
    bool ok = out->set_ioproxy(&sink) && out->open(path, spec);
    if (ok) ok = out->write_image(oiio_type(image.type()), image.data(), static_cast<OIIO::stride_t>(image.pixel_bytes()));
    ok = out->close() && ok;
    if (!ok) throw Error("cannot write " + path + ": " + one_line(out->geterror()), ErrorKind::File);
    return bytes;
  }

  Metadata attributes_of(const EmbeddedMetadata& blocks) override {
    OIIO::ImageSpec spec;
    if (!blocks.exif.empty()) OIIO::decode_exif(OIIO::string_view(blocks.exif.data(), blocks.exif.size()), spec);
    if (!blocks.xmp.empty()) OIIO::decode_xmp(OIIO::string_view(blocks.xmp.data(), blocks.xmp.size()), spec);
    if (!blocks.icc.empty())
      spec.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, static_cast<int>(blocks.icc.size())),
                     blocks.icc.data());
    return to_metadata(spec);
  }

  std::string encode_exif(const Metadata& metadata) override {
    OIIO::ImageSpec spec;
    set_attributes(spec, metadata);
    std::vector<char> blob;
    OIIO::encode_exif(spec, blob);
    return {blob.begin(), blob.end()};
  }

  void draw_text(Image& rgb, int x, int y, const std::string& text, int size, const float colour[3]) override {
    OIIO::ImageSpec spec(static_cast<int>(rgb.width()), static_cast<int>(rgb.height()), 3, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf buf(spec, reinterpret_cast<float*>(rgb.data()));  // wraps the pixels
    OIIO::ImageBufAlgo::render_text(buf, x, y, text, size, "DejaVuSans", OIIO::cspan<float>(colour, 3));
  }
};

}  // namespace
}  // namespace panoproj

extern "C" __attribute__((visibility("default"))) int panoproj_oiio_abi() { return panoproj::kOiioPluginAbi; }
extern "C" __attribute__((visibility("default"))) panoproj::OiioBackend* panoproj_oiio_backend() {
  static panoproj::Backend backend;
  return &backend;
}
