// Panoramas to perspective views with their cameras (views.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <type_traits>

#include "base/sample_io.hpp"
#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "jobs/camera_files.hpp"
#include "jobs/file_source.hpp"
#include "jobs/rendered_parts.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/rotation.hpp"
#include "panoproj/views.hpp"

namespace panoproj {
namespace {

constexpr int64_t kMaxViewSide = 65536;
constexpr size_t kMaxImages = 1000000;  // images.txt and transforms.json are held in memory

// One panorama as the job sees it.
using Frame = FileSource;

Frame open_frame(const ViewsJob& job, const std::string& input) { return open_file_source(input, job.from, job.options, "views"); }

std::string stem_of(const std::string& input) { return std::filesystem::path(input).stem().string(); }

// tan(fov / 2), exactly 1 at 90 degrees (so a cube face's focal is exactly W / 2).
double tan_half(double fov_deg) { return fov_deg == 90 ? 1.0 : std::tan(fov_deg * kPi / 360); }

// Sizes and focals: a view's own size, else the job's, else the source's resolution at its centre.
std::vector<ViewCamera> cameras_for(const ViewsJob& job, const Frame& frame) {
  std::vector<ViewCamera> cams;
  for (const ViewSpec& v : parse_rig(job.rig)) {
    const double th = tan_half(v.hfov);
    int64_t w = v.width, h = v.height;
    if (w == 0 && job.options.size) {
      w = job.options.size->width, h = job.options.size->height;
      if (v.vfov > 0) throw Error("view " + v.name + ": vfov " + std::to_string(v.vfov) + " and a size " + size_text(*job.options.size) +
                                  " both given (the height follows from vfov: give one)");
    }
    double focal;
    if (w > 0) {
      focal = 0.5 * static_cast<double>(w) / th;
    } else {
      focal = center_density(frame.base.source);
      const double wide = std::round(2 * focal * th);
      if (!(wide <= kMaxViewSide))
        throw Error("view " + v.name + ": " + std::to_string(static_cast<int64_t>(std::min(wide, 1e15))) +
                    " px wide at the source's resolution (at most " + std::to_string(kMaxViewSide) +
                    "): give a size, or a smaller hfov");
      w = std::max<int64_t>(1, static_cast<int64_t>(wide));
      focal = 0.5 * static_cast<double>(w) / th;
    }
    if (h == 0) {
      const double tall = std::round(2 * focal * tan_half(v.vfov > 0 ? v.vfov : v.hfov));
      if (!(tall <= kMaxViewSide))
        throw Error("view " + v.name + ": " + std::to_string(static_cast<int64_t>(std::min(tall, 1e15))) +
                    " px tall (at most " + std::to_string(kMaxViewSide) + "): give a size, or a smaller vfov");
      h = std::max<int64_t>(1, static_cast<int64_t>(tall));
    }
    cams.push_back({v.name, Size{w, h}, focal, rotation_from_ypr(v.yaw, v.pitch, v.roll)});
  }
  return cams;
}

ViewFiles files_of(const ViewsJob& job, bool partial) { return {job.format, job.layout == "folders", partial}; }

void check_job(const ViewsJob& job) {
  if (job.layout != "flat" && job.layout != "folders") throw Error("layout: '" + job.layout + "' (expected flat or folders)");
  if (job.inputs.empty()) throw Error("no input given (expected one or more panoramas)");
  if (job.output.empty()) throw Error("no output folder given");
  web_format(job.format, "format");
  check_write_options(job.write);
  if (const auto& s = job.options.size; s && (s->width < 1 || s->height < 1 || s->width > kMaxViewSide || s->height > kMaxViewSide))
    throw Error("size: " + size_text(*s) + " (expected 1 to " + std::to_string(kMaxViewSide) + " pixels a side)");
}

// Every input's header, name and projection, before anything is written: one size and projection
// (the rig's cameras are the same for all), names COLMAP can hold, none twice.
void check_inputs(const ViewsJob& job, const Frame& first, size_t views) {
  if (job.inputs.size() * views > kMaxImages)
    throw Error(std::to_string(job.inputs.size()) + " panoramas of " + std::to_string(views) + " views are over " +
                std::to_string(kMaxImages) + " images (split the sequence, or use fewer views)");
  std::set<std::string> seen;
  for (size_t i = 0; i < job.inputs.size(); ++i) {
    const std::string& in = job.inputs[i];
    const std::string stem = stem_of(in);
    for (char c : stem)
      if (static_cast<unsigned char>(c) <= ' ' || c == 0x7f)
        throw Error("input " + in + ": a space or control character in its name, which COLMAP's images.txt cannot hold (rename it)");
    if (stem.empty()) throw Error("input " + in + ": no file name");
    if (!seen.insert(stem).second)
      throw Error("input " + in + ": a second input named " + stem + " (the views are named by the input's name: rename one)");
    if (i == 0) continue;
    const Frame f = open_frame(job, in);
    if (f.info.size != first.info.size || f.base.source.index() != first.base.source.index() ||
        f.partial != first.partial || center_density(f.base.source) != center_density(first.base.source))
      throw Error("input " + in + " is " + size_text(f.info.size) + " " + f.from_text + ", the first " +
                  size_text(first.info.size) + " " + first.from_text + " (a rig's frames need one size and projection)");
  }
}

// 255 where the view is wholly covered, else 0 (COLMAP and nerfstudio skip the zeros).
Image mask_of(const Image& view) {
  const int a = view.alpha_channel();
  Image mask(view.size(), 1, PixelType::U8);
  with_sample_type(view.type(), [&](auto sample) {
    using T = decltype(sample);
    const double full = std::is_integral_v<T> ? static_cast<double>(std::numeric_limits<T>::max()) : 1.0;
    for (int64_t y = 0; y < view.height(); ++y) {
      uint8_t* out = mask.row(y);
      for (int64_t x = 0; x < view.width(); ++x) out[x] = load<T>(view.pixel(x, y) + a * sizeof(T)) >= full ? 255 : 0;
    }
  });
  return mask;
}

// Renders frame k's views into the temporary folder; returns {written, empty}.
std::array<int64_t, 2> render_frame(const ViewsJob& job, const std::vector<ViewCamera>& cams, const FolderWriter& folder,
                                    int64_t k, const std::function<void()>& view_done) {
  const std::string& input = job.inputs[static_cast<size_t>(k)];
  const Frame frame = open_frame(job, input);
  ConvertOptions o = job.options;
  if (frame.partial) o.add_alpha = true, o.edges.soft = true;
  std::vector<ConversionGeometry> views;
  uint64_t out_bytes = 0;
  int scale = job.options.decode_scale > 0 ? job.options.decode_scale : 8;
  for (const ViewCamera& c : cams) {
    ConversionGeometry g = frame.base;
    const double w = static_cast<double>(c.size.width), h = static_cast<double>(c.size.height);
    g.target = Pinhole(c.size, c.focal, c.focal, 0.5 * w, 0.5 * h);
    g.rotation = frame.base.rotation * c.world_from_camera;
    if (job.options.decode_scale == 0) scale = std::min(scale, frame.info.scalable ? coarsest_decode_scale(g, finest_source_step(g, 4)) : 1);
    out_bytes = std::max(out_bytes, image_bytes(c.size, frame.info.channels + 1, 2 * bytes_of(frame.info.type)));
    views.push_back(std::move(g));
  }
  if (!frame.info.scalable) scale = 1;
  require_memory("a view", out_bytes, job.options.memory_limit);
  const Size at{frame.info.size.width / scale, frame.info.size.height / scale};
  const Image source = read_image_region(input, 0, 0, at.width, at.height, job.options.memory_limit, out_bytes, scale);
  Image with_alpha;
  const Image& in = source_for(source, o, with_alpha);
  const std::string stem = stem_of(input);
  const ViewFiles files = files_of(job, frame.partial);
  const ImageFormat& format = web_format(job.format, "format");
  std::array<int64_t, 2> counts{0, 0};
  for (size_t v = 0; v < views.size(); ++v) {
    check_interrupt();
    if (scale > 1) views[v].source = rescaled(views[v].source, at);
    Image out;
    converter_for(views[v], o).run(in, out);
    // A partial source's view flattened over black by coverage (none: black); a whole one as made.
    Flat flat;
    if (frame.partial) flat = flatten(out, 0, 0, out.width(), out.height(), true);
    if (flat.empty) flat.image = Image(out.size(), out.channels() - 1, out.type());
    const std::string path = files.image_path(stem, cams[v].name);
    folder.write(path, encoded(frame.partial ? flat.image : out, format, job.write,
                               job.output + "/" + path));
    if (frame.partial) {
      const std::string mpath = files.mask_path(stem, cams[v].name);
      folder.write(mpath, encoded(mask_of(out), kPngFormat, job.write, job.output + "/" + mpath));
    }
    ++counts[0];
    counts[1] += flat.empty ? 1 : 0;
    if (view_done) view_done();
  }
  return counts;
}

ViewsReport finish(const ViewsJob& job, OutputFolder& folder, std::array<int64_t, 2> counts) {
  const Frame first = open_frame(job, job.inputs[0]);
  ViewsReport r;
  r.views = cameras_for(job, first);
  for (const std::string& in : job.inputs) r.stems.push_back(stem_of(in));
  for (const TextFile& f : camera_files(r.views, r.stems, files_of(job, first.partial)))
    folder.writer().write(f.path, f.text);
  folder.commit();
  r.from = first.from_text, r.source_size = first.info.size, r.masks = first.partial;
  r.images = counts[0], r.empty = counts[1];
  return r;
}

// Everything checked before any view is rendered; the cameras.
std::vector<ViewCamera> begin(const ViewsJob& job) {
  check_job(job);
  const Frame first = open_frame(job, job.inputs[0]);
  std::vector<ViewCamera> cams = cameras_for(job, first);
  check_inputs(job, first, cams.size());
  return cams;
}

}  // namespace

ViewsReport run_views(const ViewsJob& job, const std::function<void(double)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<ViewCamera> cams = begin(job);
  OutputFolder folder(job.output, job.write.overwrite, job.inputs, "views");
  std::array<int64_t, 2> counts{0, 0};
  const double total = static_cast<double>(job.inputs.size() * cams.size());
  double done = 0;
  for (size_t k = 0; k < job.inputs.size(); ++k) {
    const auto c = render_frame(job, cams, folder.writer(), static_cast<int64_t>(k), [&] {
      if (progress) progress(++done / total);
    });
    counts[0] += c[0], counts[1] += c[1];
  }
  ViewsReport r = finish(job, folder, counts);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

StagedFolder begin_views(const ViewsJob& job) {
  begin(job);
  OutputFolder folder(job.output, job.write.overwrite, job.inputs, "views");
  folder.keep();
  return folder.staged();
}

std::array<int64_t, 2> render_views(const ViewsJob& job, const StagedFolder& staged, const std::vector<int64_t>& frames) {
  check_job(job);
  const FolderWriter folder(staged, job.output);
  const std::vector<ViewCamera> cams = cameras_for(job, open_frame(job, job.inputs.at(0)));
  std::array<int64_t, 2> counts{0, 0};
  for (int64_t k : frames) {
    if (k < 0 || k >= static_cast<int64_t>(job.inputs.size()))
      throw Error("frame " + std::to_string(k) + " is not in the job (" + std::to_string(job.inputs.size()) + " inputs)");
    const auto c = render_frame(job, cams, folder, k, {});
    counts[0] += c[0], counts[1] += c[1];
  }
  return counts;
}

ViewsReport finish_views(const ViewsJob& job, const StagedFolder& staged, std::array<int64_t, 2> counts) {
  check_job(job);
  OutputFolder folder(job.output, job.write.overwrite, staged, "views");
  return finish(job, folder, counts);
}

void abandon_views(const StagedFolder& folder) { OutputFolder::remove_staged(folder); }

}  // namespace panoproj
