// Stitch's video inputs (stitch_video.hpp).
#include "jobs/stitch/stitch_video.hpp"

#include <unistd.h>

#include <cstring>
#include <memory>
#include <vector>

#include "base/input_check.hpp"
#include "base/parallel.hpp"
#include "io/atomic_output.hpp"
#include "io/video_formats.hpp"
#include "io/video_plugin.hpp"
#include "jobs/stitch/panorama.hpp"
#include "jobs/video_spherical.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {
namespace {

std::unique_ptr<VideoReader> open_video(const std::string& path, bool copy) {
  (void)read_head(path, 16, "input", "a video file");  // (a regular file, before libavformat)
  return video_backend("reading " + path).open(path, -1, copy, VideoRange{}, true);
}

std::string rate_text(const VideoInfo& v) {
  return v.frame_rate[1] > 0
             ? std::to_string(v.frame_rate[0]) + "/" + std::to_string(v.frame_rate[1]) + " fps"
             : "an unknown rate";
}

// The panorama's colour samples (its alpha dropped: a video has none), packed.
void colour_of(const Image& pano, Image& out) {
  const int colour = pano.channels() - 1, c = colour == 1 ? 3 : colour;
  if (out.size() != pano.size() || out.channels() != c || out.type() != pano.type())
    out = Image(pano.size(), c, pano.type(), -1, Image::Unfilled{});
  const size_t bytes = bytes_of(pano.type());
  parallel_rows(pano.height(), 0, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      const unsigned char* in = pano.row(y);
      unsigned char* o = out.row(y);
      for (int64_t x = 0; x < pano.width(); ++x, in += bytes * (colour + 1), o += bytes * c)
        for (int k = 0; k < c; ++k)
          std::memcpy(o + bytes * k, in + bytes * (colour == 1 ? 0 : k), bytes);
    }
  });
}

}  // namespace

ImageInfo video_frames_info(const std::string& path) {
  const VideoInfo v = open_video(path, false)->info();
  return {v.size, v.pixels.alpha ? 4 : 3, v.pixels.bits > 8 ? PixelType::U16 : PixelType::U8,
          "video", false};
}

void check_video_output(const Arguments& args, const StitchPlan& plan) {
  const VideoContainer* c = plan.panorama.empty() ? nullptr : video_container_of(plan.panorama);
  if (!c)
    throw Error("the inputs are videos (" + plan.videos[0] +
                "): give a video output, e.g. pano.mp4" +
                (plan.panorama == "(array)" ? " (arrays take images)" : ""));
  const WriteOptions image_defaults, given = args.write();
  if (given.quality != image_defaults.quality || given.subsampling != image_defaults.subsampling ||
      plan.depth || args.optional_text("compression"))
    throw Error("--quality, --subsampling, --depth and --compression are for images: " +
                plan.panorama + " is a video (its frames keep their inputs' depth)");
  const std::string why = video_backend("writing " + plan.panorama)
                              .check_output(plan.panorama, video_codec(c->codec).encoder);
  if (!why.empty()) throw Error("cannot write " + plan.panorama + ": " + why);
}

Report run_stitch_video(StitchPlan plan, const JobEvents& events) {
  const size_t n = plan.videos.size();
  std::vector<std::unique_ptr<VideoReader>> readers;
  for (size_t k = 0; k < n; ++k) readers.push_back(open_video(plan.videos[k], k == 0));
  const VideoInfo& first = readers[0]->info();
  for (size_t k = 1; k < n; ++k) {
    const VideoInfo& v = readers[k]->info();
    if (static_cast<int64_t>(v.frame_rate[0]) * first.frame_rate[1] !=
        static_cast<int64_t>(first.frame_rate[0]) * v.frame_rate[1])
      throw Error(plan.videos[k] + " runs at " + rate_text(v) + ", " + plan.videos[0] + " at " +
                  rate_text(first) + " (a rig's videos are frames in step: give them one rate)");
    if (v.frames > 0 && first.frames > 0 && v.frames != first.frames)
      throw Error(plan.videos[k] + " has " + std::to_string(v.frames) + " frames, " +
                  plan.videos[0] + " " + std::to_string(first.frames) +
                  " (a rig's videos are frames in step: cut them to one length)");
  }
  const PixelType type = panorama_type(plan);
  VideoBackend& vb = video_backend("writing " + plan.panorama);
  VideoSettings s;
  s.codec = video_codec(video_container_of(plan.panorama)->codec).encoder;
  s.size = plan.canvas;
  VideoPixels& p = s.pixels;
  p.packed = true, p.rgb = true, p.full_range = true, p.planes = 1;
  p.bits = type == PixelType::U16 ? 16 : 8;
  p.pixel_format = p.bits > 8 ? "rgb48le" : "rgb24";
  s.time_base[0] = first.time_base[0], s.time_base[1] = first.time_base[1];
  s.frame_rate[0] = first.frame_rate[0], s.frame_rate[1] = first.frame_rate[1];
  s.threads = plan.options.threads;
  const Projection pano = make_projection(*plan.pano, plan.canvas);
  std::string why;
  s.spherical =
      spherical_of_target(ConversionGeometry{pano, pano, Eigen::Matrix3d::Identity()}, why);
  if (!why.empty() && events.warning)
    events.warning(plan.panorama + ": no spherical metadata written: " + why);
  if (type == PixelType::F32)
    throw Error(plan.panorama + ": float samples (a video's are integers)");
  OutputSet set(plan.overwrite);
  const int fd = set.open(plan.panorama);
  int64_t frames = 0;
  try {
    auto writer = vb.create(fd, plan.panorama, s, readers[0].get());
    if (events.warning)
      for (const std::string& note : writer->notes()) events.warning(note);
    std::vector<VideoFrame> in(n);
    VideoFrame out;
    while (true) {
      check_interrupt();
      std::vector<size_t> ended;
      for (size_t k = 0; k < n; ++k)
        if (!readers[k]->read(in[k])) ended.push_back(k);
      if (ended.size() == n) break;
      if (!ended.empty())
        throw Error(plan.videos[ended[0]] + " ended after " + std::to_string(frames) +
                    " frames while the other inputs go on (a rig's videos are frames in step: "
                    "cut them to one length)");
      std::vector<std::shared_ptr<const Image>> frame(n);
      for (size_t k = 0; k < n; ++k) frame[k] = std::make_shared<Image>(std::move(in[k].planes[0]));
      for (StitchLayer& l : plan.layers) l.frame = frame[static_cast<size_t>(l.input)];
      colour_of(blend_panorama(plan, type, nullptr, nullptr).image, out.planes[0]);
      out.pts = in[0].pts;
      writer->write(out);
      ++frames;
      if (events.status)
        events.status(
            first.frames > 0 ? static_cast<double>(frames) / static_cast<double>(first.frames) : 0,
            "frame " + std::to_string(frames));
    }
    if (frames == 0)
      throw Error("cannot read " + plan.videos[0] + ": no frame could be decoded", ErrorKind::File);
    writer->finish();
  } catch (...) {
    ::close(fd);
    throw;
  }
  set.seal(fd, plan.panorama);
  set.commit();
  if (events.line)
    events.line(plan.panorama + ": " + std::to_string(frames) + " frames of " +
                size_text(plan.canvas) + ", " + std::to_string(plan.layers.size()) + " lenses, " +
                (plan.blend.multiband ? "multiband" : "feather"));
  return {{"output", {plan.panorama}},
          {"canvas", report_size(plan.canvas)},
          {"frames", {frames}},
          {"blend", {std::string(plan.blend.multiband ? "multiband" : "feather")}}};
}

}  // namespace panoproj
