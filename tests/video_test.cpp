// Videos through the convert job, checked against independent oracles: clips made at test time
// by the ffmpeg command, decoded back by it to raw planes (FFV1 is lossless); each output frame's
// luma equals the per-image conversion of the decoded luma as a one-channel image (10-bit as
// 16-bit clamped to 1023, video black where no source); each chroma sample is within 1 LSB of the
// reference sampler at the exact map of its sited place, derived from the luma geometry; frame
// count, pts and the audio's packets are the input's (ffprobe, ffmpeg's streamhash).
#include <gtest/gtest.h>

extern "C" {
#include <libavformat/avformat.h>
}

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "av_support.hpp"
#include "geometry/source_taps.hpp"
#include "io/video_plugin.hpp"
#include "job_support.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "sampling/reference_sampler.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

namespace fs = std::filesystem;

using test::shell;

class Clips : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("panoproj_video_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string p(const std::string& name) const { return (dir_ / name).string(); }

  // A 256x128 equirect clip of 12 frames made by ffmpeg: a blurred test pattern (smooth), or
  // what `source` says.
  std::string clip(
      const std::string& name, const std::string& codec_args, const std::string& more_inputs = "",
      const std::string& source = "testsrc2=size=256x128:rate=24:duration=0.5,gblur=sigma=1.5") {
    const std::string out = p(name);
    const std::string cmd = "ffmpeg -v error -y -f lavfi -i '" + source + "' " + more_inputs + " " +
                            codec_args + " '" + out + "'";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return out;
  }

  // The frames' planes as ffmpeg decodes them, in pixel format fmt (planar, chroma planes
  // halved across and, but for 4:2:2, down), 16-bit samples where bits > 8.
  std::vector<std::array<Image, 3>> planes(const std::string& file, const char* fmt, Size size,
                                           int bits) const {
    const std::string raw = p("raw.yuv");
    const std::string cmd = "ffmpeg -v error -y -i '" + file + "' -vsync 0 -f rawvideo -pix_fmt " +
                            fmt + " '" + raw + "'";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    std::ifstream in(raw, std::ios::binary);
    const PixelType type = bits > 8 ? PixelType::U16 : PixelType::U8;
    const bool h422 = std::string(fmt).find("422") != std::string::npos;
    const Size c{size.width / 2, h422 ? size.height : size.height / 2};
    std::vector<std::array<Image, 3>> frames;
    for (;;) {
      std::array<Image, 3> f{Image(size, 1, type), Image(c, 1, type), Image(c, 1, type)};
      for (Image& im : f)
        in.read(reinterpret_cast<char*>(im.data()), static_cast<std::streamsize>(im.byte_size()));
      if (!in) break;
      frames.push_back(std::move(f));
    }
    return frames;
  }

  std::string pts(const std::string& file) const {
    return shell("ffprobe -v error -select_streams v -show_entries frame=pts_time -of csv=p=0 '" +
                 file + "'");
  }

  Report convert(std::vector<std::pair<const char*, OptionValue>> args) const {
    return test::run_job("convert", test::job_args("convert", std::move(args)));
  }

  // `in` converted to `dst` at `size` into an FFV1 file (lossless), antialiasing off.
  Report ffv1(const std::string& in, const std::string& out, const std::string& dst,
              const std::string& size) const {
    return convert({{"inputs", std::vector<std::string>{in}},
                    {"output", out},
                    {"dst", dst},
                    {"size", size},
                    {"antialias", std::string("off")},
                    {"codec", std::string("ffv1")}});
  }

  fs::path dir_;
};

double sample_at(const Image& plane, const Projection& proj, double x, double y) {
  const SourceTaps taps(proj);
  const uint8_t ok = 1;
  unsigned char out[2];
  sample_reference(plane, taps, Interp::Bicubic, &x, &y, &ok, 1, out);
  return test::get(Image::view(out, {1, 1}, 1, plane.type()), 0, 0, 0);
}

TEST_F(Clips, TenBitLumaIsThePerImageConversionAndChromaSitsWhereItSays) {
  for (const char* siting : {"left", "topleft"}) {
    const std::string in =
        clip(std::string("in_") + siting + ".mkv",
             std::string("-c:v ffv1 -pix_fmt yuv420p10le -chroma_sample_location ") + siting);
    const std::string out = p(std::string("out_") + siting + ".mkv");
    const Report r = ffv1(in, out, "fisheye:fov=200", "128x128");
    ASSERT_EQ(test::integer(r, "frames"), 12);
    const auto src = planes(in, "yuv420p10le", {256, 128}, 10);
    const auto dst = planes(out, "yuv420p10le", {128, 128}, 10);
    ASSERT_EQ(src.size(), 12u);
    ASSERT_EQ(dst.size(), 12u);
    EXPECT_EQ(pts(in), pts(out));
    ConvertOptions o;
    o.size = Size{128, 128}, o.antialias = Antialias{};
    const ConversionGeometry g =
        make_geometry({256, 128}, parse_spec("equirect"), parse_spec("fisheye:fov=200"), o);
    const Projection chroma_source = rescaled(g.source, {128, 64});
    const bool top = std::string(siting) == "topleft";
    for (size_t f = 0; f < src.size(); f += 5) {
      // Luma: the per-image path on the plane alone, clamped to 10 bits, black (64) where none.
      Image luma =
          panoproj::convert(src[f][0], parse_spec("equirect"), parse_spec("fisheye:fov=200"), o);
      int64_t differ = 0, blacks = 0;
      for (int64_t y = 0; y < 128; ++y)
        for (int64_t x = 0; x < 128; ++x) {
          double sx, sy;
          const bool has = source_pixel(g.source, g.target, g.rotation, x + 0.5, y + 0.5, sx, sy);
          const double want = has ? std::min(1023.0, test::get(luma, x, y, 0)) : 64.0;
          blacks += !has;
          differ += test::get(dst[f][0], x, y, 0) != want;
        }
      EXPECT_EQ(differ, 0) << siting << " frame " << f;
      EXPECT_GT(blacks, 100) << "the fisheye's corners are outside its field";
      // Chroma: sample (i, j) sits at luma (2i + 0.5, 2j + 1) (left) or (2i + 0.5, 2j + 0.5)
      // (topleft); the source's chroma sample k at luma 2k + 0.5 (and rows alike).
      double most = 0;
      for (int c = 1; c < 3; ++c)
        for (int64_t j = 0; j < 64; ++j)
          for (int64_t i = 0; i < 64; ++i) {
            double sx, sy;
            if (!source_pixel(g.source, g.target, g.rotation, 2.0 * i + 0.5,
                              2.0 * j + (top ? 0.5 : 1.0), sx, sy)) {
              EXPECT_EQ(test::get(dst[f][c], i, j, 0), 512.0);
              continue;
            }
            const double cx = (sx - 0.5) / 2 + 0.5, cy = top ? (sy - 0.5) / 2 + 0.5 : sy / 2;
            const double want =
                std::clamp(sample_at(src[f][c], chroma_source, cx, cy), 0.0, 1023.0);
            most = std::max(most, std::fabs(test::get(dst[f][c], i, j, 0) - want));
          }
      EXPECT_LE(most, 1.0) << siting << " frame " << f;
    }
  }
}

// 4:2:2 (ProRes', a camera's MJPEG): a cube's cells in the chroma planes are half as wide as
// high; each chroma sample at its sited place, derived from the luma geometry, as above.
TEST_F(Clips, FourTwoTwoChromaOfACubeSitsWhereItSays) {
  const std::string in = clip("in.mkv", "-c:v ffv1 -pix_fmt yuv422p10le");
  const std::string out = p("out.mkv");
  const Report r = ffv1(in, out, "cubemap:layout=3x2", "192x128");
  ASSERT_EQ(test::integer(r, "frames"), 12);
  const auto src = planes(in, "yuv422p10le", {256, 128}, 10);
  const auto dst = planes(out, "yuv422p10le", {192, 128}, 10);
  ASSERT_EQ(dst.size(), 12u);
  ConvertOptions o;
  o.size = Size{192, 128}, o.antialias = Antialias{};
  const ConversionGeometry g =
      make_geometry({256, 128}, parse_spec("equirect"), parse_spec("cubemap:layout=3x2"), o);
  const Projection chroma_source = rescaled(g.source, {128, 128});
  for (size_t f = 0; f < src.size(); f += 11) {
    const Image luma =
        panoproj::convert(src[f][0], parse_spec("equirect"), parse_spec("cubemap:layout=3x2"), o);
    int64_t differ = 0;
    for (int64_t y = 0; y < 128; ++y)
      for (int64_t x = 0; x < 192; ++x)
        differ += test::get(dst[f][0], x, y, 0) != std::min(1023.0, test::get(luma, x, y, 0));
    EXPECT_EQ(differ, 0) << "frame " << f;
    // Chroma sample (i, j) sits at luma (2i + 0.5, j + 0.5) (left); the source's k at 2k + 0.5.
    double most = 0;
    for (int c = 1; c < 3; ++c)
      for (int64_t j = 0; j < 128; ++j)
        for (int64_t i = 0; i < 96; ++i) {
          double sx, sy;
          ASSERT_TRUE(source_pixel(g.source, g.target, g.rotation, 2.0 * i + 0.5, j + 0.5, sx, sy));
          const double want = std::clamp(
              sample_at(src[f][c], chroma_source, (sx - 0.5) / 2 + 0.5, sy), 0.0, 1023.0);
          most = std::max(most, std::fabs(test::get(dst[f][c], i, j, 0) - want));
        }
    EXPECT_LE(most, 1.0) << "frame " << f;
  }
}

// FFmpeg's EAC frame (border=ffmpeg) has 2-px borders in every plane's own pixels, as v360
// converts each plane alone: centre-sited chroma is the per-image conversion of the chroma
// plane to that frame at the plane's size.
TEST_F(Clips, FfmpegEacChromaIsEachPlaneLaidOutAlone) {
  const std::string in =
      clip("in.mkv", "-c:v ffv1 -pix_fmt yuv420p10le -chroma_sample_location center");
  const std::string out = p("out.mkv");
  const char* eac = "cubemap:layout=eac,border=ffmpeg";
  ffv1(in, out, eac, "192x128");
  const auto src = planes(in, "yuv420p10le", {256, 128}, 10);
  const auto dst = planes(out, "yuv420p10le", {192, 128}, 10);
  ASSERT_EQ(dst.size(), 12u);
  for (int c = 0; c < 3; ++c) {
    ConvertOptions o;
    o.size = c ? Size{96, 64} : Size{192, 128}, o.antialias = Antialias{};
    const Image want = panoproj::convert(src[6][c], parse_spec("equirect"), parse_spec(eac), o);
    int64_t differ = 0;
    for (int64_t y = 0; y < o.size->height; ++y)
      for (int64_t x = 0; x < o.size->width; ++x)
        differ += test::get(dst[6][c], x, y, 0) != std::min(1023.0, test::get(want, x, y, 0));
    EXPECT_EQ(differ, 0) << "plane " << c;
  }
}

TEST_F(Clips, TenBitOvershootIsClampedTo1023) {
  // Stripes of 0 and 1023: bicubic rings past both ends.
  const std::string in = clip("sharp.mkv", "-c:v ffv1 -pix_fmt yuv420p10le", "",
                              "nullsrc=size=256x128:rate=24:duration=0.1,format=yuv420p10le,"
                              "geq=lum=if(gt(mod(X+Y\\,16)\\,8)\\,1023\\,0):cb=512:cr=512");
  const std::string out = p("sharp_out.mkv");
  convert({{"inputs", std::vector<std::string>{in}},
           {"output", out},
           {"dst", std::string("equirect")},
           {"yaw", 10.3},
           {"codec", std::string("ffv1")}});
  const auto src = planes(in, "yuv420p10le", {256, 128}, 10),
             dst = planes(out, "yuv420p10le", {256, 128}, 10);
  ASSERT_FALSE(dst.empty());
  ConvertOptions o;
  o.yaw = 10.3;
  const Image luma =
      panoproj::convert(src[0][0], parse_spec("equirect"), parse_spec("equirect"), o);
  int64_t over = 0, differ = 0;
  for (int64_t y = 0; y < 128; ++y)
    for (int64_t x = 0; x < 256; ++x) {
      over += test::get(luma, x, y, 0) > 1023;
      differ += test::get(dst[0][0], x, y, 0) != std::min(1023.0, test::get(luma, x, y, 0));
    }
  EXPECT_GT(over, 100) << "the kernel overshoots";
  EXPECT_EQ(differ, 0);
}

// A copy of `video`'s stream with a GoPro telemetry stream (data, tag gpmd) beside it: packet i
// holds `payload(i)` at the video packet's time. (The ffmpeg command cannot write one.)
void add_gpmd(const std::string& video, const std::string& out,
              const std::function<std::string(int)>& payload) {
  AVFormatContext* in = nullptr;
  ASSERT_GE(avformat_open_input(&in, video.c_str(), nullptr, nullptr), 0);
  ASSERT_GE(avformat_find_stream_info(in, nullptr), 0);
  AVFormatContext* o = nullptr;
  ASSERT_GE(avformat_alloc_output_context2(&o, nullptr, nullptr, out.c_str()), 0);
  AVStream* v = avformat_new_stream(o, nullptr);
  avcodec_parameters_copy(v->codecpar, in->streams[0]->codecpar);
  v->codecpar->codec_tag = 0;
  v->time_base = in->streams[0]->time_base;
  AVStream* d = avformat_new_stream(o, nullptr);
  d->codecpar->codec_type = AVMEDIA_TYPE_DATA;
  d->codecpar->codec_id = AV_CODEC_ID_BIN_DATA;
  d->codecpar->codec_tag = MKTAG('g', 'p', 'm', 'd');
  d->time_base = in->streams[0]->time_base;
  ASSERT_GE(avio_open(&o->pb, out.c_str(), AVIO_FLAG_WRITE), 0);
  ASSERT_GE(avformat_write_header(o, nullptr), 0);
  AVPacket* p = av_packet_alloc();
  for (int i = 0; av_read_frame(in, p) >= 0;) {
    if (p->stream_index != 0) {  // (the tmcd track: not carried here)
      av_packet_unref(p);
      continue;
    }
    const int64_t dts = p->dts, duration = p->duration;
    av_packet_rescale_ts(p, in->streams[0]->time_base, v->time_base);
    p->stream_index = 0;
    ASSERT_GE(av_interleaved_write_frame(o, p), 0);
    const std::string bytes = payload(i);
    AVPacket* q = av_packet_alloc();
    av_new_packet(q, static_cast<int>(bytes.size()));
    std::memcpy(q->data, bytes.data(), bytes.size());
    q->pts = q->dts =
        av_rescale_q(std::max<int64_t>(dts, 0) + i, in->streams[0]->time_base, d->time_base);
    q->duration = duration, q->stream_index = 1;
    ASSERT_GE(av_interleaved_write_frame(o, q), 0);
    av_packet_free(&q);
    ++i;
  }
  av_write_trailer(o);
  av_packet_free(&p);
  avio_closep(&o->pb);
  avformat_free_context(o);
  avformat_close_input(&in);
}

TEST_F(Clips, GoProTelemetryIsCopiedByteForByteAndATimecodeMadeAgain) {
  const std::string plain =
      clip("plain.mp4", "-c:v libx264 -pix_fmt yuv420p -timecode 01:02:03:04");
  const std::string in = p("gopro.mp4"), out = p("gopro_out.mp4");
  add_gpmd(plain, in, [](int i) {
    return "DEVC" + std::string(static_cast<size_t>(5 + i), static_cast<char>('a' + i));
  });
  const std::vector<std::string> telemetry = test::stream_packets(in, AVMEDIA_TYPE_DATA);
  ASSERT_EQ(telemetry.size(), 12u);
  convert({{"inputs", std::vector<std::string>{in}},
           {"output", out},
           {"dst", std::string("equirect")}});
  EXPECT_EQ(test::stream_packets(out, AVMEDIA_TYPE_DATA), telemetry);
  EXPECT_NE(
      shell("ffprobe -v error -show_entries stream=codec_tag_string -of csv=p=0 '" + out + "'")
          .find("gpmd"),
      std::string::npos);
  // A timecode on the input (a tmcd track) comes out as the same start timecode.
  const std::string tc = shell(
      "ffprobe -v error -show_entries format_tags=timecode:stream_tags=timecode -of csv=p=0 '" +
      plain + "'");
  EXPECT_NE(tc.find("01:02:03:04"), std::string::npos) << tc;
  const std::string tc_out = p("tc_out.mp4");
  convert({{"inputs", std::vector<std::string>{plain}},
           {"output", tc_out},
           {"dst", std::string("equirect")}});
  EXPECT_NE(
      shell("ffprobe -v error -show_entries stream_tags=timecode -of csv=p=0 '" + tc_out + "'")
          .find("01:02:03:04"),
      std::string::npos);
  // Into Matkroska the telemetry is dropped (it takes no data stream), with a warning naming it.
  std::vector<std::string> warnings;
  JobEvents events;
  events.warning = [&](const std::string& w) { warnings.push_back(w); };
  job_named("convert").run(test::job_args("convert", {{"inputs", std::vector<std::string>{in}},
                                                      {"output", p("gopro.mkv")},
                                                      {"dst", std::string("equirect")}}),
                           events);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("gpmd"), std::string::npos) << warnings[0];
  EXPECT_TRUE(test::stream_packets(p("gopro.mkv"), AVMEDIA_TYPE_DATA).empty());
}

TEST_F(Clips, PartsOfAClipJoinIntoTheWhole) {
  // 2 s at 24 fps, a keyframe every 10 frames: parts cut between keyframes decode from the one
  // before; each frame belongs to one part, converted as in the whole.
  const std::string in = clip("long.mkv", "-c:v ffv1 -g 10 -pix_fmt yuv420p", "",
                              "testsrc2=size=256x128:rate=24:duration=2,gblur=sigma=1");
  auto run = [&](const std::string& out, std::vector<std::pair<const char*, OptionValue>> more) {
    std::vector<std::pair<const char*, OptionValue>> args = {
        {"inputs", std::vector<std::string>{in}},
        {"output", p(out)},
        {"dst", std::string("cubemap:layout=3x2")},
        {"size", std::string("192x128")},
        {"codec", std::string("ffv1")}};
    for (auto& m : more) args.push_back(m);
    return test::integer(convert(args), "frames");
  };
  EXPECT_EQ(run("whole.mkv", {}), 48);
  EXPECT_EQ(run("a.mkv", {{"duration", std::string("0.7")}}), 17);  // frames 0..16 (t < 0.7)
  EXPECT_EQ(run("b.mkv", {{"start", std::string("0.7")}, {"duration", std::string("0:00.8")}}), 19);
  EXPECT_EQ(run("c.mkv", {{"start", std::string("1.5")}}), 12);
  const auto whole = planes(p("whole.mkv"), "yuv420p", {192, 128}, 8);
  std::vector<std::array<Image, 3>> joined;
  for (const char* part : {"a.mkv", "b.mkv", "c.mkv"})
    for (auto& f : planes(p(part), "yuv420p", {192, 128}, 8)) joined.push_back(std::move(f));
  ASSERT_EQ(joined.size(), whole.size());
  for (size_t f = 0; f < whole.size(); ++f)
    for (int c = 0; c < 3; ++c)
      EXPECT_TRUE(joined[f][c] == whole[f][c]) << "frame " << f << " plane " << c;
  // A part's times count from its start.
  EXPECT_EQ(pts(p("c.mkv")).substr(0, 6), "0.0000") << pts(p("c.mkv"));
  // Frames picked: every 10th, or at most 5 a second.
  EXPECT_EQ(run("every.mkv", {{"every", int64_t{10}}}), 5);
  EXPECT_EQ(run("fps.mkv", {{"fps", std::string("5")}}), 10);
  EXPECT_THROW(run("none.mkv", {{"start", std::string("3")}}), Error);
  EXPECT_FALSE(fs::exists(p("none.mkv")));
}

TEST_F(Clips, FramesToImagesAndImagesToAVideo) {
  const std::string in = clip("in.mp4", "-c:v libx264 -crf 12 -pix_fmt yuv420p");
  fs::create_directories(p("frames"));
  // Every 4th frame as a PNG: the per-image conversion of ffmpeg's RGB decode of that frame.
  const Report r = convert({{"inputs", std::vector<std::string>{in}},
                            {"output", p("frames/{n}.png")},
                            {"dst", std::string("pinhole:hfov=90")},
                            {"size", std::string("128x96")},
                            {"every", int64_t{4}}});
  EXPECT_EQ(test::integer(r, "frames"), 3);
  std::vector<std::string> images;
  for (int n = 0; n < 3; ++n) images.push_back(p("frames/" + std::to_string(n) + ".png"));
  EXPECT_FALSE(fs::exists(p("frames/3.png")));
  ASSERT_EQ(std::system(("ffmpeg -v error -y -i '" + in +
                         "' -vf select='not(mod(n\\,4))' -vsync 0 -pix_fmt rgb24 '" +
                         p("ref%d.png") + "'")
                            .c_str()),
            0);
  ConvertOptions o;
  o.size = Size{128, 96};
  for (int n = 0; n < 3; ++n) {
    const Image want = panoproj::convert(read_image(p("ref" + std::to_string(n + 1) + ".png")),
                                         parse_spec("equirect"), parse_spec("pinhole:hfov=90"), o);
    EXPECT_GT(test::psnr(read_image(images[static_cast<size_t>(n)]), want), 38.0) << n;
  }
  // The images back to a video at 2 frames a second: their number, rate and times, and pixels.
  const std::string out = p("from_images.mkv");
  const Report v = convert({{"inputs", images},
                            {"output", out},
                            {"src", std::string("pinhole:hfov=90")},
                            {"dst", std::string("pinhole:hfov=90")},
                            {"size", std::string("128x96")},
                            {"fps", std::string("2")},
                            {"codec", std::string("ffv1")}});
  EXPECT_EQ(test::integer(v, "frames"), 3);
  EXPECT_EQ(pts(out), "0.000000\n0.500000\n1.000000\n");
  const auto back = planes(out, "yuv420p", {128, 96}, 8);
  ASSERT_EQ(back.size(), 3u);
  ASSERT_EQ(std::system(("ffmpeg -v error -y -i '" + out + "' -vsync 0 -pix_fmt rgb24 '" +
                         p("back%d.png") + "'")
                            .c_str()),
            0);
  for (int n = 0; n < 3; ++n)
    EXPECT_GT(test::psnr(read_image(p("back" + std::to_string(n + 1) + ".png")),
                         read_image(images[static_cast<size_t>(n)])),
              30.0);
  // Images unlike each other are refused naming the first that differs.
  write_image(Image({64, 32}, 3, PixelType::U8), p("small.png"), {});
  try {
    convert({{"inputs", std::vector<std::string>{images[0], p("small.png")}},
             {"output", p("mixed.mkv")},
             {"dst", std::string("equirect")},
             {"src", std::string("pinhole:hfov=90")}});
    ADD_FAILURE() << "mixed sizes converted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("small.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(p("mixed.mkv")));
}

// Files of a folder, by path below it, and their bytes.
std::map<std::string, std::string> folder_files(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) {
      std::ifstream f(e.path(), std::ios::binary);
      files[fs::relative(e.path(), dir).string()] =
          std::string(std::istreambuf_iterator<char>(f), {});
    }
  return files;
}

TEST_F(Clips, ViewsOfAVideoAreTheViewsOfItsFramesAsImages) {
  const std::string in = clip("walk.mp4", "-c:v libx264 -crf 12 -pix_fmt yuv420p");
  // Frames 0, 4 and 8 decoded as RGB (the reader the job uses; its RGB is checked against
  // ffmpeg's in FramesToImagesAndImagesToAVideo), written losslessly as the job names them.
  fs::create_directories(p("frames"));
  std::vector<std::string> images;
  {
    auto reader = video_backend("test").open(in, -1, false, {}, true);
    VideoFrame f;
    for (int n = 0; reader->read(f); ++n)
      if (n % 4 == 0) {
        char name[32];
        std::snprintf(name, sizeof name, "frames/walk_%06d.png", n / 4);
        images.push_back(p(name));
        write_image(f.planes[0], images.back(), {});
      }
  }
  ASSERT_EQ(images.size(), 3u);
  auto views = [&](std::vector<std::string> inputs, const std::string& out,
                   std::vector<std::pair<const char*, OptionValue>> more) {
    std::vector<std::pair<const char*, OptionValue>> args = {
        {"images", std::move(inputs)},
        {"out_dir", p(out)},
        {"size", std::string("48x48")},
        {"format", std::string("png")},
        {"rig", std::string("cube+ring:n=3,fov=100,pitch=20")}};
    for (auto& m : more) args.push_back(m);
    return test::run_job("views", test::job_args("views", std::move(args)));
  };
  const Report r = views({in}, "from_video", {{"every", int64_t{4}}});
  views(images, "from_images", {});
  EXPECT_EQ(test::integer(r, "images"), 27);
  auto a = folder_files(p("from_video")), b = folder_files(p("from_images"));
  a.erase("panoproj-output.json"), b.erase("panoproj-output.json");  // (they list the inputs)
  EXPECT_EQ(a.size(), 27u + 6u);  // (images; cameras, images, rigs, frames, points3D, transforms)
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [path, bytes] : a) EXPECT_TRUE(b.count(path) && b[path] == bytes) << path;
  // At most 8 frames a second: frames 0, 3, 6, 9 of 24 a second.
  EXPECT_EQ(test::integer(views({in}, "fps", {{"fps", std::string("8")}}), "images"), 36);
  // A video with other inputs, and a video's options for images, are refused; nothing written.
  EXPECT_THROW(views({in, images[0]}, "mixed", {}), Error);
  EXPECT_THROW(views(images, "images_start", {{"start", std::string("1")}}), Error);
  EXPECT_THROW(views({in}, "past_end", {{"start", std::string("9")}}), Error);
  EXPECT_FALSE(fs::exists(p("mixed")) || fs::exists(p("images_start")) ||
               fs::exists(p("past_end")));
}

TEST_F(Clips, Hdr10MetadataIsKept) {
  // HEVC 10-bit PQ with HDR10's SEI (x265 puts it in the frames only, not in the container).
  const std::string in = clip(
      "hdr.mkv",
      "-frames:v 3 -c:v libx265 -pix_fmt yuv420p10le -color_primaries bt2020 -color_trc smpte2084 "
      "-colorspace bt2020nc -x265-params log-level=none:hdr10=1:master-display='G(13250,34500)"
      "B(7500,3000)R(34000,16000)WP(15635,16450)L(10000000,1)':max-cll=1000,400");
  const std::string out = p("hdr.mp4");
  convert({{"inputs", std::vector<std::string>{in}},
           {"output", out},
           {"dst", std::string("cubemap:layout=3x2")},
           {"size", std::string("192x128")},
           {"codec", std::string("hevc")}});
  const std::string frames = shell(
      "ffprobe -v error -select_streams v -read_intervals %+#1 -show_entries "
      "frame_side_data=max_content,max_average,max_luminance,min_luminance,red_x -of compact '" +
      out + "'");
  EXPECT_NE(frames.find("red_x=34000/50000"), std::string::npos) << frames;
  EXPECT_NE(frames.find("max_luminance=10000000/10000"), std::string::npos) << frames;
  EXPECT_NE(frames.find("max_content=1000|max_average=400"), std::string::npos) << frames;
  const std::string stream = shell(
      "ffprobe -v error -show_entries stream_side_data=max_content,red_x:stream=color_transfer,"
      "color_primaries,pix_fmt -of compact '" +
      out + "'");
  EXPECT_NE(stream.find("red_x=34000/50000"), std::string::npos) << stream;  // (MP4's mdcv box)
  EXPECT_NE(stream.find("max_content=1000"), std::string::npos) << stream;   // (clli)
  EXPECT_NE(stream.find("yuv420p10le"), std::string::npos) << stream;
  EXPECT_NE(stream.find("smpte2084"), std::string::npos) << stream;
  EXPECT_NE(stream.find("bt2020"), std::string::npos) << stream;
}

TEST_F(Clips, FramesTimesAndAudioAreTheInputs) {
  const std::string in = clip("in.mp4", "-shortest -c:v libx264 -pix_fmt yuv420p -c:a aac",
                              "-f lavfi -i 'sine=frequency=440:duration=0.5'");
  const std::string out = p("out.mp4");
  const Report r = convert({{"inputs", std::vector<std::string>{in}},
                            {"output", out},
                            {"dst", std::string("cubemap:layout=eac")}});
  EXPECT_EQ(test::integer(r, "frames"), 12);
  EXPECT_EQ(pts(in), pts(out));
  const auto hash = [&](const std::string& f) {
    return shell("ffmpeg -v error -i '" + f + "' -map 0:a -c copy -f streamhash -");
  };
  EXPECT_NE(hash(in), "");
  EXPECT_EQ(hash(in), hash(out));
  EXPECT_EQ(shell("ffprobe -v error -select_streams v -show_entries "
                  "stream=time_base,chroma_location -of csv=p=0 '" +
                  in + "'"),
            shell("ffprobe -v error -select_streams v -show_entries "
                  "stream=time_base,chroma_location -of csv=p=0 '" +
                  out + "'"));
  // An existing output is kept without overwrite.
  const auto before = fs::last_write_time(out);
  EXPECT_THROW(convert({{"inputs", std::vector<std::string>{in}},
                        {"output", out},
                        {"dst", std::string("equirect")}}),
               Error);
  EXPECT_EQ(fs::last_write_time(out), before);
}

}  // namespace
}  // namespace panoproj
