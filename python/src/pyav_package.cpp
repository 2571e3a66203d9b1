// PyAV as the video backend (video_plugin.hpp's VideoBackend) where the plugin cannot load: the
// convert job, its checks, plans and reports stay the library's; panoproj/_pyav.py demuxes,
// decodes, encodes and muxes. Each call holds the GIL (the job's threads take it in turn).
// Frames cross as numpy arrays: a decoded plane whose rows are back to back is viewed, not
// copied (the frame held until the planes are done with); others are copied once.
#include "pyav_package.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <unistd.h>

#include <cstring>
#include <mutex>

#include "io/container_spherical.hpp"
#include "io/video_formats.hpp"
#include "package_backend.hpp"
#include "panoproj/error.hpp"

namespace py = pybind11;

namespace panoproj {
namespace {

py::module_ pyav() {
  return py::module_::import("panoproj._pyav");
}

// A Python exception as the library's Error of its class (its one-line message kept); others
// (KeyboardInterrupt) pass on as they are.
[[noreturn]] void rethrow(py::error_already_set& e) {
  const std::string message = one_line(py::str(e.value()).cast<std::string>());
  if (e.matches(PyExc_FileNotFoundError)) throw Error(message, ErrorKind::Missing);
  if (e.matches(PyExc_FileExistsError)) throw Error(message, ErrorKind::Exists);
  if (e.matches(PyExc_OSError)) throw Error(message, ErrorKind::File);
  if (e.matches(PyExc_MemoryError)) throw Error(message, ErrorKind::Memory);
  if (e.matches(PyExc_ValueError) || e.matches(PyExc_TypeError)) throw Error(message);
  throw;
}

template <class F>
auto call(F&& f) {
  py::gil_scoped_acquire gil;
  try {
    return f();
  } catch (py::error_already_set& e) {
    rethrow(e);
  }
}

// Whether a container's spherical boxes are MP4's (libavformat's demuxer name, or panoproj's
// container name): panoproj reads and writes them itself (io/container_spherical.hpp); Matroska's
// it reads.
bool own_boxes(const std::string& container) {
  return container.find("mp4") != std::string::npos || container.find("mov") != std::string::npos;
}

VideoInfo info_of(const py::dict& d) {
  VideoInfo v;
  v.container = d["container"].cast<std::string>();
  v.codec = d["codec"].cast<std::string>();
  v.stream = d["stream"].cast<int>();
  v.size = {d["width"].cast<int64_t>(), d["height"].cast<int64_t>()};
  v.pixels = video_pixels(d["pixels"].cast<py::dict>());
  const auto tb = d["time_base"].cast<std::pair<int, int>>(),
             fr = d["frame_rate"].cast<std::pair<int, int>>();
  v.time_base[0] = tb.first, v.time_base[1] = tb.second;
  v.frame_rate[0] = fr.first, v.frame_rate[1] = fr.second;
  v.duration = d["duration"].cast<double>();
  v.frames = d["frames"].cast<int64_t>();
  for (const auto& o : d["others"].cast<py::list>()) {
    const py::dict s = o.cast<py::dict>();
    v.others.push_back({s["index"].cast<int>(), s["kind"].cast<std::string>(),
                        s["codec"].cast<std::string>(), s["tag"].cast<std::string>()});
  }
  return v;
}

void release_held(void* held) {
  py::gil_scoped_acquire gil;
  delete static_cast<py::object*>(held);
}

class PyAvReader final : public VideoReader {
 public:
  PyAvReader(py::object reader, const std::string& path) : reader_(std::move(reader)) {
    info_ = info_of(reader_.attr("info").cast<py::dict>());
    const std::string what = "cannot read " + path;
    if (own_boxes(info_.container)) {
      const std::string moov = read_moov(path);
      if (!moov.empty()) info_.spherical = spherical_of_moov(moov, info_.stream, what);
    } else if (info_.container.find("matroska") != std::string::npos) {
      info_.spherical = read_matroska_spherical(path, info_.stream, what);
    }
  }
  ~PyAvReader() override {
    py::gil_scoped_acquire gil;
    reader_ = py::object();
  }

  const VideoInfo& info() const override { return info_; }
  int64_t concealed() const override {
    return call([&] { return reader_.attr("concealed").cast<int64_t>(); });
  }

  bool read(VideoFrame& f) override {
    return call([&] {
      const py::object got = reader_.attr("read")();
      if (got.is_none()) return false;
      const py::tuple t = got.cast<py::tuple>();
      take(t[0].cast<py::list>(), f);
      f.pts = t[1].cast<int64_t>();
      f.owner = std::shared_ptr<void>(new py::object(got), release_held);
      return true;
    });
  }

  const py::object& object() const { return reader_; }

 private:
  // The arrays as planes: views of those whose rows are back to back, else copies.
  void take(const py::list& planes, VideoFrame& f) const {
    const VideoPixels& px = info_.pixels;
    const PixelType type = px.bits > 8 ? PixelType::U16 : PixelType::U8;
    const int channels = px.packed ? (px.alpha ? 4 : 3) : 1;
    if (static_cast<int>(planes.size()) != px.planes)
      throw InternalError("PyAV reader: " + std::to_string(planes.size()) + " planes");
    for (int p = 0; p < px.planes; ++p) {
      const py::array a = planes[static_cast<size_t>(p)].cast<py::array>();
      const Size s = px.plane_size(info_.size, p);
      if (a.ndim() != (channels > 1 ? 3 : 2) || a.shape(0) != s.height || a.shape(1) != s.width ||
          a.itemsize() != static_cast<py::ssize_t>(bytes_of(type)) ||
          a.strides(a.ndim() - 1) != a.itemsize() ||
          (channels > 1 && (a.shape(2) != channels || a.strides(1) != channels * a.itemsize())))
        throw InternalError("PyAV reader: plane " + std::to_string(p) +
                            " has another shape or type");
      auto* data = static_cast<unsigned char*>(const_cast<void*>(a.data()));
      Image& im = f.planes[static_cast<size_t>(p)];
      const int alpha = channels == 4 ? 3 : -1;
      if (a.strides(0) == static_cast<py::ssize_t>(s.width * channels * bytes_of(type))) {
        im = Image::view(data, s, channels, type, alpha);
        continue;
      }
      if (im.is_view() || im.size() != s || im.type() != type || im.channels() != channels)
        im = Image(s, channels, type, alpha, Image::Unfilled{});
      for (int64_t y = 0; y < s.height; ++y)
        std::memcpy(im.row(y), data + y * a.strides(0), im.row_bytes());
    }
  }

  py::object reader_;
  VideoInfo info_;
};

class PyAvWriter final : public VideoWriter {
 public:
  // spherical: the boxes written into the finished MP4 at fd (none: nothing).
  PyAvWriter(py::object writer, int fd, std::string path, const SphericalVideo& spherical)
      : writer_(std::move(writer)), fd_(fd), path_(std::move(path)), spherical_(spherical) {
    notes_ = writer_.attr("notes").cast<std::vector<std::string>>();
  }
  ~PyAvWriter() override {
    py::gil_scoped_acquire gil;
    writer_ = py::object();
  }

  void write(const VideoFrame& f) override {
    call([&] {
      py::list planes;
      for (const Image& im : f.planes) {
        if (im.width() == 0) break;
        std::vector<py::ssize_t> shape{im.height(), im.width()};
        const auto item = static_cast<py::ssize_t>(bytes_of(im.type()));
        std::vector<py::ssize_t> strides{static_cast<py::ssize_t>(im.row_bytes()),
                                         im.channels() * item};
        if (im.channels() > 1) shape.push_back(im.channels()), strides.push_back(item);
        // (a view for the call: the writer copies it into the encoder's frame)
        planes.append(
            py::array(im.type() == PixelType::U8 ? py::dtype("uint8") : py::dtype("uint16"), shape,
                      strides, im.data(), py::none()));
      }
      writer_.attr("write")(planes, f.pts);
    });
  }
  void finish() override {
    call([&] { writer_.attr("finish")(); });
    if (spherical_.any()) write_mp4_spherical(fd_, path_, spherical_);
  }
  const std::vector<std::string>& notes() const override { return notes_; }
  SphericalVideo spherical() const override { return spherical_; }

 private:
  py::object writer_;
  int fd_;
  std::string path_;
  SphericalVideo spherical_;
  std::vector<std::string> notes_;
};

class PyAvBackend final : public VideoBackend {
 public:
  std::unique_ptr<VideoReader> open(const std::string& path, int stream, bool copy,
                                    const VideoRange& range, bool rgb) override {
    return call([&] {
      return std::make_unique<PyAvReader>(
          pyav().attr("open")(path, stream, copy, range.start, range.end, rgb), path);
    });
  }
  std::unique_ptr<VideoReader> open_pair(const std::string& path, bool, const VideoRange&,
                                         bool) override {
    throw Error("cannot read " + path +
                " as a GoPro MAX's two strips through PyAV (not yet: the command, or "
                "this module with FFmpeg's libraries installed, reads them)");
  }
  std::string check_output(const std::string& path, const std::string& codec) override {
    return call([&] { return pyav().attr("check_output")(path, codec).cast<std::string>(); });
  }
  std::unique_ptr<VideoWriter> create(int fd, const std::string& path, const VideoSettings& s,
                                      VideoReader* copy_from) override {
    const auto* from = dynamic_cast<const PyAvReader*>(copy_from);
    const VideoContainer* container = video_container_of(path);
    const bool own = s.spherical.any() && container && own_boxes(container->name);
    return call([&] {
      const py::dict settings(
          py::arg("codec") = s.codec, py::arg("width") = s.size.width,
          py::arg("height") = s.size.height, py::arg("pixels") = video_pixels_dict(s.pixels),
          py::arg("time_base") = std::pair{s.time_base[0], s.time_base[1]},
          py::arg("frame_rate") = std::pair{s.frame_rate[0], s.frame_rate[1]},
          py::arg("crf") = s.crf, py::arg("bitrate") = s.bitrate, py::arg("preset") = s.preset,
          py::arg("gop") = s.gop, py::arg("threads") = s.threads,
          py::arg("spherical") = s.spherical.any() && !own);
      return std::make_unique<PyAvWriter>(
          pyav().attr("create")(fd, path, settings, from ? from->object() : py::none()), fd, path,
          own ? s.spherical : SphericalVideo{});
    });
  }
  std::string version() override {
    return call([&] { return pyav().attr("version")().cast<std::string>(); });
  }
};

VideoBackend* pyav_backend(std::string& why_not) {
  return package_backend<PyAvBackend>("PyAV", [] { pyav().attr("require")(); }, why_not);
}

}  // namespace

py::dict video_pixels_dict(const VideoPixels& v) {
  return py::dict(py::arg("pixel_format") = v.pixel_format, py::arg("planes") = v.planes,
                  py::arg("rgb") = v.rgb, py::arg("alpha") = v.alpha, py::arg("packed") = v.packed,
                  py::arg("bits") = v.bits, py::arg("log2_chroma_w") = v.log2_chroma_w,
                  py::arg("log2_chroma_h") = v.log2_chroma_h,
                  py::arg("siting") = static_cast<int>(v.siting),
                  py::arg("siting_said") = v.siting_said, py::arg("full_range") = v.full_range,
                  py::arg("matrix") = v.matrix, py::arg("primaries") = v.primaries,
                  py::arg("transfer") = v.transfer);
}

VideoPixels video_pixels(const py::dict& d) {
  VideoPixels v;
  v.pixel_format = d["pixel_format"].cast<std::string>();
  v.planes = d["planes"].cast<int>();
  v.rgb = d["rgb"].cast<bool>();
  v.alpha = d["alpha"].cast<bool>();
  v.packed = d["packed"].cast<bool>();
  v.bits = d["bits"].cast<int>();
  v.log2_chroma_w = d["log2_chroma_w"].cast<int>(),
  v.log2_chroma_h = d["log2_chroma_h"].cast<int>();
  v.siting = static_cast<ChromaSiting>(std::clamp(d["siting"].cast<int>(), 0, 6));
  v.siting_said = d["siting_said"].cast<bool>();
  v.full_range = d["full_range"].cast<bool>();
  v.matrix = d["matrix"].cast<int>(), v.primaries = d["primaries"].cast<int>(),
  v.transfer = d["transfer"].cast<int>();
  if (v.planes < 1 || v.planes > 4 || v.bits < 8 || v.bits > 16 || v.log2_chroma_w < 0 ||
      v.log2_chroma_w > 2 || v.log2_chroma_h < 0 || v.log2_chroma_h > 2)
    throw Error("pixels of " + v.pixel_format +
                ": not planar samples of 8 to 16 bits in 1 to 4 planes");
  return v;
}

void use_pyav_package() {
  set_video_fallback(&pyav_backend, "PyAV (pip install 'panoproj[av]')");
}

}  // namespace panoproj
