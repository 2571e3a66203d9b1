// A GoPro MAX .360 through the convert job: a file made here as the camera lays it out (two HEVC
// streams of the real 3K strips, the second video stream last, an AAC stream and a gpmd
// telemetry stream written through libavformat) converts to an equirect MP4 (x264 lossless)
// whose luma equals the image path's conversion of the two strips' decoded luma stacked, whose
// audio and telemetry packets are the input's byte for byte, which ffprobe reports spherical, and
// which holds one video stream, and whose back lens takes its own exposure (ev2); a file without
// two strips of one size, or with --stream, is refused in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "av_support.hpp"
#include "job_support.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/projection.hpp"
#include "photometry/response.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

namespace fs = std::filesystem;
using test::shell;

const std::string kFrames = test::source_dir() + "/samples/gopro_max/";

class MaxFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("panoproj_max_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string p(const std::string& name) const { return (dir_ / name).string(); }

  void run(const std::string& cmd) const { ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd; }

  // Photometric keys per lens (ev2: the back lens a stop under) on `in`'s second frame: decoded
  // as RGB, as images the front lens's part is the plain conversion's exactly, the back lens's
  // the plain one's a stop up (medians: correcting before sampling moves sharp edges).
  void check_each_lens_takes_its_exposure(const std::string& in) const {
    const auto frame = [&](const std::string& from, const std::string& to,
                           const std::string& stem) {
      test::run_job("convert", test::job_args("convert", {{"inputs", std::vector<std::string>{in}},
                                                          {"output", p(stem + "_{n}.png")},
                                                          {"src", from},
                                                          {"dst", to},
                                                          {"size", std::string("512x256")},
                                                          {"duration", std::string("0.06")}}));
      return read_image(p(stem + "_1.png"));
    };
    const Image plain = frame("gopro-max", "equirect", "plain");
    const Image got = frame("gopro-max:ev2=1", "equirect:ev=0", "keys");
    const Response f0 = Response::emor({0, 0, 0, 0, 0}, "f0");
    const Projection e = make_projection(parse_spec("equirect"), {512, 256});
    std::vector<double> back;
    int64_t front = 0;
    for (int64_t y = 0; y < 256; ++y)
      for (int64_t x = 0; x < 512; ++x) {
        Ray d;
        ASSERT_TRUE(to_ray(e, static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, d));
        const double t = GoProMax::seam_angle(d);  // (front positive; the band a few degrees)
        for (int c = 0; c < 3; ++c) {
          const double v = test::get(plain, x, y, c), w = test::get(got, x, y, c);
          if (t > 0.2) {
            ASSERT_EQ(w, v) << x << "," << y;
            ++front;
          } else if (t < -0.2 && v < 200) {
            back.push_back(std::fabs(w - 255 * f0.code(2 * f0.irradiance(v / 255))));
          }
        }
      }
    std::nth_element(back.begin(), back.begin() + static_cast<int64_t>(back.size() / 2),
                     back.end());
    EXPECT_GT(front, 10000);
    ASSERT_GT(back.size(), 10000u);
    EXPECT_LE(back[back.size() / 2], 1.0);
  }

  // A strip as `frames` HEVC frames at 30 fps (each the strip, moved a pixel a frame).
  std::string hevc(const std::string& jpg, const std::string& name, int frames) const {
    const std::string out = p(name);
    run("ffmpeg -v error -y -loop 1 -framerate 30 -i '" + kFrames + jpg + "' -frames:v " +
        std::to_string(frames) +
        " -vf \"scroll=h=0.0005\" -c:v libx265 -preset ultrafast -x265-params log-level=none "
        "-pix_fmt yuv420p '" +
        out + "'");
    return out;
  }

  // The .360: streams 0 video (strip 0:0), 1 audio (AAC), 2 data (gpmd: packet i holds
  // `payload(i)`), 3 video (strip 0:5); `second` empty: no second strip.
  std::string make_360(const std::string& first, const std::string& second, int frames) const {
    const std::string audio = p("audio.m4a"), out = p("clip.360");
    run("ffmpeg -v error -y -f lavfi -i sine=frequency=440:duration=" +
        std::to_string(frames / 30.0) + " -c:a aac '" + audio + "'");
    std::vector<std::string> inputs = {first, audio};
    if (!second.empty()) inputs.push_back(second);
    std::vector<AVFormatContext*> in(inputs.size(), nullptr);
    for (size_t i = 0; i < inputs.size(); ++i) {
      EXPECT_GE(avformat_open_input(&in[i], inputs[i].c_str(), nullptr, nullptr), 0);
      EXPECT_GE(avformat_find_stream_info(in[i], nullptr), 0);
    }
    AVFormatContext* o = nullptr;
    EXPECT_GE(avformat_alloc_output_context2(&o, nullptr, "mp4", out.c_str()), 0);
    auto copy_stream = [&](AVFormatContext* from) {
      AVStream* s = avformat_new_stream(o, nullptr);
      avcodec_parameters_copy(s->codecpar, from->streams[0]->codecpar);
      s->codecpar->codec_tag = 0;
      s->time_base = from->streams[0]->time_base;
      return s;
    };
    AVStream* v0 = copy_stream(in[0]);
    AVStream* a = copy_stream(in[1]);
    AVStream* d = avformat_new_stream(o, nullptr);
    d->codecpar->codec_type = AVMEDIA_TYPE_DATA;
    d->codecpar->codec_id = AV_CODEC_ID_BIN_DATA;
    d->codecpar->codec_tag = MKTAG('g', 'p', 'm', 'd');
    d->time_base = {1, 30};
    AVStream* v1 = second.empty() ? nullptr : copy_stream(in[2]);
    EXPECT_GE(avio_open(&o->pb, out.c_str(), AVIO_FLAG_WRITE), 0);
    EXPECT_GE(avformat_write_header(o, nullptr), 0);
    // Every packet, in each input's order; libavformat interleaves them by time.
    AVPacket* pk = av_packet_alloc();
    const std::vector<AVStream*> to = {v0, a, v1};
    for (size_t i = 0; i < inputs.size(); ++i) {
      while (av_read_frame(in[i], pk) >= 0) {
        if (pk->stream_index != 0) {
          av_packet_unref(pk);
          continue;
        }
        av_packet_rescale_ts(pk, in[i]->streams[0]->time_base, to[i]->time_base);
        pk->stream_index = to[i]->index;
        pk->pos = -1;
        EXPECT_GE(av_interleaved_write_frame(o, pk), 0);
      }
    }
    for (int i = 0; i < frames; ++i) {
      const std::string bytes = payload(i);
      AVPacket* q = av_packet_alloc();
      av_new_packet(q, static_cast<int>(bytes.size()));
      std::memcpy(q->data, bytes.data(), bytes.size());
      q->pts = q->dts = i, q->duration = 1, q->stream_index = d->index;
      EXPECT_GE(av_interleaved_write_frame(o, q), 0);
      av_packet_free(&q);
    }
    av_write_trailer(o);
    av_packet_free(&pk);
    avio_closep(&o->pb);
    avformat_free_context(o);
    for (AVFormatContext*& c : in) avformat_close_input(&c);
    return out;
  }

  static std::string payload(int i) {
    return "DEVC" + std::string(static_cast<size_t>(7 + i), static_cast<char>('A' + i));
  }

  // Frame `n`'s luma of a file's video stream `map` (ffmpeg's decode: the Y plane of yuv420p as
  // it is; -pix_fmt gray would expand its range).
  Image luma(const std::string& file, const std::string& map, int n, Size size) const {
    const std::string raw = p("luma.raw");
    run("ffmpeg -v error -y -i '" + file + "' -map " + map + " -vf \"select=eq(n\\," +
        std::to_string(n) + ")\" -frames:v 1 -f rawvideo -pix_fmt yuv420p '" + raw + "'");
    Image im(size, 1, PixelType::U8);
    std::ifstream f(raw, std::ios::binary);
    f.read(reinterpret_cast<char*>(im.data()), static_cast<std::streamsize>(im.byte_size()));
    EXPECT_TRUE(f.good()) << file << " frame " << n;
    return im;
  }

  fs::path dir_;
};

TEST_F(MaxFile, ConvertsAsItsTwoStripsWithItsAudioAndTelemetryAndIsSpherical) {
  const int frames = 6;
  const std::string a = hevc("3k_track0_GS018423_1.jpg", "a.mp4", frames);
  const std::string b = hevc("3k_track5_GS018423_1.jpg", "b.mp4", frames);
  const std::string in = make_360(a, b, frames), out = p("out.mp4");
  std::vector<std::string> warnings;
  JobEvents events;
  events.warning = [&](const std::string& w) { warnings.push_back(w); };
  const Report r =
      job_named("convert").run(test::job_args("convert", {{"inputs", std::vector<std::string>{in}},
                                                          {"output", out},
                                                          {"dst", std::string("equirect")},
                                                          {"size", std::string("1136x568")},
                                                          {"crf", int64_t{0}}}),
                               events);
  EXPECT_TRUE(warnings.empty()) << warnings[0];
  EXPECT_EQ(test::integer(r, "frames"), frames);
  EXPECT_EQ(test::stream_packets(out, AVMEDIA_TYPE_AUDIO),
            test::stream_packets(in, AVMEDIA_TYPE_AUDIO));
  EXPECT_EQ(test::stream_packets(out, AVMEDIA_TYPE_DATA),
            test::stream_packets(in, AVMEDIA_TYPE_DATA));
  EXPECT_EQ(test::stream_packets(out, AVMEDIA_TYPE_DATA).size(), static_cast<size_t>(frames));
  const std::string kinds =
      shell("ffprobe -v error -show_entries stream=codec_type -of default=nw=1 '" + out + "'");
  EXPECT_EQ(kinds, "codec_type=video\ncodec_type=audio\ncodec_type=data\n");
  EXPECT_NE(shell("ffprobe -v error -show_streams '" + out + "' 2>&1").find("equirectangular"),
            std::string::npos);
  // Each frame's luma: the image path's conversion of the strips' decoded luma, stacked.
  for (int n : {0, frames - 1}) {
    const Image top = luma(in, "0:0", n, {2272, 736}), bottom = luma(in, "0:3", n, {2272, 736});
    Image both({2272, 1472}, 1, PixelType::U8);
    std::memcpy(both.data(), top.data(), top.byte_size());
    std::memcpy(both.row(736), bottom.data(), bottom.byte_size());
    ConvertOptions o;
    o.size = Size{1136, 568};
    const Image want = panoproj::convert(both, parse_spec("gopro-max"), parse_spec("equirect"), o);
    const Image got = luma(out, "0:v:0", n, {1136, 568});
    int64_t differ = 0;
    for (int64_t y = 0; y < 568; ++y)
      for (int64_t x = 0; x < 1136; ++x)
        differ += test::get(got, x, y, 0) != test::get(want, x, y, 0);
    EXPECT_EQ(differ, 0) << "frame " << n;
  }
  check_each_lens_takes_its_exposure(in);
}

TEST_F(MaxFile, WithoutTwoStripsOrWithAStreamIsRefusedInOneLine) {
  const std::string a = hevc("3k_track0_GS018423_1.jpg", "a.mp4", 2);
  const std::string one = make_360(a, "", 2);
  auto error_of = [&](const std::string& in,
                      std::vector<std::pair<const char*, OptionValue>> more) {
    std::vector<std::pair<const char*, OptionValue>> args = {
        {"inputs", std::vector<std::string>{in}},
        {"output", p("o.mp4")},
        {"dst", std::string("equirect")}};
    for (auto& m : more) args.push_back(m);
    try {
      test::run_job("convert", test::job_args("convert", std::move(args)));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string e = error_of(one, {});
  EXPECT_NE(e.find("it has 1 video stream (2272x736), not a GoPro MAX's two strips"),
            std::string::npos)
      << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
  EXPECT_NE(error_of(one, {{"stream", int64_t{0}}}).find("drop --stream"), std::string::npos);
  EXPECT_FALSE(fs::exists(p("o.mp4")));
}

}  // namespace
}  // namespace panoproj
