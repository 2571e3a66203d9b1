// The compiled core of the Python module (panoproj._core); python/panoproj/__init__.py builds
// the public API on it. numpy arrays in, numpy arrays out:
//   - a C-contiguous input is viewed in place (Image::view), never copied; other layouts are
//     copied once to C order;
//   - outputs are the engine's own buffers, handed to numpy with a capsule that frees them;
//   - every heavy call releases the GIL;
//   - panoproj::Error becomes the class of its kind (ValueError, OSError, FileExistsError,
//     FileNotFoundError, MemoryError), std::bad_alloc a one-line MemoryError, a wrong dtype TypeError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Imath/half.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#ifdef __GLIBC__
#include <malloc.h>  // malloc_trim
#endif

#include "attribute_values.hpp"
#include "jobs/convert/video_planes.hpp"
#include "jobs/stitch/panorama.hpp"
#include "jobs/stitch/stitch.hpp"
#include "oiio_package.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/io.hpp"
#include "panoproj/jobs.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/maps.hpp"
#include "panoproj/options.hpp"
#include "pyav_package.hpp"

namespace py = pybind11;
using namespace panoproj;

namespace {

// (By equality, not identity: a dtype that carries metadata is another object of the same type.)
PixelType pixel_type(const py::dtype& dt) {
  if (dt.equal(py::dtype::of<uint8_t>())) return PixelType::U8;
  if (dt.equal(py::dtype::of<uint16_t>())) return PixelType::U16;
  if (dt.equal(py::dtype("float16"))) return PixelType::F16;
  if (dt.equal(py::dtype::of<float>())) return PixelType::F32;
  throw py::type_error("array dtype: " + py::str(dt).cast<std::string>() +
                       " (expected uint8, uint16, float16 or float32)");
}

py::dtype dtype_of(PixelType t) {
  switch (t) {
    case PixelType::U8: return py::dtype::of<uint8_t>();
    case PixelType::U16: return py::dtype::of<uint16_t>();
    case PixelType::F16: return py::dtype("float16");
    case PixelType::F32: return py::dtype::of<float>();
  }
  return py::dtype::of<uint8_t>();
}

// The GIL released for a long call, which Ctrl-C stops: between units of work the calling thread
// takes the GIL back (at most every 50 ms) to run Python's signal handlers; KeyboardInterrupt (or
// whatever a handler raises) stops the job, which then writes nothing.
class Unlocked {
 public:
  Unlocked() : previous_(set_interrupt_check([last = std::chrono::steady_clock::now()]() mutable {
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(50)) return;
    last = now;
    py::gil_scoped_acquire locked;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  })) {}
  ~Unlocked() { set_interrupt_check(std::move(previous_)); }
  Unlocked(const Unlocked&) = delete;
  Unlocked& operator=(const Unlocked&) = delete;

 private:
  std::function<void()> previous_;
  py::gil_scoped_release released_;
};

// 2 and 4 channels carry alpha last (grey + alpha, RGBA), as the image files do.
int alpha_for(int channels) { return channels == 2 || channels == 4 ? channels - 1 : -1; }

// An array as an Image: a view of its pixels when C-contiguous, else of a C-order copy (kept in
// `keep`), counted against the memory budget before it is made (a broadcast array of stride 0
// would expand whole). HxW or HxWxC, C in 1..4; with 2 or 4 channels the last is alpha when
// `has_alpha`.
Image image_of(const py::array& a, py::object& keep, bool has_alpha = true, int64_t memory_limit = 0) {
  const PixelType t = pixel_type(a.dtype());
  if (a.ndim() != 2 && a.ndim() != 3)
    throw py::value_error("array shape: " + std::to_string(a.ndim()) +
                          " dimensions (expected HxW or HxWxC)");
  const int channels = a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 1;
  if (channels < 1 || channels > 4)
    throw py::value_error("array shape: " + std::to_string(channels) + " channels (expected 1 to 4)");
  if (a.shape(0) < 1 || a.shape(1) < 1)
    throw py::value_error("array shape: " + std::to_string(a.shape(1)) + "x" + std::to_string(a.shape(0)) +
                          " pixels (expected at least 1x1)");
  py::array c = a;
  if (!(a.flags() & py::array::c_style)) {
    const Size size{a.shape(1), a.shape(0)};
    require_memory("a C-order copy of the " + size_text(size) + " array (it is strided or broadcast)",
                   image_bytes(size, channels, bytes_of(t)), memory_limit);
    c = py::array::ensure(a, py::array::c_style);
    if (!c) throw std::bad_alloc();  // numpy's failed allocation (ensure clears its error)
  }
  keep = c;
  auto* data = static_cast<unsigned char*>(const_cast<void*>(c.data()));
  return Image::view(data, {c.shape(1), c.shape(0)}, channels, t, has_alpha ? alpha_for(channels) : -1);
}

// Hands an image's buffer to numpy (no copy): HxWxC, or HxW for one channel when flat.
py::array array_of(Image&& image, bool flat) {
  auto* owner = new Image(std::move(image));
  py::capsule free_it(owner, [](void* p) { delete static_cast<Image*>(p); });
  const auto h = static_cast<py::ssize_t>(owner->height()), w = static_cast<py::ssize_t>(owner->width());
  const auto c = static_cast<py::ssize_t>(owner->channels()), b = static_cast<py::ssize_t>(bytes_of(owner->type()));
  std::vector<py::ssize_t> shape{h, w}, strides{w * c * b, c * b};
  if (!flat || c > 1) shape.push_back(c), strides.push_back(b);
  return py::array(dtype_of(owner->type()), shape, strides, owner->data(), free_it);
}

// An image read by read() without the GIL, as an array.
template <class Read>
py::array read_array(Read&& read) {
  Image im;
  {
    Unlocked unlocked;
    im = read();
  }
  return array_of(std::move(im), true);
}

// Six faces (front, right, back, left, up, down) of one shape and dtype as the 6x1 strip.
Image strip_of(const py::sequence& faces, bool has_alpha, int64_t memory_limit) {
  if (py::len(faces) != 6)
    throw py::value_error("cube faces: " + std::to_string(py::len(faces)) + " arrays (expected 6)");
  std::vector<Image> views;
  std::vector<py::object> keep(6);
  for (size_t f = 0; f < 6; ++f) {
    views.push_back(image_of(faces[f].cast<py::array>(), keep[f], has_alpha, memory_limit));
    const Image& v = views.back();
    if (v.width() != v.height())
      throw py::value_error("cube face " + std::string(kFaceNames[f]) + ": " + std::to_string(v.width()) + "x" +
                            std::to_string(v.height()) + " (expected square faces)");
    if (v.size() != views[0].size() || v.channels() != views[0].channels() || v.type() != views[0].type())
      throw py::value_error("cube face " + std::string(kFaceNames[f]) + ": " + std::to_string(v.width()) + "x" +
                            std::to_string(v.height()) + "x" + std::to_string(v.channels()) + " " +
                            name_of(v.type()) + " differs from the front face's " +
                            std::to_string(views[0].width()) + "x" + std::to_string(views[0].height()) + "x" +
                            std::to_string(views[0].channels()) + " " + name_of(views[0].type()) +
                            " (expected six faces of one size and dtype)");
  }
  const Image& f0 = views[0];
  Image strip({6 * f0.width(), f0.height()}, f0.channels(), f0.type(), f0.alpha_channel(), Image::Unfilled{});
  for (int f = 0; f < 6; ++f)
    for (int64_t y = 0; y < f0.height(); ++y)
      std::memcpy(strip.pixel(f * f0.width(), y), views[static_cast<size_t>(f)].row(y), f0.row_bytes());
  return strip;
}

// The source as an Image: one array, or a list of six cube faces (then the spec must be a cubemap
// laid out as 6x1 or files). panoproj/_arrays.py has made every other form one of these.
Image source_of(const py::object& src, py::object& keep, const ProjectionSpec& spec, bool has_alpha, int64_t memory_limit) {
  if (py::isinstance<py::array>(src)) return image_of(src.cast<py::array>(), keep, has_alpha, memory_limit);
  if (spec.kind() != Kind::Cubemap || (spec.choice("layout") != "6x1" && spec.choice("layout") != "files"))
    throw py::value_error("src: " + spec.str() + " with six face arrays (expected cubemap, layout 6x1 or files)");
  return strip_of(src.cast<py::list>(), has_alpha, memory_limit);
}

// Python's keyword options, by the table's names (panoproj/__init__.py hands over those given,
// already of the row's type: float, int, bool or str), set in the order given.
ConvertOptions options_from(const py::dict& given, unsigned use) {
  ConvertOptions o;
  for (const auto& [key, value] : given) {
    const OptionDef& d = conversion_option(key.cast<std::string>(), use);
    OptionValue v;
    switch (d.type) {
      case OptionType::Angle: v = value.cast<double>(); break;
      case OptionType::Integer: v = value.cast<int64_t>(); break;
      case OptionType::Flag: v = value.cast<bool>(); break;
      case OptionType::Text: v = value.cast<std::string>(); break;
      case OptionType::Path:
      case OptionType::Paths:
        throw InternalError(std::string("conversion option ") + d.name + " is a path");
    }
    d.set(o, v);
  }
  return o;
}

// A job's arguments from Python's (panoproj/_job.py hands over those given, each already of its
// row's type: float, int, bool, str or a list of str).
Arguments job_arguments(const JobDef& job, const py::dict& given) {
  Arguments args(job.rows());
  for (const auto& [key, value] : given) {
    const std::string name = key.cast<std::string>();
    const OptionDef& row = args.row(name);
    try {
      switch (row.type) {
        case OptionType::Angle:
          args.set(name, value.cast<double>());
          break;
        case OptionType::Integer:
          args.set(name, value.cast<int64_t>());
          break;
        case OptionType::Flag:
          args.set(name, value.cast<bool>());
          break;
        case OptionType::Paths:
          args.set(name, value.cast<std::vector<std::string>>());
          break;
        case OptionType::Text:
        case OptionType::Path:
          args.set(name, value.cast<std::string>());
          break;
      }
    } catch (const py::cast_error&) {
      throw py::type_error(name + ": " + py::repr(value).cast<std::string>() +
                           " (expected a value of the row's type)");
    }
  }
  return args;
}

// A folder job's temporary folder as the tasks carry it (picklable): (path, device, inode).
py::tuple staged_handle(const StagedFolder& s) { return py::make_tuple(s.path, s.device, s.inode); }
StagedFolder staged_of(const py::tuple& t) {
  if (t.size() != 3) throw py::type_error("staged folder: expected (path, device, inode)");
  return {t[0].cast<std::string>(), t[1].cast<uint64_t>(), t[2].cast<uint64_t>()};
}

py::object report_value(const ReportValue& v);

// A report as a dict (its order kept); lists as lists, tuples as tuples.
py::dict python_report(const Report& r) {
  py::dict out;
  for (const ReportField& f : r) out[py::str(f.key)] = report_value(f.value);
  return out;
}

py::object report_value(const ReportValue& v) {
  return std::visit(
      [&](const auto& x) -> py::object {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::vector<ReportValue>>) {
          py::list items;
          for (const ReportValue& e : x) items.append(report_value(e));
          return v.tuple ? py::object(py::tuple(items)) : py::object(items);
        } else if constexpr (std::is_same_v<T, Report>) {
          return python_report(x);
        } else {
          return py::cast(x);
        }
      },
      v.value);
}

// A row as Python reads it (panoproj/_options.py, python/generate_api.py).
py::dict row_dict(const OptionDef& d) {
  py::list use;
  for (auto [bit, name] : {std::pair{kUseConvert, "convert"},
                           {kUseMaps, "maps"},
                           {kUseAccuracy, "accuracy"},
                           {kUseTiles, "tiles"},
                           {kUseViews, "views"}})
    if (d.use & bit) use.append(name);
  const char* types[] = {"angle", "integer", "flag", "text", "path", "paths"};
  return py::dict(py::arg("name") = d.name, py::arg("type") = types[static_cast<int>(d.type)],
                  py::arg("use") = use, py::arg("default") = d.default_text,
                  py::arg("help") = d.help, py::arg("choices") = d.choices ? d.choices : "",
                  py::arg("conversion") = d.set != nullptr,
                  py::arg("positional") = (d.traits & kPositional) != 0,
                  py::arg("required") = (d.traits & kRequired) != 0,
                  py::arg("python") = (d.traits & (kCommandOnly | kNeither)) == 0);
}

const JobDef& staged_job(const std::string& name) {
  const JobDef& job = job_named(name);
  if (!job.begin) throw Error("job " + name + " has no parts");
  return job;
}

Size size_pair(std::pair<int64_t, int64_t> s) {
  if (s.first < 1 || s.second < 1)
    throw Error("size: " + std::to_string(s.first) + "x" + std::to_string(s.second) + " (expected at least 1x1)");
  return {s.first, s.second};
}

// A conversion bound to one source size: the map of non-fused tiles and the taps of fused ones
// are kept by the first run for the others, while they fit the file jobs' budget (jobs.hpp), and
// counted against memory_limit (panoproj.Plan wraps it and pickles its parameters). run() may be
// called from several threads.
class PyPlan {
 public:
  PyPlan(const std::string& src, const std::string& dst, std::pair<int64_t, int64_t> source_size,
         const py::dict& options)
      : src_(src),
        options_(options_from(options, kUseConvert)),
        geometry_(
            make_geometry(size_pair(source_size), parse_spec(src), parse_spec(dst), options_)),
        kept_bytes_(image_bytes(geometry_.target_frame(), 1, kept_bytes_per_pixel(geometry_))),
        converter_(Converter(geometry_, options_,
                             kept_bytes_ <= static_cast<uint64_t>(kMapCacheBudget)
                                 ? Keep::MapsAndTaps
                                 : Keep::Nothing)) {
    if (kept_bytes_ > static_cast<uint64_t>(kMapCacheBudget)) kept_bytes_ = 0;
  }
  const ConversionGeometry& geometry() const { return geometry_; }

  py::array run(const py::object& src, std::optional<py::array> out, bool has_alpha) const {
    py::object keep;
    const Image raw = source_of(src, keep, parse_spec(src_), has_alpha, options_.memory_limit);
    Image with_alpha;
    const Image& in = source_for(raw, options_, with_alpha);
    const bool flat = py::isinstance<py::array>(src) && src.cast<py::array>().ndim() == 2 && in.channels() == 1;
    require_job_memory(geometry_, raw.channels(), raw.type(), options_, kept_bytes_,
                       "the maps and taps the plan keeps (up to " +
                           std::to_string(kept_bytes_per_pixel(geometry_)) + " bytes a pixel)");
    if (out) {
      // Written in place: must be C-contiguous, writable, of the output's shape and dtype.
      const Size s = geometry_.target_frame();
      if (!(out->flags() & py::array::c_style) || !out->writeable() || out->dtype().not_equal(dtype_of(in.type())) ||
          out->shape(0) != s.height || out->shape(1) != s.width ||
          (out->ndim() == 3 ? out->shape(2) : 1) != in.channels())
        throw py::value_error("out: expected a writable C-contiguous " + std::string(name_of(in.type())) + " array of " +
                              std::to_string(s.height) + "x" + std::to_string(s.width) + "x" +
                              std::to_string(in.channels()));
      // The engine reads the image while it writes out: they must not overlap.
      const auto* o0 = static_cast<const unsigned char*>(out->data());
      const unsigned char* o1 = o0 + out->nbytes();
      if (o0 < in.data() + in.byte_size() && in.data() < o1)
        throw py::value_error("out: shares memory with the image (expected a separate array: the conversion reads the "
                              "image while it writes out)");
      Image o = Image::view(static_cast<unsigned char*>(out->mutable_data()), s, in.channels(), in.type(),
                            in.alpha_channel());
      {
        Unlocked unlocked;
        converter_.run(in, o);
      }
      return *out;
    }
    Image result;
    {
      Unlocked unlocked;
      result = converter_.run(in);
    }
    return array_of(std::move(result), flat);
  }

 private:
  std::string src_;
  ConvertOptions options_;
  ConversionGeometry geometry_;
  uint64_t kept_bytes_;  // what converter_ keeps, at most
  Converter converter_;
};

// A video's frames converted plane by plane in their own format (jobs/convert/video_planes.hpp):
// panoproj.VideoPlan (panoproj/_video.py) hands over each frame's planes as C-contiguous 2-D
// arrays (uint8, or uint16 for 9 to 16 bits) and arrays to write into. run() may be called from
// several threads.
class PyVideoPlan {
 public:
  PyVideoPlan(const py::dict& pixels, std::pair<int64_t, int64_t> source_size,
              const std::string& src, const std::string& dst, const py::dict& options)
      : px_(video_pixels(pixels)), options_(options_from(options, kUseConvert)) {
    if (px_.packed)
      throw Error("pixels of " + px_.pixel_format + ": packed RGB frames convert as images (Plan)");
    check_video_options(options_, true);
    const Size in = size_pair(source_size);
    const ProjectionSpec from = parse_spec(src), to = parse_spec(dst);
    const ConversionGeometry g = fit_chroma(
        px_, output_subsampling(px_, true), options_,
        [&](const ConvertOptions& o) { return make_geometry(in, from, to, o); },
        [&](const std::string& w) { warnings_.push_back(w); });
    const Size out = g.target_frame();
    require_job_memory(g, px_.planes, px_.bits > 8 ? PixelType::U16 : PixelType::U8, options_,
                       static_cast<uint64_t>(kept_bytes_per_pixel(g)) *
                           static_cast<uint64_t>(out.width * out.height),
                       "the plan's kept maps");
    planes_.emplace(px_, g, options_, "the frames", from.str());
  }

  // Plane p's (width, height) in the source or the output.
  std::pair<int64_t, int64_t> plane_size(int p, bool output) const {
    const Size s = px_.plane_size(output ? planes_->target_size() : planes_->source_size(), p);
    return {s.width, s.height};
  }
  const std::vector<std::string>& warnings() const { return warnings_; }

  void run(const py::list& in, const py::list& out) const {
    if (static_cast<int>(in.size()) != px_.planes || static_cast<int>(out.size()) != px_.planes)
      throw py::value_error("planes: " + std::to_string(in.size()) + " in, " +
                            std::to_string(out.size()) + " out (expected " +
                            std::to_string(px_.planes) + " of " + px_.pixel_format + ")");
    std::array<Image, 4> src, dst;
    for (int p = 0; p < px_.planes; ++p) {
      src[static_cast<size_t>(p)] = plane(in[static_cast<size_t>(p)], p, false);
      dst[static_cast<size_t>(p)] = plane(out[static_cast<size_t>(p)], p, true);
    }
    Unlocked unlocked;
    for (int p = 0; p < px_.planes; ++p)
      planes_->convert_plane(p, src[static_cast<size_t>(p)], dst[static_cast<size_t>(p)]);
  }

 private:
  Image plane(const py::handle& h, int p, bool output) const {
    const py::array a = py::reinterpret_borrow<py::array>(h);
    const auto [w, hgt] = plane_size(p, output);
    const PixelType type = px_.bits > 8 ? PixelType::U16 : PixelType::U8;
    if (pixel_type(a.dtype()) != type || a.ndim() != 2 || a.shape(0) != hgt || a.shape(1) != w ||
        !(a.flags() & py::array::c_style) || (output && !a.writeable()))
      throw py::value_error(
          std::string(output ? "output" : "input") + " plane " + std::to_string(p) + ": " +
          py::repr(a.attr("shape")).cast<std::string>() + " " +
          py::str(a.dtype()).cast<std::string>() + " (expected a C-contiguous" +
          (output ? ", writable " : " ") + std::to_string(hgt) + "x" + std::to_string(w) + " " +
          (type == PixelType::U8 ? "uint8" : "uint16") + " array)");
    return Image::view(static_cast<unsigned char*>(const_cast<void*>(a.data())), {w, hgt}, 1, type);
  }

  VideoPixels px_;
  ConvertOptions options_;
  std::vector<std::string> warnings_;  // fit_chroma's
  std::optional<VideoPlanes> planes_;
};

std::pair<py::array, py::array> split_map(Image&& map) {
  const int64_t w = map.width(), h = map.height();
  Image x({w, h}, 1, PixelType::F32, -1, Image::Unfilled{}), y({w, h}, 1, PixelType::F32, -1, Image::Unfilled{});
  {
    Unlocked unlocked;
    const auto* m = reinterpret_cast<const float*>(map.data());
    auto* px = reinterpret_cast<float*>(x.data());
    auto* py_ = reinterpret_cast<float*>(y.data());
    for (int64_t i = 0; i < w * h; ++i) px[i] = m[2 * i], py_[i] = m[2 * i + 1];
  }
  return {array_of(std::move(x), true), array_of(std::move(y), true)};
}

// Finite x, y arrays of one shape as flat double vectors.
using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The lines a job warns of as Python's UserWarnings, in order.
void warn_all(const std::vector<std::string>& lines) {
  for (const std::string& line : lines)
    if (PyErr_WarnEx(PyExc_UserWarning, line.c_str(), 2) != 0) throw py::error_already_set();
}

// The tables the Python side is made from (options, jobs, the catalogue), and small helpers.
void bind_tables(py::module_& m) {
  m.def("options", [] {
    py::list out;
    for (const OptionDef& d : conversion_options()) out.append(row_dict(d));
    return out;
  });
  m.def("jobs", [] {
    py::list out;
    for (const JobDef* j : jobs()) {
      py::list rows;
      for (const OptionDef& d : j->rows()) rows.append(row_dict(d));
      out.append(
          py::dict(py::arg("name") = j->name, py::arg("summary") = j->summary,
                   py::arg("python") = j->python ? py::object(py::str(j->python)) : py::none(),
                   py::arg("staged") = j->begin != nullptr, py::arg("rows") = rows,
                   py::arg("python_name") = j->python_name ? j->python_name : j->name));
    }
    return out;
  });
  m.def("catalog", [] {
    py::list out;
    for (const ProjectionDef& d : projection_catalog()) {
      py::list params;
      for (const ParamDef& p : d.params)
        params.append(py::dict(py::arg("key") = p.key,
                               py::arg("type") = p.type == ParamType::Number    ? "number"
                                                 : p.type == ParamType::Integer ? "integer"
                                                 : p.type == ParamType::Text    ? "text"
                                                                                : "choice",
                               py::arg("default") = p.default_text, py::arg("lo") = p.lo, py::arg("hi") = p.hi,
                               py::arg("choices") = p.choices ? p.choices : "", py::arg("help") = p.help));
      out.append(py::dict(py::arg("name") = d.name, py::arg("summary") = d.summary, py::arg("params") = params));
    }
    return out;
  });
  m.def("canonical", [](const std::string& text) { return parse_spec(text).str(); },
        "The canonical text of a spec; raises ValueError naming a bad part.");
  m.def("simd_target", &simd_target);
  m.def("parse_memory_limit", [](const std::string& text) { return parse_memory_limit(text); }, py::arg("text"));
  m.def("require_memory", &require_memory, py::arg("what"), py::arg("bytes"), py::arg("limit"),
        "Raises MemoryError when `bytes` would not fit the budget (limit 0: the memory available now).");
}

// Conversions in memory: convert, build_map and Plan.
void bind_conversions(py::module_& m) {
  m.def(
      "convert",
      [](const py::object& src_image, const std::string& src, const std::string& dst, const py::dict& options,
         bool has_alpha) {
        const ProjectionSpec from = parse_spec(src);
        py::object keep;
        const ConvertOptions o = options_from(options, kUseConvert);
        const Image in = source_of(src_image, keep, from, has_alpha, o.memory_limit);
        const ProjectionSpec to = parse_spec(dst);
        const bool flat = py::isinstance<py::array>(src_image) && src_image.cast<py::array>().ndim() == 2 && !o.add_alpha;
        Image out;
        {
          Unlocked unlocked;
          out = convert(in, from, to, o);
        }
        return array_of(std::move(out), flat);
      },
      py::arg("image"), py::arg("src"), py::arg("dst"), py::arg("options"), py::arg("has_alpha") = true);

  m.def(
      "build_map",
      [](const std::string& src, const std::string& dst, std::pair<int64_t, int64_t> source_size,
         const std::string& convention, const py::dict& options) {
        ConvertOptions o = options_from(options, kUseMaps);
        o.interp = Interp::Bilinear;
        const ConversionGeometry geometry =
            make_geometry(size_pair(source_size), parse_spec(src), parse_spec(dst), o);
        require_mono(geometry, "maps");
        require_no_correction(geometry, "maps", "a map holds positions (drop them)");
        // The 2-float map and the two arrays split from it.
        require_memory("map " + size_text(size_of(geometry.target)), image_bytes(size_of(geometry.target), 4, sizeof(float)),
                       o.memory_limit);
        MapConvention c;
        if (convention == "opencv") c = MapConvention::OpenCV;
        else if (convention == "panoproj") c = MapConvention::Panoproj;
        else throw Error("convention: " + convention + " (expected opencv or panoproj)");
        Image map;
        {
          Unlocked unlocked;
          map = build_map(geometry.source, geometry.target, geometry.rotation, c, o.threads);
        }
        return split_map(std::move(map));
      },
      py::arg("src"), py::arg("dst"), py::arg("source_size"), py::arg("convention"), py::arg("options"));

  py::class_<PyPlan>(m, "Plan")
      .def(py::init<const std::string&, const std::string&, std::pair<int64_t, int64_t>, const py::dict&>(),
           py::arg("src"), py::arg("dst"), py::arg("source_size"), py::arg("options"))
      .def("run", &PyPlan::run, py::arg("image"), py::arg("out") = std::nullopt, py::arg("has_alpha") = true)
      .def_property_readonly("size", [](const PyPlan& p) {
        const Size s = size_of(p.geometry().target);
        return std::pair{s.width, s.height};
      });
  m.def(
      "video_pixels",
      [](const py::dict& d, bool mjpeg) {
        VideoPixels v = video_pixels(d);
        apply_coding_defaults(v, mjpeg);
        return video_pixels_dict(v);
      },
      py::arg("pixels"), py::arg("mjpeg"),
      "A stream's pixels (panoproj/_pyav.py) completed by what its coding says.");
  py::class_<PyVideoPlan>(m, "VideoPlan")
      .def(py::init<const py::dict&, std::pair<int64_t, int64_t>, const std::string&,
                    const std::string&, const py::dict&>(),
           py::arg("pixels"), py::arg("source_size"), py::arg("src"), py::arg("dst"),
           py::arg("options"))
      .def("run", &PyVideoPlan::run, py::arg("planes"), py::arg("out"))
      .def("plane_size", &PyVideoPlan::plane_size, py::arg("plane"), py::arg("output"))
      .def_property_readonly("warnings", &PyVideoPlan::warnings);
}

// Jobs (jobs.hpp): whole, or begun, rendered in parts (any process) and finished.
void bind_jobs(py::module_& m) {
  m.def("job_run", [](const std::string& name, const py::dict& given) {
    const JobDef& job = job_named(name);
    const Arguments args = job_arguments(job, given);
    Report r;
    std::vector<std::string> warnings;  // (the job's events come from this thread)
    JobEvents events;
    events.warning = [&](const std::string& line) { warnings.push_back(line); };
    {
      Unlocked unlocked;
      r = job.run(args, events);
    }
    warn_all(warnings);
    return python_report(r);
  });
  m.def("job_begin", [](const std::string& name, const py::dict& given) {
    const JobDef& job = staged_job(name);
    const Arguments args = job_arguments(job, given);
    Staged s;
    {
      Unlocked unlocked;
      s = job.begin(args);
    }
    return py::make_tuple(staged_handle(s.folder), s.parts);
  });
  m.def("job_render", [](const std::string& name, const py::dict& given, const py::tuple& folder,
                         const std::vector<int64_t>& parts) {
    const JobDef& job = staged_job(name);
    const Arguments args = job_arguments(job, given);
    const StagedFolder staged = staged_of(folder);
    Unlocked unlocked;
    const PartCounts c = job.render(args, staged, parts);
    return std::pair{c.written, c.empty};
  });
  m.def("job_finish", [](const std::string& name, const py::dict& given, const py::tuple& folder,
                         std::array<int64_t, 2> counts) {
    const JobDef& job = staged_job(name);
    const Arguments args = job_arguments(job, given);
    const StagedFolder staged = staged_of(folder);
    Report r;
    {
      Unlocked unlocked;
      r = job.finish(args, staged, {counts[0], counts[1]});
    }
    return python_report(r);
  });
  m.def("job_abandon", [](const py::tuple& folder) { abandon_staged(staged_of(folder)); });
}

// Gives the memory a job freed back to the system: glibc keeps what its threads' arenas freed, so
// a Python process would stay hundreds of MB larger after a large stitch (and every process it
// forks starts that large).
void release_freed_memory() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

// Stitch's arrays: a project's layers, its panorama, and a plan over frames in memory.
void bind_stitch(py::module_& m) {
  // A project's layers as arrays (the stitch job's rows; its output row unused): a list of
  // (image, array, (x, y)) and the canvas's (width, height).
  m.def("stitch_layers", [](const py::dict& given) {
    const Arguments args = job_arguments(job_named("stitch"), given);
    std::vector<std::pair<int, RenderedLayer>> layers;
    Size canvas;
    {
      Unlocked unlocked;
      const StitchPlan plan = plan_stitch(args, StitchMade::LayerArrays);
      canvas = plan.canvas;
      for (const StitchLayer& l : plan.layers) {
        check_interrupt();
        RenderedLayer r = render_layer(plan, l);
        if (r.image.size().width > 0) layers.emplace_back(l.index, std::move(r));
      }
      release_freed_memory();
    }
    py::list out;
    for (auto& [index, r] : layers) {
      py::object weights = py::none();
      if (r.weights.size().width > 0) weights = array_of(std::move(r.weights), false);
      out.append(py::make_tuple(index, array_of(std::move(r.image), false),
                                py::make_tuple(r.x, r.y), weights));
    }
    return py::make_tuple(out, py::make_tuple(canvas.width, canvas.height));
  });
  // The blended panorama as an array (the stitch job's rows; its output row unused) and the
  // levels multiband used (0: feather).
  m.def("stitch_panorama", [](const py::dict& given) {
    const Arguments args = job_arguments(job_named("stitch"), given);
    BlendedPanorama b;
    {
      Unlocked unlocked;
      const StitchPlan plan = plan_stitch(args, StitchMade::PanoramaArray);
      b = blend_panorama(plan, panorama_type(plan), {}, {});
      release_freed_memory();
    }
    return py::make_tuple(array_of(std::move(b.image), false), b.levels);
  });  // A plan over in-memory frames (Python's StitchPlan): planned once from the first frames'
  // shapes (one array per input), then each call's frames blended into the panorama.
  struct ArrayStitch {
    StitchPlan plan;
    std::vector<ImageInfo> infos;
  };
  py::class_<ArrayStitch>(m, "ArrayStitch")
      .def(py::init([](const py::dict& given, const std::vector<py::array>& first) {
        const Arguments args = job_arguments(job_named("stitch"), given);
        std::vector<ImageInfo> infos;
        for (const py::array& a : first) {
          py::object keep;
          const Image im = image_of(a, keep);
          infos.push_back({im.size(), im.channels(), im.type(), "array", false});
        }
        Unlocked unlocked;
        return ArrayStitch{plan_stitch(args, StitchMade::PanoramaArray, &infos), infos};
      }))
      .def("__call__",
           [](ArrayStitch& s, const std::vector<py::array>& frames) {
             if (frames.size() != s.infos.size())
               throw py::value_error("frames: " + std::to_string(frames.size()) +
                                     " arrays for a plan of " + std::to_string(s.infos.size()) +
                                     " inputs (one per input, in order)");
             std::vector<py::object> keep(frames.size());
             std::vector<std::shared_ptr<const Image>> images;
             for (size_t k = 0; k < frames.size(); ++k) {
               auto im = std::make_shared<Image>(image_of(frames[k], keep[k]));
               const ImageInfo& i = s.infos[k];
               if (im->size() != i.size || im->channels() != i.channels || im->type() != i.type)
                 throw py::value_error("frames[" + std::to_string(k) +
                                       "]: " + size_text(im->size()) + " x " +
                                       std::to_string(im->channels()) + " " + name_of(im->type()) +
                                       " where the plan's is " + size_text(i.size) + " x " +
                                       std::to_string(i.channels) + " " + name_of(i.type) +
                                       " (a plan's frames keep the first frames' shapes)");
               images.push_back(std::move(im));
             }
             BlendedPanorama b;
             {
               Unlocked unlocked;
               for (StitchLayer& l : s.plan.layers) l.frame = images[static_cast<size_t>(l.input)];
               // (The arrays' views are dropped however the call ends.)
               struct Drop {
                 StitchPlan& p;
                 ~Drop() {
                   for (StitchLayer& l : p.layers) l.frame.reset();
                 }
               } drop{s.plan};
               b = blend_panorama(s.plan, panorama_type(s.plan), {}, {});
               release_freed_memory();
             }
             return array_of(std::move(b.image), false);
           })
      .def_property_readonly("canvas", [](const ArrayStitch& s) {
        return py::make_tuple(s.plan.canvas.width, s.plan.canvas.height);
      });
}

// Image files: read, read_faces, read_metadata, write.
void bind_files(py::module_& m) {
  m.def(
      "read", [](const std::string& path, int64_t limit) { return read_array([&] { return read_image(path, limit); }); },
      py::arg("path"), py::arg("memory_limit") = 0);
  m.def(
      "read_faces",
      [](const std::string& pattern, int64_t limit) {
        return read_array([&] { return read_cube_faces(pattern, limit); });
      },
      py::arg("pattern"), py::arg("memory_limit") = 0);
  m.def(
      "read_metadata",
      [](const std::string& path) {
        Metadata m;
        {
          Unlocked unlocked;  // (the package backend takes it back)
          m = read_metadata(path);
        }
        py::dict out;
        for (const Attribute& a : m) out[py::str(a.name)] = python_value(a);
        return out;
      },
      py::arg("path"));
  m.def(
      "write",
      [](const std::string& path, const py::array& array, const py::dict& options,
         std::optional<std::string> dtype, const py::dict& metadata) {
        py::object keep;
        const Image im = image_of(array, keep);
        // The write options' rows (jobs.hpp), as the command's and the jobs' writes take them.
        Arguments args(write_options());
        for (const auto& [k, v] : options) {
          const std::string name = k.cast<std::string>();
          const OptionType type = write_option(name).type;
          if (type == OptionType::Flag)
            args.set(name, v.cast<bool>());
          else if (type == OptionType::Integer)
            args.set(name, v.cast<int64_t>());
          else
            args.set(name, v.cast<std::string>());
        }
        WriteOptions w = args.write();
        if (dtype) w.type = pixel_type(py::dtype(*dtype));
        for (const auto& [k, v] : metadata) {
          auto value = attribute_value(v);
          if (!value)
            throw py::type_error("metadata " + k.cast<std::string>() + ": " + py::repr(v).cast<std::string>() +
                                 " (expected int, float, str, bytes or a sequence of numbers)");
          w.metadata.push_back({k.cast<std::string>(), std::move(*value)});
        }
        warn_all(write_warnings(path, im, w));  // (the command's named warnings)
        Unlocked unlocked;
        is_face_pattern(path) ? write_cube_faces(im, path, w) : write_image(im, path, w);
      },
      py::arg("path"), py::arg("array"), py::arg("options"), py::arg("dtype"), py::arg("metadata"));
  m.def("write_options", [] {
    py::list out;
    for (const OptionDef& d : write_options()) out.append(row_dict(d));
    return out;
  });
}

// Pixel coordinates and rays, cube faces, and a test hook.
void bind_coordinates(py::module_& m) {
  m.def(
      "to_ray",
      [](const std::string& spec, std::pair<int64_t, int64_t> size, const Doubles& x, const Doubles& y) {
        if (x.ndim() != y.ndim() || !std::equal(x.shape(), x.shape() + x.ndim(), y.shape()))
          throw py::value_error("x and y: shapes differ (expected arrays of one shape)");
        const Projection p = make_projection(parse_spec(spec), size_pair(size));
        std::vector<py::ssize_t> shape(x.shape(), x.shape() + x.ndim());
        const py::ssize_t n = x.size();
        shape.push_back(3);
        py::array_t<double> rays(shape);
        std::vector<py::ssize_t> flat(x.shape(), x.shape() + x.ndim());
        py::array_t<bool> ok(flat);
        const double *px = x.data(), *py_ = y.data();
        double* r = rays.mutable_data();
        bool* o = ok.mutable_data();
        {
          Unlocked unlocked;
          for (py::ssize_t i = 0; i < n; ++i) {
            Ray d;
            o[i] = std::isfinite(px[i]) && std::isfinite(py_[i]) && to_ray(p, px[i], py_[i], d);
            for (int k = 0; k < 3; ++k) r[3 * i + k] = o[i] ? d[k] : NAN;
          }
        }
        return py::make_tuple(rays, ok);
      },
      py::arg("spec"), py::arg("size"), py::arg("x"), py::arg("y"));
  m.def(
      "to_pixel",
      [](const std::string& spec, std::pair<int64_t, int64_t> size, const Doubles& rays) {
        if (rays.ndim() < 1 || rays.shape(rays.ndim() - 1) != 3)
          throw py::value_error("rays: last dimension " +
                                std::to_string(rays.ndim() ? rays.shape(rays.ndim() - 1) : 0) + " (expected 3)");
        const Projection p = make_projection(parse_spec(spec), size_pair(size));
        std::vector<py::ssize_t> shape(rays.shape(), rays.shape() + rays.ndim() - 1);
        const py::ssize_t n = rays.size() / 3;
        py::array_t<double> xs(shape), ys(shape);
        py::array_t<bool> ok(shape);
        const double* r = rays.data();
        double *px = xs.mutable_data(), *py_ = ys.mutable_data();
        bool* o = ok.mutable_data();
        {
          Unlocked unlocked;
          for (py::ssize_t i = 0; i < n; ++i) {
            const Ray d(r[3 * i], r[3 * i + 1], r[3 * i + 2]);
            const double len = d.norm();
            double x = NAN, y = NAN;
            o[i] = std::isfinite(len) && len > 0 && to_pixel(p, d / len, x, y);
            px[i] = o[i] ? x : NAN, py_[i] = o[i] ? y : NAN;
          }
        }
        return py::make_tuple(xs, ys, ok);
      },
      py::arg("spec"), py::arg("size"), py::arg("rays"));
  m.def(
      "face_origins",
      [](const std::string& spec, std::pair<int64_t, int64_t> size) {
        const Projection p = make_projection(parse_spec(spec), size_pair(size));
        const auto* c = std::get_if<Cubemap>(&p);
        if (!c) throw Error("spec: " + spec + " (expected a cubemap)");
        if (!c->uniform()) throw Error("spec: " + spec + " (border=ffmpeg cells are not square faces)");
        py::list out;
        for (int f = 0; f < 6; ++f) {
          int slot = 0;
          while (c->format().order[slot] != f) ++slot;
          out.append(py::make_tuple(c->face_origin(f)[0], c->face_origin(f)[1], c->format().rot[slot]));
        }
        return py::make_tuple(c->face_size(), out);
      },
      py::arg("spec"), py::arg("size"));
  // For tests of the no-copy rule: the address of the pixels the engine would read.
  m.def("_pixels_address", [](const py::array& a) {
    py::object keep;
    return reinterpret_cast<uintptr_t>(image_of(a, keep).data());
  });
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "panoproj's compiled core; use the panoproj package.";
  m.attr("__version__") = PANOPROJ_VERSION;  // CMake's project version, as is the package's
  use_python_option_names();
  use_oiio_package();  // TIFF, EXR, HDR through `pip install openimageio` where the system has no
                       // OpenImageIO
  use_pyav_package();  // video through `pip install av` where the system has no FFmpeg libraries
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      PyObject* type = PyExc_ValueError;
      switch (e.kind()) {
        case ErrorKind::Value:
          type = PyExc_ValueError;
          break;
        case ErrorKind::File:
          type = PyExc_OSError;
          break;
        case ErrorKind::Exists:
          type = PyExc_FileExistsError;
          break;
        case ErrorKind::Missing:
          type = PyExc_FileNotFoundError;
          break;
        case ErrorKind::Memory:
          type = PyExc_MemoryError;
          break;
      }
      PyErr_SetString(type, e.what());
    } catch (const std::bad_alloc&) {
      PyErr_SetString(PyExc_MemoryError,
                      "out of memory (ask for a smaller size, or pass memory_limit= to be refused "
                      "before the work starts)");
    }
  });
  bind_tables(m);
  bind_conversions(m);
  bind_jobs(m);
  bind_stitch(m);
  bind_files(m);
  bind_coordinates(m);
}
