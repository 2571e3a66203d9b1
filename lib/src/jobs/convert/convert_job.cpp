// The convert job: images (or a cube-face set, or a batch) to another projection, file to file.
// Planned whole first (convert_plan.hpp), then each frame read (only what the view needs),
// converted and written atomically.
#include <chrono>
#include <cstdio>
#include <mutex>
#include <set>

#include "base/pixel_buffers.hpp"
#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "io/region_read.hpp"
#include "io/streamed_output.hpp"
#include "jobs/convert/convert_plan.hpp"
#include "jobs/convert/frame_pipeline.hpp"
#include "jobs/convert/video_convert.hpp"
#include "jobs/frame_selection.hpp"
#include "jobs/list.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/photo_sphere.hpp"

namespace panoproj {
namespace {

// The rows only a video's output takes.
const std::vector<OptionDef>& encoder_rows() {
  static const std::vector<OptionDef> rows{
      {"codec", OptionType::Text, 0, "None",
       "video: the output's codec (default: h264; vp9 for .webm)", nullptr,
       "h264|hevc|av1|vp9|ffv1|prores"},
      {"crf", OptionType::Integer, 0, "None",
       "video: the encoder's constant quality (default: its own, 23 for h264)"},
      {"bitrate", OptionType::Text, 0, "None", "video: a bit rate instead of crf, e.g. 8M, 2500k"},
      {"preset", OptionType::Text, 0, "None",
       "video: the encoder's preset, e.g. veryfast, medium, slow"},
      {"gop", OptionType::Integer, 0, "None",
       "video: frames between keyframes (default: the encoder's)", nullptr, nullptr, "-g,--gop"},
  };
  return rows;
}

// A video's rows given for an image: refused, naming the first.
void refuse_video_rows(const Arguments& a, const std::string& input) {
  for (const auto* rows : {&encoder_rows(), &frame_selection_rows()})
    for (const OptionDef& d : *rows)
      if (d.type == OptionType::Integer ? a.optional_integer(d.name).has_value()
                                        : !a.text(d.name).empty()) {
        const std::string flag = flag_of(d);  // ("-g,--gop": the long one)
        throw Error(flag.substr(flag.rfind(',') + 1) + " is for a video: " + input + " is not one");
      }
}

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows = [] {
    std::vector<OptionDef> r = job_rows(
        {
            {"inputs", OptionType::Paths, 0, "None",
             "IN... OUT: an input image (or a cube-face pattern with {face}/{index}/{axis}; with "
             "--from gopro-max, a GoPro MAX's two strips, stream 0:0's first) and the output; "
             "several inputs (same size) need an output pattern with {stem} or {n}",
             nullptr, nullptr, "files", kPositional | kRequired},
            {"output", OptionType::Path, 0, "None",
             "the output: a path, a face pattern or a batch pattern", nullptr, nullptr, nullptr,
             kPositional | kRequired},
            {"src", OptionType::Text, 0, "None",
             "source projection spec (default: 2:1 image = equirect; face pattern = "
             "cubemap:layout=files; .360 video = gopro-max)",
             nullptr, nullptr, "from"},
            {"dst", OptionType::Text, 0, "None", "target projection spec, e.g. fisheye:fov=180",
             nullptr, nullptr, "to", kRequired},
        },
        kUseConvert | kUseFiles,
        {write_option("depth"),
         write_option("overwrite"),
         write_option("quality"),
         write_option("subsampling"),
         {"no_metadata", OptionType::Flag, 0, "False",
          "write no metadata (default: the input's EXIF, ICC profile ..., less orientation, size "
          "and "
          "thumbnail)"},
         command_option("quiet"),
         command_option("verbose")});
    for (const auto* video : {&encoder_rows(), &frame_selection_rows()})
      r.insert(r.end() - 2, video->begin(), video->end());
    return r;
  }();
  return rows;
}

ConvertRequest request_of(const Arguments& a) {
  ConvertRequest r;
  r.inputs = a.paths("inputs");
  r.output = a.text("output");
  r.from = a.optional_text("src");
  r.to = a.text("dst");
  r.options = a.options();
  r.write = a.write();
  r.keep_metadata = !a.flag("no_metadata");
  return r;
}

// The input's metadata an output keeps: all but what described the old pixels (orientation: the
// conversion worked on the stored pixels; dimensions, thumbnail, pixel aspect, an EXR's screen
// window) and how the old file was stored (compression, layout, format-specific settings: an
// EXR's lossy DWAB must not pass to its output). By OpenImageIO's names, for TIFF, EXR and HDR
// inputs.
Metadata carried_metadata(const std::string& input) {
  static const char* const kDropped[] = {
      "Orientation",        "Exif:PixelXDimension", "Exif:PixelYDimension", "PixelAspectRatio",
      "screenWindowCenter", "screenWindowWidth",    "compression",          "planarconfig"};
  Metadata kept;
  for (Attribute& a : read_metadata(input)) {
    const std::string& n = a.name;
    bool drop = n.rfind("thumbnail", 0) == 0 ||
                n.rfind("rla:", 0) == 0;  // (RLA: a format OpenImageIO reads)
    for (const char* d : kDropped) drop |= n == d;
    for (const ImageFormat* f : image_formats())
      drop |= n.rfind(std::string(f->name) + ":", 0) == 0;
    if (!drop) kept.push_back(std::move(a));
  }
  return kept;
}

// Inputs whose blocks panoproj reads itself (JPEG, PNG) pass them as stored (the writer resets
// EXIF's orientation, rewrites its dimensions and drops its thumbnail; a Photo Sphere packet is
// not carried); formats without metadata (PPM) have none.
void carry_metadata(const std::string& input, const std::string& format, WriteOptions& write) {
  const ImageFormat& f = format_named(format);
  if (f.embedded_metadata)
    write.embedded = read_embedded_metadata(input);
  else if (f.holds_metadata)
    write.metadata = carried_metadata(input);
}

const char* layout_name(StereoLayout l) {
  return l == StereoLayout::TopBottom ? "tb" : l == StereoLayout::SideBySide ? "sbs" : "mono";
}

// The report's stereo words: the layouts, the eye taken, each eye's size.
std::string stereo_note(const ConversionGeometry& g) {
  if (!g.stereo.any()) return "";
  std::string s =
      std::string("stereo ") + layout_name(g.stereo.source) + " -> " + layout_name(g.stereo.target);
  if (g.stereo.source != StereoLayout::Mono && g.stereo.target == StereoLayout::Mono)
    s += g.stereo.eye ? " (right eye)" : " (left eye)";
  if (g.stereo.source == StereoLayout::Mono) s += " (both eyes from the one image)";
  return s + ", eyes " + size_text(size_of(g.source)) + " -> " + size_text(size_of(g.target));
}

// One frame's report: what the command prints, and the fields a caller reads.
struct FrameReport {
  std::string input, output;
  Size input_size, output_size;  // one face's size where a face set
  // From the conversion's start until the output landed: map (first input of a batch), remap
  // with the source's decoding, encoding and writing; in a pipelined batch the decoding is done
  // ahead, on other threads, and is not counted.
  std::chrono::steady_clock::time_point started;
  double map_seconds = 0;
  double seconds = 0;         // (done())
  double read_fraction = 1;   // share of the source's pixels read (only what the view needs)
  std::string source_format;  // "" for face sets
};

std::string frame_line(const ConvertPlan& p, const FrameReport& r) {
  auto dims = [](Size sz, bool faces) {
    return std::string(faces ? "6 faces of " : "") + size_text(sz);
  };
  const std::string decoded =
      r.source_format.empty()
          ? ""
          : " (" + r.source_format +
                (p.scale > 1 ? " at 1/" + std::to_string(p.scale) + " scale" : "") + ")";
  const std::string stereo = stereo_note(*p.geometry);
  char line[4096];
  std::snprintf(line, sizeof line,
                "%s (%s, %s) -> %s (%s, %s): %.3f s, %s, antialias %s, %s engine (%s), %d threads, "
                "decoded %.0f%% of "
                "the source%s%s",
                r.input.c_str(), dims(r.input_size, p.in_faces).c_str(), p.from_text.c_str(),
                r.output.c_str(), dims(r.output_size, p.out_faces).c_str(), p.to->str().c_str(),
                r.seconds, name_of(p.options.interp), name_of(antialias_of(p.options)).c_str(),
                name_of(p.options.engine), simd_target(), resolve_threads(p.options.threads),
                100 * r.read_fraction, decoded.c_str(),
                stereo.empty() ? "" : (", " + stereo).c_str());
  return line;
}

Report frame_report(const FrameReport& r) {
  return {{"input", {r.input}},
          {"output", {r.output}},
          {"input_size", report_size(r.input_size)},
          {"output_size", report_size(r.output_size)},
          {"seconds", {r.seconds}},
          {"read_fraction", {r.read_fraction}},
          {"source_format", {r.source_format}}};
}

// Runs a plan's frames: one after another, or through a pipeline (frame_pipeline.hpp) where its
// memory allows.
class FrameRunner {
 public:
  FrameRunner(ConvertPlan& plan, const JobEvents& events) : p_(plan), events_(events) {}

  std::vector<ReportValue> run() {
    // A batch of files goes through the pipeline: two frames decode at once, each on one thread,
    // while the one before converts (on every thread) and the one before that is written; so 3
    // source windows, 2 outputs and 3 encoded outputs (counted at their decoded size) at most.
    // Otherwise one frame after another, each decoded while it converts.
    const int readers = std::min(2, resolve_threads(p_.options.threads));
    const uint64_t budget = memory_budget(p_.options.memory_limit);
    const uint64_t counted = add_bytes(p_.memory.pipeline(readers), p_.memory.window);
    if (p_.batch && readers > 1 && counted <= budget)
      run_pipelined(readers, budget - counted);
    else
      run_serial();
    return std::move(reports_);
  }

 private:
  // A frame: its source (a file's window, or the face set), its output's encoded files, its report.
  struct Frame {
    std::optional<RegionRead> file;
    Image face_set;
    EncodedOutput encoded;
    FrameReport report;
  };

  // (spare: a source buffer the frame before is done with)
  void open(size_t n, Frame& f, uint64_t other_bytes, Image spare) {
    if (p_.held())
      f.face_set = std::move(*p_.faces);  // (one frame)
    else
      f.file.emplace(p_.request.inputs[n], p_.need.x0, p_.need.y0, p_.need.x1, p_.need.y1,
                     p_.options.memory_limit, other_bytes, p_.scale, std::move(spare));
  }

  WriteOptions write_options(size_t n) const {
    WriteOptions write = p_.request.write;
    write.threads = p_.options.threads;
    if (!p_.request.keep_metadata) return write;
    if (!p_.held()) carry_metadata(p_.request.inputs[n], p_.infos[n].format, write);
    // Equirect outputs say where they sit in the sphere (Photo Sphere XMP, read by viewers).
    // (A stereo frame: one eye's fields and GSpherical:StereoMode.)
    if (const auto* e = std::get_if<Equirect>(&p_.geometry->target)) {
      PhotoSphere ps = photo_sphere_of(*e);
      if (p_.geometry->stereo.target != StereoLayout::Mono)
        ps.stereo_mode =
            p_.geometry->stereo.target == StereoLayout::TopBottom ? "top-bottom" : "left-right";
      write.xmp = photo_sphere_xmp(ps);
    }
    return write;
  }

  // Converts frame n into out and encodes it; `reading`: decodes the file meanwhile, the tiles
  // taking its rows as they come (else it has been read).
  void convert(size_t n, Frame& f, Image& out, bool reading) {
    // The rows are waited for unless an alpha channel is first added to a copy of the source.
    if (reading && f.file && p_.options.add_alpha && f.file->image().alpha_channel() < 0)
      f.file->read(), reading = false;
    Image with_alpha;
    const Image& source = source_for(f.file ? f.file->image() : f.face_set, p_.options, with_alpha);
    const auto t0 = std::chrono::steady_clock::now();
    const double frames = static_cast<double>(p_.outputs.size());
    const auto progress = [&](double x) {
      if (events_.progress) events_.progress((static_cast<double>(n) + x) / frames);
    };
    const WriteOptions write = write_options(n);
    // A single JPEG output encodes its parts as they are done (while the source is still read).
    std::optional<StreamedOutput> single;
    const Size out_size = p_.geometry->target_frame();
    if (!p_.out_faces)
      single.emplace(p_.outputs[n], write, out_size, output_channels(p_.channels, p_.options),
                     p_.type);
    std::function<void(const PixelRect&)> finished;
    if (single && single->streams()) finished = [&](const PixelRect& r) { single->done(out, r); };
    const Converter& c = *p_.converter;
    if (reading)
      c.run_reading(
          source, out, [&](const RowsArrived& arrived) { f.file->read(arrived); }, nullptr,
          progress, finished);
    else
      c.run(source, out, nullptr, progress, finished);
    // (Each name is said once a job: once clipping was, later frames skip counting it.)
    for (const std::string& w :
         write_warnings(p_.outputs[n], out, write, !warned("samples clipped")))
      warn_once(w);
    f.encoded =
        single ? single->finish(out) : encode_cube_faces(out, p_.outputs[n], write, p_.out_order);
    auto face_size = [](Size strip) { return Size{strip.height, strip.height}; };
    const double read = static_cast<double>(source.width() * source.height()) /
                        static_cast<double>(source.frame_size().width * source.frame_size().height);
    f.report = {
        p_.in_pair ? p_.request.inputs[0] + " + " + p_.request.inputs[1] : p_.request.inputs[n],
        p_.outputs[n],
        p_.in_faces ? face_size(source.size()) : p_.frame,
        p_.out_faces ? face_size(out.size()) : out.size(),
        t0,
        n == 0 ? p_.map_seconds : 0.0,  // the map is built once, for the first
        0.0,
        read,
        p_.held() ? "" : p_.infos[n].format};
  }

  // Writes a frame's files and counts them for an interruption's line.
  void landed(const Frame& f) {
    f.encoded.write(
        [&] { set_batch_progress(++landed_, static_cast<int64_t>(p_.outputs.size())); });
  }

  bool warned(const std::string& name) {
    std::lock_guard lock(warned_mutex_);
    return warned_.count(name) > 0;
  }

  // Each named warning ("alpha dropped: ...") once a job, with the first file it concerns.
  void warn_once(const std::string& line) {
    std::lock_guard lock(warned_mutex_);
    if (warned_.insert(line.substr(0, line.find(':'))).second && events_.warning)
      events_.warning(line);
  }

  void done(Frame& f) {
    f.report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - f.report.started).count() +
        f.report.map_seconds;
    reports_.push_back({frame_report(f.report)});
    if (events_.line) events_.line(frame_line(p_, f.report));
  }

  void run_serial() {
    Image out, source;  // one buffer each for every frame
    for (size_t n = 0; n < p_.outputs.size(); ++n) {
      Frame f;
      open(n, f, p_.memory.job(), std::move(source));
      convert(n, f, out, f.file.has_value());
      if (f.file) source = std::move(f.file->image());
      landed(f);
      done(f);
    }
  }

  // `spare_bytes`: the budget's rest, where the encoders' buffers freed with each frame serve the
  // next ones.
  void run_pipelined(int readers, uint64_t spare_bytes) {
    const ReuseFreedBuffers reuse(static_cast<size_t>(spare_bytes));  // (at most kMostBytes)
    const size_t n_frames = p_.outputs.size();
    std::vector<Frame> frames(n_frames);
    std::vector<Image> outs(2);  // frame n's in outs[n % 2]
    std::mutex spare_mutex;
    std::vector<Image> spare;  // source buffers converted frames are done with
    const uint64_t others = p_.memory.pipeline(readers);
    FrameStages stages;
    stages.read = [&](size_t n) {
      Image buffer;
      {
        std::lock_guard<std::mutex> lock(spare_mutex);
        if (!spare.empty()) buffer = std::move(spare.back()), spare.pop_back();
      }
      open(n, frames[n], others, std::move(buffer));
      // (no arrived: one decoder a frame; a second for its lower band would decode the rows it
      // skips again, and the readers fill the cores)
      frames[n].file->read([](int64_t) {});
      return true;
    };
    stages.convert = [&](size_t n) {
      convert(n, frames[n], outs[n % 2], false);
      std::lock_guard<std::mutex> lock(spare_mutex);
      spare.push_back(std::move(frames[n].file->image()));
      frames[n].file.reset();
    };
    stages.write = [&](size_t n) {
      landed(frames[n]);
      frames[n].encoded = {};
    };
    stages.written = [&](size_t n) { done(frames[n]); };
    run_frame_pipeline(n_frames, readers, stages);
  }

  ConvertPlan& p_;
  const JobEvents& events_;
  std::vector<ReportValue> reports_;
  int64_t landed_ = 0;  // (written by one thread: the serial loop's or the pipeline's writer)
  std::mutex warned_mutex_;
  std::set<std::string> warned_;
};

VideoRequest video_request_of(const Arguments& a) {
  VideoRequest r;
  r.files = request_of(a);
  r.files.write.threads = r.files.options.threads;
  r.frames = frame_selection_of(a);
  r.codec = a.text("codec");
  r.crf = a.optional_integer("crf");
  r.bitrate = a.text("bitrate");
  r.preset = a.text("preset");
  r.gop = a.optional_integer("gop").value_or(0);
  return r;
}

Report run(const Arguments& args, const JobEvents& events) {
  const std::vector<std::string> inputs = args.paths("inputs");
  if (!inputs.empty() && is_video_job(inputs[0], args.text("output")))
    return convert_video(video_request_of(args), events);
  if (!inputs.empty()) refuse_video_rows(args, inputs[0]);
  ConvertPlan plan = plan_convert(request_of(args));
  MadeFolders folders;  // a pattern's missing folders, removed again if the job fails
  if (plan.batch || plan.out_faces) folders.make(plan.files_out);
  FrameRunner runner(plan, events);
  set_batch_progress(0, static_cast<int64_t>(plan.outputs.size()));
  std::vector<ReportValue> frames = runner.run();
  set_batch_progress(0, 0);
  folders.keep();
  return {{"frames", {std::move(frames)}},
          {"src", {plan.from_text}},
          {"dst", {plan.to->str()}},
          {"decode_scale", {int64_t{plan.scale}}}};
}

}  // namespace

const JobDef convert_job{
    .name = "convert",
    .summary = "convert one image (or cube-face set) to another projection",
    .python =
        R"(Converts files to another projection (as ``panoproj convert``): an image, a cube-face
pattern, several images of one size into an output pattern with ``{stem}`` or ``{n}``, or a video.

A video (MP4, MOV, MKV, WebM, AVI, MPEG-TS) is converted on one plan, plane by plane in its own
pixel format, and encoded again (``codec``, ``crf``, ``bitrate``, ``preset``, ``gop``); its audio
and subtitles are copied, its spherical metadata gives the source and pose (unless ``src`` is
given) and is written where the container takes it. ``start`` and ``duration`` (seconds, or text
such as ``"1:30"``), ``fps``, ``every`` and ``stream`` pick its frames. An output pattern with
``{n}`` takes the frames as images; images with a video output make one. Video goes through the
system's FFmpeg libraries, else through PyAV (``pip install 'panoproj[av]'``; then the input's
spherical metadata is not read and none is written, each said by a warning).

Every output lands whole or not at all (an existing one kept unless ``overwrite``). The command's
warnings are UserWarnings. Returns a report: for images ``frames`` (one report each), for a video
its sizes, frame count, seconds, codecs and source spec.)",
    .rows = rows,
    .run = run,
    .python_name = "convert_file",
};

}  // namespace panoproj
