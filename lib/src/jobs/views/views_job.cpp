// The views job: panoramas to perspective views with their cameras (jobs/views/views.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <type_traits>

#include "base/input_check.hpp"
#include "base/sample_io.hpp"
#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "io/video_formats.hpp"
#include "io/video_plugin.hpp"
#include "jobs/file_source.hpp"
#include "jobs/frame_selection.hpp"
#include "jobs/list.hpp"
#include "jobs/rendered_parts.hpp"
#include "jobs/video_spherical.hpp"
#include "jobs/views/camera_files.hpp"
#include "jobs/views/views.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {
namespace {

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows = [] {
    std::vector<OptionDef> r = job_rows(
        {
            {"images", OptionType::Paths, 0, "None",
             "panoramas (one size and projection; each a frame), or one video, then the folder to "
             "make",
             nullptr, nullptr, "files", kPositional | kRequired},
            {"out_dir", OptionType::Path, 0, "None", "the folder to make", nullptr, nullptr,
             nullptr, kPositional | kRequired},
            {"rig", OptionType::Text, 0, "'cube'",
             "cube (default) | ring:n=8,fov=90,pitch=0[,vfov=,yaw=] | A+B | @rig.yaml (views: "
             "name, "
             "yaw, pitch, roll, "
             "hfov, vfov, size)"},
            {"src", OptionType::Text, 0, "None",
             "source projection spec (default as convert infers it)", nullptr, nullptr, "from"},
            web_format_option(),
            {"layout", OptionType::Text, 0, "'flat'",
             "flat (default: images/{stem}_{view}) | folders (images/{view}/{stem} and "
             "rig_config.json for COLMAP's "
             "rig_configurator)",
             nullptr, "flat|folders"},
            with_help(write_option("quality"), "JPEG quality, 1 to 100 (default 95)"),
        },
        kUseViews,
        {with_help(write_option("overwrite"), "replace an existing output folder"),
         command_option("quiet")});
    r.insert(r.end() - 2, frame_selection_rows().begin(), frame_selection_rows().end());
    return r;
  }();
  return rows;
}

struct ViewsJob {
  std::vector<std::string> inputs;  // panoramas (one size and projection), each a frame; or
                                    // one video, each frame taken a frame
  std::string output;               // the folder to make
  std::optional<std::string> from;  // source spec; default as convert infers it
  std::string rig;
  std::string format;      // a web format (formats.hpp)
  std::string layout;      // flat: images/{stem}_{view}; folders: images/{view}/{stem}
  ConvertOptions options;  // size (each view's, unless the rig gives one; none: from the
                           // source), interp, antialias, engine, threads, decode scale, memory
  WriteOptions write;      // quality, overwrite (the folder)
  FrameSelection frames;   // a video's frames taken
  bool video = false;      // the input is a video
};

ViewsJob job_of(const Arguments& a) {
  ViewsJob job{a.paths("images"), a.text("out_dir"), a.optional_text("src"),
               a.text("rig"),     a.text("format"),  a.text("layout"),
               a.options(),       a.write(),         frame_selection_of(a)};
  job.video = !job.inputs.empty() && is_video_file(job.inputs[0]);
  return job;
}

constexpr int64_t kMaxViewSide = 65536;
constexpr size_t kMaxImages = 1000000;  // images.txt and transforms.json are held in memory

// One panorama as the job sees it.
using Frame = FileSource;

Frame open_frame(const ViewsJob& job, const std::string& input) {
  return open_file_source(input, job.from, job.options, "views");
}

std::string stem_of(const std::string& input) {
  return std::filesystem::path(input).stem().string();
}

// A video's frame n as the job names it (numbers of six digits sort as the frames do).
std::string frame_name(const std::string& stem, int64_t n) {
  char b[32];
  std::snprintf(b, sizeof b, "_%06lld", static_cast<long long>(n));
  return stem + b;
}

// A video's frames as the job's panoramas: those taken (frame_selection.hpp), decoded as RGB one
// at a time.
class VideoPanoramas {
 public:
  explicit VideoPanoramas(const ViewsJob& job)
      : job_(job), reader_(open_reader(job)), frame_(source(job, reader_->info())) {
    require_memory("a video's frame",
                   image_bytes(frame_.info.size, frame_.info.channels, bytes_of(frame_.info.type)),
                   job.options.memory_limit);
    picker_.emplace(job.frames, reader_->info());
  }
  const Frame& frame() const { return frame_; }
  // The next frame taken into f; false at the end.
  bool next(VideoFrame& f) { return picker_->next(*reader_, f); }
  double expected() const { return job_.frames.expected(reader_->info()); }
  int64_t concealed() const { return reader_->concealed(); }

 private:
  static std::unique_ptr<VideoReader> open_reader(const ViewsJob& job) {
    const std::string& input = job.inputs[0];
    (void)read_head(input, 16, "input", "a video file");  // (a regular file, before libavformat)
    VideoBackend& vb = video_backend("reading " + input);
    if (!gopro_max_video(input, job.from))
      return vb.open(input, job.frames.stream, false, job.frames.range, true);
    if (job.frames.stream >= 0)
      throw Error(option_number("stream", std::to_string(job.frames.stream)) + " with " + input +
                  " as a GoPro MAX's strips: its two strip streams are found by their size (drop "
                  "--stream)");
    return vb.open_pair(input, false, job.frames.range, true);
  }
  static Frame source(const ViewsJob& job, const VideoInfo& v) {
    const ImageInfo info{v.size, v.pixels.alpha ? 4 : 3,
                         v.pixels.bits > 8 ? PixelType::U16 : PixelType::U8, "video", false};
    // (Without --from, the stream's spherical metadata: its projection, levelled by its pose.)
    const bool strips = gopro_max_video(job.inputs[0], job.from);
    if (job.from || strips || !v.spherical.any())
      return source_of(info, job.inputs[0], strips && !job.from ? "gopro-max" : job.from,
                       std::nullopt, job.options, "views");
    Frame f =
        source_of(info, job.inputs[0], spherical_source_spec(v.spherical, v.size, job.inputs[0]),
                  std::nullopt, job.options, "views");
    f.base.rotation = spherical_pose(v.spherical).transpose() * f.base.rotation;
    f.from_text += " (its spherical metadata: " + spherical_text(v.spherical) + ")";
    return f;
  }

  const ViewsJob& job_;
  std::unique_ptr<VideoReader> reader_;
  Frame frame_;
  std::optional<FramePicker> picker_;
};

std::vector<ViewCamera> cameras_for(const ViewsJob& job, const Frame& frame) {
  return view_cameras(parse_rig(job.rig), job.options.size, center_density(frame.base.source));
}

ViewFiles files_of(const ViewsJob& job, bool partial) {
  return {job.format, job.layout == "folders", partial};
}

void check_job(const ViewsJob& job) {
  if (job.layout != "flat" && job.layout != "folders")
    throw Error("layout: '" + job.layout + "' (expected flat or folders)");
  if (job.inputs.empty()) throw Error("no input given (expected one or more panoramas)");
  if (job.video && job.inputs.size() > 1)
    throw Error("input " + job.inputs[0] +
                " is a video: give it alone (its frames are the panoramas)");
  for (size_t i = 1; i < job.inputs.size(); ++i)
    if (is_video_file(job.inputs[i]))
      throw Error("input " + job.inputs[i] + " is a video among images: give it alone");
  if (!job.video && frame_selection_given(job.frames))
    throw Error("--stream, --start, --duration, --fps and --every are for a video: " +
                job.inputs[0] + " is an image");
  if (job.output.empty()) throw Error("no output folder given");
  web_format(job.format, "format");
  check_write_options(job.write);
  if (const auto& s = job.options.size;
      s && (s->width < 1 || s->height < 1 || s->width > kMaxViewSide || s->height > kMaxViewSide))
    throw Error("size: " + size_text(*s) + " (expected 1 to " + std::to_string(kMaxViewSide) +
                " pixels a side)");
}

// A name COLMAP's images.txt can hold.
void check_name(const std::string& input, const std::string& stem) {
  for (char c : stem)
    if (static_cast<unsigned char>(c) <= ' ' || c == 0x7f)
      throw Error("input " + input +
                  ": a space or control character in its name, which COLMAP's images.txt cannot "
                  "hold (rename it)");
  if (stem.empty()) throw Error("input " + input + ": no file name");
}

// Every input's header, name and projection, before anything is written: one size and projection
// (the rig's cameras are the same for all), names COLMAP can hold, none twice.
void check_inputs(const ViewsJob& job, const Frame& first, size_t views) {
  if (job.inputs.size() * views > kMaxImages)
    throw Error(std::to_string(job.inputs.size()) + " panoramas of " + std::to_string(views) +
                " views are over " + std::to_string(kMaxImages) +
                " images (split the sequence, or use fewer views)");
  std::set<std::string> seen;
  for (size_t i = 0; i < job.inputs.size(); ++i) {
    const std::string& in = job.inputs[i];
    const std::string stem = stem_of(in);
    check_name(in, stem);
    if (!seen.insert(stem).second)
      throw Error("input " + in + ": a second input named " + stem +
                  " (the views are named by the input's name: rename one)");
    if (i == 0) continue;
    const Frame f = open_frame(job, in);
    if (f.info.size != first.info.size || f.base.source.index() != first.base.source.index() ||
        f.partial != first.partial ||
        center_density(f.base.source) != center_density(first.base.source))
      throw Error("input " + in + " is " + size_text(f.info.size) + " " + f.from_text +
                  ", the first " + size_text(first.info.size) + " " + first.from_text +
                  " (a rig's frames need one size and projection)");
  }
}

// A frame's views: their geometries and the decode scale they allow (1 unless the file scales).
struct FramePlan {
  std::vector<ConversionGeometry> views;
  int scale = 1;
  uint64_t out_bytes = 0;  // the largest view's
};

FramePlan plan_frame(const ViewsJob& job, const std::vector<ViewCamera>& cams, const Frame& frame) {
  FramePlan plan;
  int scale = job.options.decode_scale > 0 ? job.options.decode_scale : 8;
  for (const ViewCamera& c : cams) {
    ConversionGeometry g = frame.base;
    const double w = static_cast<double>(c.size.width), h = static_cast<double>(c.size.height);
    g.target = Pinhole(c.size, c.focal, c.focal, 0.5 * w, 0.5 * h);
    g.rotation = frame.base.rotation * c.world_from_camera;
    if (job.options.decode_scale == 0)
      scale = std::min(
          scale, frame.info.scalable ? coarsest_decode_scale(g, finest_source_step(g, 4)) : 1);
    plan.out_bytes = std::max(plan.out_bytes, image_bytes(c.size, frame.info.channels + 1,
                                                          2 * bytes_of(frame.info.type)));
    plan.views.push_back(std::move(g));
  }
  plan.scale = frame.info.scalable ? scale : 1;
  require_memory("a view", plan.out_bytes, job.options.memory_limit);
  if (plan.scale > 1) {
    const Size at{frame.info.size.width / plan.scale, frame.info.size.height / plan.scale};
    for (ConversionGeometry& g : plan.views) g.source = rescaled(g.source, at);
  }
  return plan;
}

// Renders one panorama's views (`source`, read at the plan's scale) into the temporary folder as
// `stem`; returns {written, empty}.
PartCounts render_views(const ViewsJob& job, const std::vector<ViewCamera>& cams,
                        const FolderWriter& folder, const Frame& frame, const FramePlan& plan,
                        const Image& source, const std::string& stem,
                        const std::function<void()>& view_done) {
  ConvertOptions o = job.options;
  if (frame.partial) o.add_alpha = true, o.edges.soft = true;
  Image with_alpha;
  const Image& in = source_for(source, o, with_alpha);
  const ViewFiles files = files_of(job, frame.partial);
  const ImageFormat& format = web_format(job.format, "format");
  PartCounts counts;
  for (size_t v = 0; v < plan.views.size(); ++v) {
    check_interrupt();
    Image out;
    Converter(plan.views[v], o).run(in, out);
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
    ++counts.written;
    counts.empty += flat.empty ? 1 : 0;
    if (view_done) view_done();
  }
  return counts;
}

// Renders input k's views (read only at the scale they need).
PartCounts render_frame(const ViewsJob& job, const std::vector<ViewCamera>& cams,
                        const FolderWriter& folder, int64_t k,
                        const std::function<void()>& view_done) {
  const std::string& input = job.inputs[static_cast<size_t>(k)];
  const Frame frame = open_frame(job, input);
  const FramePlan plan = plan_frame(job, cams, frame);
  const Size at{frame.info.size.width / plan.scale, frame.info.size.height / plan.scale};
  const Image source = read_image_region(input, 0, 0, at.width, at.height, job.options.memory_limit,
                                         plan.out_bytes, plan.scale);
  return render_views(job, cams, folder, frame, plan, source, stem_of(input), view_done);
}

// The cameras' files and the report (the frames named `stems`, `first` their source).
Report finish(const ViewsJob& job, OutputFolder& folder, PartCounts counts, const Frame& first,
              const std::vector<ViewCamera>& cams, const std::vector<std::string>& stems) {
  for (const TextFile& f : camera_files(cams, stems, files_of(job, first.partial)))
    folder.writer().write(f.path, f.text);
  folder.commit();
  std::vector<ReportValue> views, frames;
  for (const ViewCamera& c : cams) {
    std::vector<ReportValue> rotation;
    for (int i = 0; i < 3; ++i)
      rotation.push_back({std::vector<ReportValue>{{c.world_from_camera(i, 0)},
                                                   {c.world_from_camera(i, 1)},
                                                   {c.world_from_camera(i, 2)}},
                          true});
    views.push_back({Report{{"name", {c.name}},
                            {"size", report_size(c.size)},
                            {"focal", {c.focal}},
                            {"world_from_camera", {rotation}}}});
  }
  for (const std::string& s : stems) frames.push_back({s});
  return {{"views", {views}},         {"frames", {frames}},
          {"src", {first.from_text}}, {"source_size", report_size(first.info.size)},
          {"masks", {first.partial}}, {"images", {counts.written}},
          {"empty", {counts.empty}},  {"seconds", {0.0}}};
}

// The image inputs' stems, in order.
std::vector<std::string> stems_of(const ViewsJob& job) {
  std::vector<std::string> stems;
  for (const std::string& in : job.inputs) stems.push_back(stem_of(in));
  return stems;
}

// Everything checked before any view is rendered; the cameras.
std::vector<ViewCamera> begin_job(const ViewsJob& job) {
  check_job(job);
  const Frame first = open_frame(job, job.inputs[0]);
  std::vector<ViewCamera> cams = cameras_for(job, first);
  check_inputs(job, first, cams.size());
  return cams;
}

std::string summary(const ViewsJob& job, const Report& r, const std::vector<ViewCamera>& cams,
                    PartCounts counts, double seconds) {
  std::string sizes;
  for (const ViewCamera& c : cams)
    if (sizes.find(size_text(c.size)) == std::string::npos)
      sizes += (sizes.empty() ? "" : ", ") + size_text(c.size);
  const auto& wh = std::get<std::vector<ReportValue>>(report_find(r, "source_size")->value);
  const Size source{std::get<int64_t>(wh[0].value), std::get<int64_t>(wh[1].value)};
  const bool masks = std::get<bool>(report_find(r, "masks")->value);
  const size_t n = std::get<std::vector<ReportValue>>(report_find(r, "frames")->value).size();
  const std::string what =
      job.video ? job.inputs[0] + ": " + std::to_string(n) + " frame" + (n == 1 ? "" : "s")
                : std::to_string(n) + " panorama" + (n == 1 ? "" : "s");
  char b[2048];
  std::snprintf(b, sizeof b,
                "%s (%s, %s) -> %s: %zu views each (%s), %lld images%s, COLMAP model in sparse/0, "
                "transforms.json, %.3f s",
                what.c_str(), size_text(source).c_str(),
                std::get<std::string>(report_find(r, "src")->value).c_str(), job.output.c_str(),
                cams.size(), sizes.c_str(), static_cast<long long>(counts.written),
                masks ? " with masks" : "", seconds);
  std::string line = b;
  if (counts.empty)
    line += "\n  " + std::to_string(counts.empty) +
            " views see no part of the panorama (written black, masked)";
  return line;
}

// A video's views: its frames taken, one after another, each a panorama named stem_NNNNNN.
// (cams and counts: the summary's.)
Report run_video(const ViewsJob& job, const JobEvents& events, std::vector<ViewCamera>& cams,
                 PartCounts& counts) {
  check_job(job);
  VideoPanoramas video(job);
  cams = cameras_for(job, video.frame());
  const std::string stem = stem_of(job.inputs[0]);
  check_name(job.inputs[0], stem);
  const FramePlan plan = plan_frame(job, cams, video.frame());
  OutputFolder folder(job.output, job.write.overwrite, job.inputs, "views");
  const double total = video.expected() * static_cast<double>(cams.size());
  double done = 0;
  std::vector<std::string> stems;
  VideoFrame f;
  while (video.next(f)) {
    if ((stems.size() + 1) * cams.size() > kMaxImages)
      throw Error(job.inputs[0] + ": its frames of " + std::to_string(cams.size()) +
                  " views are over " + std::to_string(kMaxImages) +
                  " images (take fewer with --fps or --every, or a part with --start and "
                  "--duration)");
    stems.push_back(frame_name(stem, static_cast<int64_t>(stems.size())));
    const PartCounts c = render_views(job, cams, folder.writer(), video.frame(), plan, f.planes[0],
                                      stems.back(), [&] {
                                        if (events.progress && total > 0)
                                          events.progress(std::min(1.0, ++done / total));
                                      });
    counts.written += c.written, counts.empty += c.empty;
  }
  if (stems.empty())
    throw Error("cannot read " + job.inputs[0] + ": no frame " +
                    (job.frames.whole() ? std::string("could be decoded") : "in the range given"),
                ErrorKind::File);
  if (video.concealed() > 0 && events.warning)
    events.warning(job.inputs[0] + ": " + std::to_string(video.concealed()) +
                   " corrupt packets or frames concealed");
  return finish(job, folder, counts, video.frame(), cams, stems);
}

Report run(const Arguments& args, const JobEvents& events) {
  const auto t0 = std::chrono::steady_clock::now();
  const ViewsJob job = job_of(args);
  Report r;
  std::vector<ViewCamera> cams;
  PartCounts counts;
  if (job.video) {
    r = run_video(job, events, cams, counts);
  } else {
    cams = begin_job(job);
    OutputFolder folder(job.output, job.write.overwrite, job.inputs, "views");
    const double total = static_cast<double>(job.inputs.size() * cams.size());
    double done = 0;
    for (size_t k = 0; k < job.inputs.size(); ++k) {
      const PartCounts c = render_frame(job, cams, folder.writer(), static_cast<int64_t>(k), [&] {
        if (events.progress) events.progress(++done / total);
      });
      counts.written += c.written, counts.empty += c.empty;
    }
    r = finish(job, folder, counts, open_frame(job, job.inputs[0]), cams, stems_of(job));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report_set(r, "seconds", {seconds});
  if (events.line) events.line(summary(job, r, cams, counts, seconds));
  return r;
}

// (A video is read once, in order: its views are one process's, not staged.)
ViewsJob staged_job_of(const Arguments& args) {
  ViewsJob job = job_of(args);
  if (job.video)
    throw Error("input " + job.inputs[0] +
                " is a video: its views are made in one process (give no client; or convert its "
                "frames to images first, e.g. 'frames/{n}.png', and give those)");
  return job;
}

Staged begin(const Arguments& args) {
  const ViewsJob job = staged_job_of(args);
  begin_job(job);
  OutputFolder folder(job.output, job.write.overwrite, job.inputs, "views");
  folder.keep();
  return {folder.staged(), static_cast<int64_t>(job.inputs.size())};
}

PartCounts render(const Arguments& args, const StagedFolder& staged,
                  const std::vector<int64_t>& frames) {
  const ViewsJob job = staged_job_of(args);
  check_job(job);
  const FolderWriter folder(staged, job.output);
  const std::vector<ViewCamera> cams = cameras_for(job, open_frame(job, job.inputs.at(0)));
  PartCounts counts;
  for (int64_t k : frames) {
    if (k < 0 || k >= static_cast<int64_t>(job.inputs.size()))
      throw Error("frame " + std::to_string(k) + " is not in the job (" +
                  std::to_string(job.inputs.size()) + " inputs)");
    const PartCounts c = render_frame(job, cams, folder, k, {});
    counts.written += c.written, counts.empty += c.empty;
  }
  return counts;
}

Report finish_staged(const Arguments& args, const StagedFolder& staged, PartCounts counts) {
  const ViewsJob job = staged_job_of(args);
  check_job(job);
  OutputFolder folder(job.output, job.write.overwrite, staged, "views");
  const Frame first = open_frame(job, job.inputs[0]);
  return finish(job, folder, counts, first, cameras_for(job, first), stems_of(job));
}

}  // namespace

const JobDef views_job{
    .name = "views",
    .summary = "split panoramas into perspective views with COLMAP and nerfstudio cameras",
    .python =
        R"(Splits each panorama file of ``images`` (one path, or a sequence: one size and projection,
each a frame) into perspective views and writes them with their cameras into the new folder
``out_dir`` (as ``panoproj views``): ``images/{stem}_{view}.jpg`` (or PNG; ``layout="folders"``:
``images/{view}/{stem}.jpg`` and ``rig_config.json`` for COLMAP's rig_configurator), for a
partial panorama ``masks/<image's name>.png``, COLMAP's text model in ``sparse/0`` (PINHOLE
cameras with cx = W/2 by COLMAP's pixel convention, images, one rig whose sensors are the
views, one frame per panorama) and nerfstudio's ``transforms.json``. The world is the
panorama's frame (x right, y down, z forward; transforms.json turns it z up).

``rig``: ``"cube"``, ``"ring:n=8,fov=90,pitch=0"``, a sum ``"A+B"``, ``"@rig.yaml"``, or a
sequence of mappings with name, yaw, pitch, roll, hfov, vfov, size. ``size``: each view's
(W, H) unless the rig gives one; default: the source's resolution.

``images`` may instead be one video: each frame taken (``start``, ``duration``: a part by
time; ``fps`` or ``every``: fewer frames; ``stream``: another video stream) is a panorama
named ``{stem}_000000``, ``{stem}_000001`` ... in order (the frames of SfM or splatting from a
360 video); a video's views are made in one process.

``client``: a ``dask.distributed`` Client; each frame is then a task (the workers must see
the inputs and the output's parent folder at the same paths), with the same bytes as a local
run. Returns a report: the views (size, focal, world_from_camera), frames, source spec.)",
    .rows = rows,
    .run = run,
    .begin = begin,
    .render = render,
    .finish = finish_staged,
};

}  // namespace panoproj
