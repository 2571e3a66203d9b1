// OpenImageIO through its Python package (`pip install openimageio`, 3.x: a Python API, no C++
// headers), the module's second backend where the plugin is missing (a wheel without the system's
// OpenImageIO): the same OiioBackend as the plugin, so reads keep their checks (memory budget,
// channels) and writes stay atomic (the bytes go through OutputSet). Each call holds the GIL.
#include "oiio_package.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>

#include "attribute_values.hpp"
#include "io/oiio_plugin.hpp"
#include "package_backend.hpp"
#include "panoproj/error.hpp"

namespace py = pybind11;

namespace panoproj {
namespace {

const char* type_name(PixelType t) {
  switch (t) {
    case PixelType::U8: return "uint8";
    case PixelType::U16: return "uint16";
    case PixelType::F16: return "half";
    case PixelType::F32: return "float";
  }
  return "float";
}

// The package's message of its last error (ImageInput, ImageOutput or the global one), one line.
std::string error_of(const py::object& o) {
  const std::string e = !o.is_none() ? o.attr("geterror")().cast<std::string>() : "";
  return one_line(e.empty() ? py::module_::import("OpenImageIO").attr("geterror")().cast<std::string>() : e);
}

Metadata metadata_of(const py::object& spec) {
  Metadata out;
  for (const auto& p : spec.attr("extra_attribs")) {
    const std::string name = p.attr("name").cast<std::string>();
    if (name.rfind("oiio:", 0) == 0) continue;
    if (auto v = attribute_value(p.attr("value"))) out.push_back({name, std::move(*v)});  // (string arrays: none, as the plugin)
  }
  return out;
}

void set_attributes(py::object& spec, const Metadata& metadata) {
  const py::module_ oiio = py::module_::import("OpenImageIO");
  for (const Attribute& a : metadata) {
    std::visit(
        [&](const auto& v) {
          using V = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<V, std::vector<uint8_t>>) {
            spec.attr("attribute")(a.name, oiio.attr("TypeDesc")("uint8[" + std::to_string(v.size()) + "]"),
                                   py::array_t<uint8_t>(static_cast<py::ssize_t>(v.size()), v.data()));
          } else if constexpr (std::is_same_v<V, std::vector<double>>) {
            spec.attr("attribute")(a.name, oiio.attr("TypeDesc")("float[" + std::to_string(v.size()) + "]"),
                                   py::tuple(py::cast(v)));
          } else if constexpr (std::is_same_v<V, int64_t>) {
            spec.attr("attribute")(a.name, static_cast<int>(std::clamp<int64_t>(v, INT32_MIN, INT32_MAX)));
          } else {
            spec.attr("attribute")(a.name, v);
          }
        },
        a.value);
  }
}

// An input opened by the package: its header at once, the whole frame on read.
class PackageDecoder final : public Decoder {
 public:
  PackageDecoder(const std::string& path, const InputFile& file) : path_(path) {
    py::gil_scoped_acquire gil;
    const py::module_ oiio = py::module_::import("OpenImageIO");
    py::object config = oiio.attr("ImageSpec")();
    config.attr("attribute")("oiio:UnassociatedAlpha", 1);  // straight alpha kept straight
    in_ = oiio.attr("ImageInput").attr("open")(path, config);
    if (in_.is_none())
      throw Error("cannot read " + path + ": " + error_of(py::none()) + " (the file is damaged or not an image)",
                  ErrorKind::File);
    // The reader its magic bytes chose (InputFile::format), not one guessed from the name.
    if (in_.attr("format_name")().cast<std::string>() != file.format)
      throw Error("cannot read " + path + ": read as " + in_.attr("format_name")().cast<std::string>() + ", but it is " +
                      file.format + " (the file is damaged)",
                  ErrorKind::File);
    const py::object s = in_.attr("spec")();
    const int w = s.attr("width").cast<int>(), h = s.attr("height").cast<int>(), c = s.attr("nchannels").cast<int>();
    if (c < 1 || c > 4)
      throw Error("input " + path + " has " + std::to_string(c) + " channels (expected 1 to 4)", ErrorKind::File);
    if (w < 1 || h < 1)
      throw Error("input " + path + " declares " + std::to_string(w) + "x" + std::to_string(h) +
                      " pixels (a damaged header)",
                  ErrorKind::File);
    const std::string format = py::str(s.attr("format")).cast<std::string>();
    header_.size = {w, h};
    header_.channels = c;
    header_.type = format == "uint8" ? PixelType::U8 : format == "uint16" ? PixelType::U16
                 : format == "half"  ? PixelType::F16 : PixelType::F32;
    const int alpha = s.attr("alpha_channel").cast<int>();
    header_.alpha_channel = alpha >= 0 && alpha < c ? alpha : -1;
    header_.sample_bits = s.attr("get_int_attribute")("oiio:BitsPerSample", 8 * s.attr("format").attr("size")().cast<int>()).cast<int>();
    header_.compression = s.attr("get_string_attribute")("compression").cast<std::string>();
  }
  ~PackageDecoder() override {
    py::gil_scoped_acquire gil;
    if (!in_.is_none()) in_.attr("close")();
    in_ = py::object();
  }

  PixelRect window(PixelRect, int) const override { return {0, 0, header_.size.width, header_.size.height}; }

  void read_into(PixelRect r, int, Image& win, const RowsArrived& arrived) override {
    {
      py::gil_scoped_acquire gil;
      const py::object a = in_.attr("read_image")(0, 0, 0, header_.channels, type_name(header_.type));
      if (a.is_none() || in_.attr("has_error").cast<bool>()) throw_damaged(path_, error_of(in_));
      const auto pixels = py::array::ensure(a, py::array::c_style);
      if (!pixels || static_cast<size_t>(pixels.nbytes()) != win.row_bytes() * static_cast<size_t>(win.height()))
        throw_damaged(path_, "the package returned " + std::to_string(pixels ? pixels.nbytes() : 0) + " bytes");
      for (int64_t y = 0; y < win.height(); ++y)
        std::memcpy(win.row(y), static_cast<const unsigned char*>(pixels.data()) + y * win.row_bytes(), win.row_bytes());
    }
    if (arrived) arrived(r.y1 - r.y0);
  }

  const py::object& input() const { return in_; }

 private:
  std::string path_;
  py::object in_;
};

// A private folder for the package's output files: it writes files only (no memory output in its
// Python API), read back into memory and removed at once.
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& extension) {
    const char* tmp = std::getenv("TMPDIR");
    std::string dir = std::string(tmp && *tmp ? tmp : "/tmp") + "/panoproj-XXXXXX";
    if (!mkdtemp(dir.data())) throw Error("cannot make a scratch folder in " + dir + ": " + std::strerror(errno), ErrorKind::File);
    dir_ = dir;
    path_ = dir + "/out" + extension;
  }
  ~ScratchFile() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  const std::string& path() const { return path_; }
  std::vector<unsigned char> bytes() const {
    std::ifstream in(path_, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }

 private:
  std::string dir_, path_;
};

class PackageBackend final : public OiioBackend {
 public:
  std::unique_ptr<Decoder> open(const std::string& path, const InputFile& file) override {
    return std::make_unique<PackageDecoder>(path, file);
  }

  Metadata metadata(const std::string& path, const InputFile& file) override {
    PackageDecoder d(path, file);
    py::gil_scoped_acquire gil;
    return metadata_of(d.input().attr("spec")());
  }

  std::vector<unsigned char> encode(const Image& image, const std::string& path, const WriteOptions& options,
                                    const Metadata& extra) override {
    const ScratchFile scratch(std::filesystem::path(path).extension().string());
    write_file(image, path, scratch.path(), options, extra);
    return scratch.bytes();
  }

  Metadata attributes_of(const EmbeddedMetadata& blocks) override { return built_in_attributes(blocks); }

  // The package has no EXIF encoder of its own in Python: a 1x1 JPEG written with the attributes,
  // whose EXIF block is taken.
  std::string encode_exif(const Metadata& metadata) override {
    const ScratchFile jpeg(".jpg");
    write_file(Image({1, 1}, 1, PixelType::U8), "EXIF attributes", jpeg.path(), {}, metadata);
    return read_embedded_metadata(jpeg.path()).exif;
  }

  void draw_text(Image&, int, int, const std::string&, int, const float*) override {}  // (plots: the command's)

 private:
  // The image as the file `file` (the format its extension names); errors name `path`.
  static void write_file(const Image& image, const std::string& path, const std::string& file,
                         const WriteOptions& options, const Metadata& extra) {
    py::gil_scoped_acquire gil;
    const py::module_ oiio = py::module_::import("OpenImageIO");
    py::object out = oiio.attr("ImageOutput").attr("create")(file);
    if (out.is_none())
      throw Error("cannot write " + path + ": no image format for its extension (use .jpg .png .ppm .tif .exr .hdr)",
                  ErrorKind::File);
    int nch = image.channels(), alpha = image.alpha_channel();
    if (alpha >= 0 && !out.attr("supports")("alpha").cast<int>() && alpha == nch - 1) --nch, alpha = -1;  // HDR
    py::object spec = oiio.attr("ImageSpec")(image.width(), image.height(), nch, type_name(image.type()));
    spec.attr("alpha_channel") = alpha;
    spec.attr("attribute")("oiio:UnassociatedAlpha", 1);
    if (static_cast<int>(options.channel_names.size()) == nch) spec.attr("channelnames") = py::tuple(py::cast(options.channel_names));
    set_attributes(spec, options.metadata);
    set_attributes(spec, extra);
    // The samples as a (H, W, C) view of the image's rows; C may leave out an alpha (HDR).
    const char* dtype = image.type() == PixelType::U8 ? "uint8" : image.type() == PixelType::U16 ? "uint16"
                      : image.type() == PixelType::F16 ? "float16" : "float32";
    const auto item = static_cast<py::ssize_t>(bytes_of(image.type()));
    const py::array pixels(py::dtype(dtype), {image.height(), image.width(), int64_t{nch}},
                           {static_cast<py::ssize_t>(image.row_bytes()), static_cast<py::ssize_t>(image.pixel_bytes()), item},
                           image.data(), py::none());
    bool ok = out.attr("open")(file, spec).cast<bool>();
    if (ok) ok = out.attr("write_image")(pixels).cast<bool>();
    ok = out.attr("close")().cast<bool>() && ok;
    if (!ok) throw Error("cannot write " + path + ": " + error_of(out), ErrorKind::File);
  }
};

OiioBackend* oiio_package_backend(std::string& why_not) {
  return package_backend<PackageBackend>(
      "openimageio package", [] { py::module_::import("OpenImageIO"); }, why_not);
}

}  // namespace

void use_oiio_package() {
  set_oiio_fallback(&oiio_package_backend, "pip install openimageio");
}

}  // namespace panoproj
