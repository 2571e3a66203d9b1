#include "jobs/convert/video_convert.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "base/input_check.hpp"
#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "io/video_formats.hpp"
#include "io/video_plugin.hpp"
#include "jobs/convert/frame_pipeline.hpp"
#include "jobs/convert/image_frames.hpp"
#include "jobs/convert/video_planes.hpp"
#include "jobs/file_source.hpp"
#include "jobs/video_spherical.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/limits.hpp"
#include "spec/photometric_keys.hpp"

namespace panoproj {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

const char* siting_name(ChromaSiting s) {
  static const char* const kNames[] = {"unspecified", "left",       "center", "topleft",
                                       "top",         "bottomleft", "bottom"};
  return kNames[static_cast<int>(s)];
}

// "8M", "2500k", "800000" in bits a second.
int64_t parse_bitrate(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  double scale = 1;
  if (end && (*end == 'k' || *end == 'K'))
    scale = 1e3, ++end;
  else if (end && (*end == 'M' || *end == 'm'))
    scale = 1e6, ++end;
  if (text.empty() || !end || *end != '\0' || !std::isfinite(v) || v <= 0 || v * scale > 1e11)
    throw Error(option_text("bitrate", text) +
                " is not a bit rate (e.g. 8M, 2500k, 800000; up to 100G)");
  return static_cast<int64_t>(v * scale);
}

// The clip's plan: the reader, the geometry per plane kind, the converters.
class VideoJob {
 public:
  VideoJob(const VideoRequest& r, const JobEvents& events, VideoWriter* sink)
      : r_(r), events_(events), sink_(sink) {}

  Report run() {
    const std::string& input = r_.files.inputs.at(0);
    from_images_ = !is_video_job(input, "");
    to_images_ = !sink_ && !video_container_of(r_.files.output);
    // (A regular file, not a FIFO or device, before libavformat opens it; missing named as such.)
    if (!from_images_) (void)read_head(input, 16, "input", "a video file");
    VideoBackend* vb = from_images_ && to_images_ ? nullptr : &video_backend("reading " + input);
    check_paths(vb);
    strips_ = !from_images_ && gopro_max_video(input, r_.files.from);
    if (strips_ && sel_.stream >= 0)
      throw Error(option_number("stream", std::to_string(sel_.stream)) + " with " + input +
                  " as a GoPro MAX's strips: its two strip streams are found by their size (drop "
                  "--stream)");
    // Frames decoded as RGB for images, and where the specs correct colours (photometric keys:
    // a response needs RGB, not a video's planes).
    const bool rgb = to_images_ || gives_photometry(parse_spec(r_.files.to)) ||
                     (r_.files.from && gives_photometry(parse_spec(*r_.files.from)));
    reader_ = from_images_ ? image_list_reader(r_.files.inputs, sel_.fps > 0 ? sel_.fps : 25)
              : strips_    ? vb->open_pair(input, !to_images_, sel_.range, rgb)
                           : vb->open(input, sel_.stream, !to_images_, sel_.range, rgb);
    if (from_images_) sel_.fps = 0;  // (the images' rate, every one taken)
    const VideoInfo& info = reader_->info();
    picker_.emplace(sel_, info);
    px_ = info.pixels;
    plan_geometry(info);
    const auto t0 = Clock::now();
    if (sink_ || to_images_) {
      std::unique_ptr<VideoWriter> images =
          sink_ ? nullptr : image_sequence_writer(r_.files.output, r_.files.write);
      plan_planes();
      run_frames(sink_ ? *sink_ : *images);
      require_frames();
      seconds_ = since(t0);
      return finish(info);
    }
    OutputSet set(r_.files.write.overwrite);
    const int fd = set.open(r_.files.output);
    try {
      // (The encoder first: it may refuse the size before the maps are made.)
      auto writer = vb->create(fd, r_.files.output, settings(info), reader_.get());
      for (const std::string& n : writer->notes()) warn(n);
      spherical_ = writer->spherical();
      plan_planes();
      run_frames(*writer);
      require_frames();
      const auto t1 = Clock::now();
      writer->finish();
      encode_seconds_ += since(t1);
    } catch (...) {
      ::close(fd);
      throw;
    }
    set.seal(fd, r_.files.output);
    set.commit();
    seconds_ = since(t0);
    return finish(info);
  }

 private:
  void require_frames() const {
    if (frames_ > 0) return;
    const std::string& input = r_.files.inputs[0];
    const VideoRange& range = sel_.range;
    if (range.start > 0 || !std::isinf(range.end))
      throw Error(
          "cannot read " + input + ": it has no frame from " +
              std::to_string(range.start).substr(0, 6) + " s" +
              (std::isinf(range.end) ? ""
                                     : " to " + std::to_string(range.end).substr(0, 6) + " s") +
              " (it lasts " + std::to_string(reader_->info().duration).substr(0, 6) + " s)",
          ErrorKind::File);
    throw Error("cannot read " + input + ": no frame could be decoded", ErrorKind::File);
  }

  // The warnings of a clip read, and the report.
  Report finish(const VideoInfo& info) const {
    const std::string& input = r_.files.inputs[0];
    if (reader_->concealed() > 0)
      warn(input + ": " + std::to_string(reader_->concealed()) +
           " corrupt packets or frames concealed");
    // A file cut short converts as far as it goes (as FFmpeg does), with a warning.
    const double tb = static_cast<double>(info.time_base[0]) / info.time_base[1];
    const double rate =
        info.frame_rate[1] > 0 ? static_cast<double>(info.frame_rate[0]) / info.frame_rate[1] : 0;
    const double step = sel_.step(rate);
    const double covered = sel_.range.start + static_cast<double>(last_pts_) * tb + step;
    if (sel_.whole() && info.frames > 0 && frames_ < info.frames)
      warn(input + ": " + std::to_string(frames_) + " of its " + std::to_string(info.frames) +
           " frames decoded (the file is damaged)");
    else if (step > 0 && std::min(info.duration, sel_.range.end) > covered + 2 * step)
      warn(input + " ended early: " + std::to_string(frames_) + " frames decoded, up to " +
           std::to_string(covered).substr(0, 5) + " s of " +
           std::to_string(std::min(info.duration, sel_.range.end)).substr(0, 5) +
           " s (the file is cut short or damaged)");
    return report(info);
  }

  void warn(const std::string& line) const {
    if (events_.warning) events_.warning(line);
  }

  // The paths and the options (vb: null where no video is read or written).
  void check_paths(VideoBackend* vb) {
    check_options();
    if (sink_) return;
    if (r_.files.inputs.size() > 1 && !from_images_)
      throw Error(
          "a video is converted alone: give one video (or images to make one) and the output");
    for (const std::string& i : r_.files.inputs)
      if (from_images_ && is_video_job(i, ""))
        throw Error("input " + i + " is a video among images: give it alone");
    if (from_images_ && to_images_) throw InternalError("images to images are the image path's");
    if (to_images_) {
      if (from_images_ || r_.files.output.find("{n}") == std::string::npos)
        throw Error("output " + r_.files.output + " is not a video container's (" +
                    container_extensions() +
                    "): images of a video's frames need {n} in it, e.g. frames/{n}.png");
      return;
    }
    if (r_.files.output.find('{') != std::string::npos)
      throw Error("output " + r_.files.output +
                  ": a video's output is one video file (patterns such as {n} name images)");
    check_output_path(r_.files.output, r_.files.write.overwrite);
    for (const std::string& i : r_.files.inputs)
      if (same_file(i, r_.files.output)) throw Error("output " + r_.files.output + " is the input");
    const VideoContainer* c = video_container_of(r_.files.output);
    codec_ = &video_codec(r_.codec.empty() ? c->codec : r_.codec);
    if (const std::string why = vb->check_output(r_.files.output, codec_->encoder); !why.empty())
      throw Error("cannot write " + r_.files.output + ": " + why);
    const WriteOptions image_defaults;
    if (r_.files.write.quality != image_defaults.quality ||
        r_.files.write.subsampling != image_defaults.subsampling || r_.files.write.type)
      throw Error(
          "--quality, --subsampling and --depth are for images: a video keeps its pixel format "
          "(--crf, --bitrate and --preset set its quality)");
  }

  static std::string container_extensions() {
    std::string exts;
    for (const VideoContainer& k : video_containers())
      for (std::string_view e : k.extensions) exts += (exts.empty() ? "" : " ") + std::string(e);
    return exts;
  }

  void check_options() {
    if (!codec_) codec_ = &video_codec(r_.codec.empty() ? "h264" : r_.codec);
    if (!r_.bitrate.empty()) bitrate_ = parse_bitrate(r_.bitrate);
    if (r_.crf && (*r_.crf < 0 || *r_.crf > 63))
      throw Error(option_number("crf", std::to_string(*r_.crf)) + " is out of range (0 to 63)");
    if (r_.gop < 0 || r_.gop > 100000)
      throw Error(option_number("gop", std::to_string(r_.gop)) + " is out of range (0 to 100000)");
    check_video_options(r_.files.options, !to_images_);
  }

  // The source spec: --from (with a warning where the file's spherical metadata says another),
  // else the metadata's (its pose then levels the frames), else a 2:1 frame's equirect.
  ProjectionSpec source_spec(const VideoInfo& info) {
    const std::string& input = r_.files.inputs[0];
    const SphericalVideo& sv = info.spherical;
    if (!r_.files.from && sv.any()) {
      const ProjectionSpec from = parse_spec(spherical_source_spec(sv, info.size, input));
      pose_ = spherical_pose(sv);
      from_text_ = from.str() + " (its spherical metadata: " + spherical_text(sv) + ")";
      return from;
    }
    const ProjectionSpec from =
        strips_ && !r_.files.from
            ? parse_spec("gopro-max")
            : infer_source_spec(r_.files.from, input, info.size, std::nullopt);
    from_text_ = from.str();
    if (r_.files.from && sv.any()) {
      std::optional<ProjectionSpec> says;
      try {
        says = parse_spec(spherical_source_spec(sv, info.size, input));
      } catch (const Error&) {  // (metadata panoproj does not read, overridden)
      }
      if (!says || !same_spec(*says, from) || sv.yaw != 0 || sv.pitch != 0 || sv.roll != 0)
        warn(input + ": " + option_text("from") + " " + from_text_ +
             " is used; its spherical metadata says " + (says ? says->str() + " (" : "(") +
             spherical_text(sv) + ")");
    }
    return from;
  }

  // make_geometry, levelled by the metadata's pose (R_pose^T R_view).
  ConversionGeometry geometry(Size in, const ProjectionSpec& from, const ProjectionSpec& to,
                              const ConvertOptions& o) const {
    ConversionGeometry g = make_geometry(in, from, to, o);
    if (pose_) g.rotation = pose_->transpose() * g.rotation;
    return g;
  }

  // The geometry of the luma (and alpha, and RGB) planes; refuses sizes the subsampling cannot
  // hold and jobs over the memory budget.
  void plan_geometry(const VideoInfo& info) {
    if (info.size.width > 65536 || info.size.height > 65536)
      throw Error("cannot read " + r_.files.inputs[0] + ": its frames of " + size_text(info.size) +
                      " are over 65536 px a side",
                  ErrorKind::File);
    const ProjectionSpec from = source_spec(info);
    const ProjectionSpec to = parse_spec(r_.files.to);
    luma_ = fit_chroma(
        px_, output_subsampling(px_, !(to_images_ || sink_)), r_.files.options,
        [&](const ConvertOptions& o) { return geometry(info.size, from, to, o); },
        [this](const std::string& line) { warn(line); });
    const Size out = luma_->target_frame();
    const uint64_t plane_bytes =
        static_cast<uint64_t>(out.width * out.height) * (px_.bits > 8 ? 2 : 1);
    // Two frames in flight per stage, each about 3 planes' worth; the kept maps and taps (the
    // chroma planes' at most as many as the luma's).
    require_job_memory(
        *luma_, px_.planes, px_.bits > 8 ? PixelType::U16 : PixelType::U8, r_.files.options,
        add_bytes(12 * plane_bytes, 2 * static_cast<uint64_t>(kept_bytes_per_pixel(*luma_)) *
                                        static_cast<uint64_t>(out.width * out.height)),
        "the video's frames in flight and kept maps");
  }

  // The planes' converters (after the encoder: it may refuse the size before the maps are made).
  void plan_planes() {
    planes_.emplace(px_, *luma_, r_.files.options, r_.files.inputs[0], from_text_);
  }

  VideoSettings settings(const VideoInfo& info) const {
    VideoSettings s;
    s.codec = codec_->encoder;
    s.size = luma_->target_frame();
    s.pixels = px_;
    s.time_base[0] = info.time_base[0], s.time_base[1] = info.time_base[1];
    s.frame_rate[0] = info.frame_rate[0], s.frame_rate[1] = info.frame_rate[1];
    if (sel_.every > 1 && info.frame_rate[0] > 0) s.frame_rate[1] *= static_cast<int>(sel_.every);
    if (sel_.fps > 0)
      s.frame_rate[0] = static_cast<int>(std::llround(sel_.fps * 1000)), s.frame_rate[1] = 1000;
    s.crf = r_.crf ? static_cast<int>(*r_.crf) : -1;
    s.bitrate = bitrate_;
    s.preset = r_.preset;
    s.gop = static_cast<int>(r_.gop);
    s.spherical = target_spherical();
    return s;
  }

  // The output's spherical metadata, where its container and projection have one; else none,
  // with a warning saying why (none with --no-metadata).
  SphericalVideo target_spherical() const {
    if (!r_.files.keep_metadata) return {};  // (--no-metadata)
    std::string why;
    SphericalVideo v = spherical_of_target(*luma_, why);
    const std::string container = video_container_of(r_.files.output)->name;
    if (why.empty() && container != "mp4" && container != "mkv" && container != "webm")
      why = "libavformat 5.1 writes it into MP4, Matroska and WebM only (not " + container + ")";
    if (why.empty()) return v;
    warn(r_.files.output + ": no spherical metadata written: " + why);
    return {};
  }

  void run_frames(VideoWriter& writer) {
    std::array<VideoFrame, 2> in, out;
    const double expected = sel_.expected(reader_->info());
    FrameStages stages;
    stages.read = [&](size_t i) {
      const auto t0 = Clock::now();
      const bool more = picker_->next(*reader_, in[i % 2]);
      decode_seconds_ += since(t0);
      return more;
    };
    stages.convert = [&](size_t i) {
      check_interrupt();
      const auto t0 = Clock::now();
      const VideoFrame& f = in[i % 2];
      VideoFrame& o = out[i % 2];
      planes_->convert(f, o);
      last_pts_ = f.pts;
      convert_seconds_ += since(t0);
    };
    stages.write = [&](size_t i) {
      const auto t0 = Clock::now();
      writer.write(out[i % 2]);
      encode_seconds_ += since(t0);
    };
    const auto t0 = Clock::now();
    stages.written = [&](size_t i) {
      frames_ = static_cast<int64_t>(i) + 1;
      const double fraction =
          expected > 0 ? std::min(1.0, static_cast<double>(frames_) / expected) : 0;
      if (events_.status) {
        char s[64];
        std::snprintf(s, sizeof s, "frame %lld, %.1f fps", static_cast<long long>(frames_),
                      static_cast<double>(frames_) / std::max(1e-9, since(t0)));
        events_.status(fraction, s);
      } else if (events_.progress && expected > 0) {
        events_.progress(fraction);
      }
    };
    run_frame_pipeline(kUnknownFrames, 1, stages);
  }

  std::string input_text() const {
    if (r_.files.inputs.size() == 1) return r_.files.inputs[0];
    return r_.files.inputs[0] + " ... " + r_.files.inputs.back() + " (" +
           std::to_string(r_.files.inputs.size()) + " images)";
  }

  Report report(const VideoInfo& info) const {
    const Size out = luma_->target_frame();
    const double fps = seconds_ > 0 ? static_cast<double>(frames_) / seconds_ : 0;
    char line[2048];
    std::snprintf(
        line, sizeof line,
        "%s (%s %s %s, %s) -> %s (%s %s, %s): %lld frames in %.2f s (%.1f fps; decode %.2f s, "
        "convert "
        "%.2f s, encode %.2f s), %s, antialias %s, %s engine (%s), chroma %s%s",
        input_text().c_str(), size_text(info.size).c_str(), info.codec.c_str(),
        px_.pixel_format.c_str(), from_text_.c_str(), r_.files.output.c_str(),
        size_text(out).c_str(),
        to_images_ ? format_of_path(r_.files.output).title : codec_->encoder, r_.files.to.c_str(),
        static_cast<long long>(frames_), seconds_, fps, decode_seconds_, convert_seconds_,
        encode_seconds_, name_of(r_.files.options.interp),
        name_of(antialias_of(r_.files.options)).c_str(), name_of(r_.files.options.engine),
        simd_target(),
        planes_->subsampled() ? siting_name(px_.siting)
        : px_.packed          ? "in RGB"
                              : "not subsampled",
        spherical_.any() ? (", spherical metadata " + spherical_text(spherical_)).c_str() : "");
    if (events_.line) events_.line(line);
    return {
        {"input", {r_.files.inputs[0]}},
        {"output", {r_.files.output}},
        {"input_size", report_size(info.size)},
        {"output_size", report_size(out)},
        {"frames", {frames_}},
        {"seconds", {seconds_}},
        {"decode_seconds", {decode_seconds_}},
        {"convert_seconds", {convert_seconds_}},
        {"encode_seconds", {encode_seconds_}},
        {"pixel_format", {px_.pixel_format}},
        {"codec", {std::string(codec_->encoder)}},
        {"concealed", {reader_->concealed()}},
        {"src", {from_text_}},
        {"dst", {r_.files.to}},
        {"spherical_metadata", {spherical_.any() ? spherical_text(spherical_) : std::string()}}};
  }

  const VideoRequest& r_;
  const JobEvents& events_;
  VideoWriter* sink_;
  bool from_images_ = false, to_images_ = false;
  bool strips_ = false;  // a GoPro MAX's two strip streams read as one frame
  const VideoCodec* codec_ = nullptr;
  int64_t bitrate_ = 0;
  std::unique_ptr<VideoReader> reader_;
  VideoPixels px_;
  std::string from_text_;
  std::optional<Eigen::Matrix3d> pose_;  // the metadata's, frame -> level
  SphericalVideo spherical_;             // the output's, as its writer wrote it
  std::optional<ConversionGeometry> luma_;
  std::optional<VideoPlanes> planes_;
  int64_t frames_ = 0, last_pts_ = 0;
  FrameSelection sel_ = r_.frames;  // (fps cleared for images to a video: their rate)
  std::optional<FramePicker> picker_;
  double seconds_ = 0, decode_seconds_ = 0, convert_seconds_ = 0, encode_seconds_ = 0;
};

}  // namespace

bool is_video_job(const std::string& input, const std::string& output) {
  return is_video_file(input) || video_container_of(output);
}

Report convert_video(const VideoRequest& request, const JobEvents& events, VideoWriter* sink) {
  return VideoJob(request, events, sink).run();
}

}  // namespace panoproj
