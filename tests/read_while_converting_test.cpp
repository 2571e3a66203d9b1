// Converting while the source is decoded (Converter::run_reading): the rows arrive from the top
// (RowFeed), each tile waits for the rows it reads. Rows not yet arrived hold a poison value, so a
// tile that reads one too early changes the output, which must equal run() on the whole source.
#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <thread>

#include "base/row_feed.hpp"
#include "io/region_read.hpp"
#include "job_support.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/jobs.hpp"
#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

Projection make(const char* spec, Size size) { return make_projection(parse_spec(spec), size); }

TEST(RowFeed, WaitsForRowsAndStopsWhenClosed) {
  RowFeed feed;
  EXPECT_TRUE(feed.has(0));
  EXPECT_FALSE(feed.has(1));
  std::thread producer([&] {
    for (int64_t k = 1; k <= 64; ++k) {
      std::this_thread::sleep_for(std::chrono::microseconds(50));
      feed.arrived(k);
    }
  });
  EXPECT_TRUE(feed.wait(64));
  EXPECT_TRUE(feed.has(64));
  producer.join();
  feed.arrived(10);  // rows never go back
  EXPECT_TRUE(feed.has(64));
  std::thread closer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    feed.close();
  });
  EXPECT_FALSE(feed.wait(65));  // closed short of it
  closer.join();
}

// Fills window `into` (poisoned) from `from`, a row at a time with pauses (so that the tiles
// start as soon as their rows are told), telling arrived.
void trickle(const Image& from, Image& into, const RowsArrived& arrived, int64_t fail_at = -1) {
  const int64_t rows = into.height(), step = 1;
  for (int64_t y = 0; y < rows; y += step) {
    const int64_t end = std::min(rows, y + step);
    if (fail_at >= 0 && end > fail_at) throw Error("cannot read source.jpg: cut (the file is damaged or truncated)");
    for (int64_t r = y; r < end; ++r) std::memcpy(into.row(r), from.row(r), from.row_bytes());
    std::this_thread::sleep_for(std::chrono::microseconds(30));
    if (arrived) arrived(end);
  }
}

// The window of whole that c reads, as a source frame's window.
Image window_of(const Image& whole, const Converter& c) {
  const PixelRect r = c.source_footprint();
  Image w({r.x1 - r.x0, r.y1 - r.y0}, whole.channels(), whole.type(), whole.alpha_channel());
  for (int64_t y = r.y0; y < r.y1; ++y)
    std::memcpy(w.row(y - r.y0), whole.pixel(r.x0, y), static_cast<size_t>(r.x1 - r.x0) * whole.pixel_bytes());
  w.set_window(r.x0, r.y0, whole.size());
  return w;
}

struct Case {
  const char* from;
  Size from_size;
  const char* to;
  Size to_size;
  double yaw, pitch, roll;
  Interp interp;
  Antialias antialias;
};

TEST(ReadWhileConverting, EqualsTheConversionOfTheWholeSource) {
  using M = Antialias::Mode;
  const Case cases[] = {
      {"equirect", {1024, 512}, "cubemap", {6 * 128, 128}, 0, 0, 0, Interp::Bilinear, {M::Auto, 1}},
      {"equirect", {1024, 512}, "cubemap:layout=cross", {4 * 96, 3 * 96}, 20, 10, 0, Interp::Bicubic, {M::Off, 1}},
      {"equirect", {1024, 512}, "pinhole:hfov=90", {320, 240}, 30, 80, 0, Interp::Bilinear, {M::Off, 1}},
      {"equirect", {1024, 512}, "pinhole:hfov=60", {320, 240}, -40, -20, 5, Interp::Bicubic, {M::Auto, 1}},
      {"equirect", {1024, 512}, "pinhole:hfov=120", {160, 120}, 10, -85, 0, Interp::Bilinear, {M::Auto, 1}},
      {"equirect", {1024, 512}, "fisheye:fov=180", {300, 300}, 0, -60, 0, Interp::Bilinear, {M::Supersample, 2}},
      {"equirect", {1024, 512}, "equirect", {512, 256}, 30, 40, 10, Interp::Lanczos3, {M::Auto, 1}},
      {"equirect", {1024, 512}, "aitoff", {400, 200}, 0, 0, 0, Interp::Bilinear, {M::Auto, 1}},
      {"fisheye:fov=180", {600, 600}, "equirect", {512, 256}, 0, 0, 0, Interp::Bicubic, {M::Auto, 1}},
      {"equirect", {1024, 512}, "equirect", {256, 128}, 0, 0, 0, Interp::Bilinear, {M::Mip, 1}},  // waits for all
      {"cubemap", {6 * 128, 128}, "equirect", {512, 256}, 10, 0, 0, Interp::Bilinear, {M::Auto, 1}},  // waits for all
      // Shrinks by 16-32: sub-pixels reach half a pixel beyond the centres at the image's and
      // the faces' edges.
      {"equirect", {1024, 512}, "equirect", {32, 16}, 0, 0, 90, Interp::Bilinear, {M::Auto, 1}},
      {"equirect", {1024, 512}, "equirect", {64, 32}, 20, 30, 60, Interp::Bicubic, {M::Supersample, 8}},
      {"equirect", {1024, 512}, "cubemap", {6 * 16, 16}, 20, 30, 10, Interp::Bilinear, {M::Auto, 1}},
      {"equirect", {1024, 512}, "cubemap:layout=cross", {4 * 16, 3 * 16}, -30, 50, 20, Interp::Bilinear, {M::Supersample, 6}},
  };
  std::map<std::string, Image> rendered;  // by source
  for (const Case& c : cases) {
    const std::string what = std::string(c.from) + " -> " + c.to + " " + std::to_string(c.to_size.width);
    const Projection src = make(c.from, c.from_size), dst = make(c.to, c.to_size);
    const Eigen::Matrix3d r = rotation_from_ypr(c.yaw, c.pitch, c.roll);
    if (!rendered.count(c.from))
      rendered[c.from] = test::render(src, test::band_limited_scene(0.1, c.from_size.width), PixelType::U8);
    const Image& whole = rendered[c.from];
    for (int threads : {1, 2, 3}) {
      const Converter conv =
          test::converter(src, dst, r, c.interp, Engine::Simd, threads, Keep::Nothing, c.antialias);
      const Image from = window_of(whole, conv);
      const Image expected = conv.run(from);
      Image arriving(from.size(), from.channels(), from.type(), from.alpha_channel(), Image::Unfilled{});
      std::memset(arriving.data(), 0xA5, arriving.row_bytes() * static_cast<size_t>(arriving.height()));  // poison
      arriving.set_window(from.origin_x(), from.origin_y(), from.frame_size());
      Image out;
      conv.run_reading(arriving, out, [&](const RowsArrived& arrived) { trickle(from, arriving, arrived); });
      EXPECT_TRUE(out == expected) << what << ", " << threads << " threads";
    }
    // A batch's converter: later frames wait for the rows kept from the first and replay its taps.
    const Converter kept =
        test::converter(src, dst, r, c.interp, Engine::Simd, 2, Keep::MapsAndTaps, c.antialias);
    const Image from = window_of(whole, kept);
    const Image expected = kept.run(from);
    for (int frame = 0; frame < 2; ++frame) {
      Image arriving(from.size(), from.channels(), from.type(), from.alpha_channel(), Image::Unfilled{});
      std::memset(arriving.data(), 0xA5, arriving.row_bytes() * static_cast<size_t>(arriving.height()));
      arriving.set_window(from.origin_x(), from.origin_y(), from.frame_size());
      Image out;
      kept.run_reading(arriving, out, [&](const RowsArrived& arrived) { trickle(from, arriving, arrived); });
      EXPECT_TRUE(out == expected) << what << ", kept, frame " << frame;
    }
  }
  // The reference engine reads first, then converts.
  const Projection src = make("equirect", {512, 256}), dst = make("pinhole:hfov=90", {160, 120});
  const Image whole = test::render(src, test::band_limited_scene(0.1, 512), PixelType::U8);
  const Converter ref = test::converter(src, dst, Eigen::Matrix3d::Identity(), Interp::Bilinear,
                                        Engine::Reference, 2);
  Image arriving(whole.size(), 3, PixelType::U8), out;
  ref.run_reading(arriving, out, [&](const RowsArrived& arrived) { trickle(whole, arriving, arrived); });
  EXPECT_TRUE(out == ref.run(whole));
}

// The parts reported finished (to encode them while the rest is made) hold their final pixels
// when reported, and cover the output once; an edge fill (which rewrites pixels after the tiles)
// reports none.
TEST(ReadWhileConverting, FinishedPartsAreFinalWhenReportedAndCoverTheOutputOnce) {
  const Projection src = make("equirect", {1024, 512});
  const Image whole = test::render(src, test::band_limited_scene(0.1, 1024), PixelType::U8);
  for (const char* to : {"cubemap", "pinhole:hfov=100"})
    for (int threads : {1, 2, 3})
      for (bool fill : {false, true}) {
        const std::string what = std::string(to) + ", " + std::to_string(threads) + " threads" + (fill ? ", edge fill" : "");
        const Projection dst = make(to, std::string(to) == "cubemap" ? Size{6 * 128, 128} : Size{300, 200});
        EdgeFill edges;
        edges.soft = fill;
        const Converter conv =
            test::converter(src, dst, rotation_from_ypr(10, 20, 0), Interp::Bicubic, Engine::Simd,
                            threads, Keep::Nothing, {Antialias::Mode::Auto, 1}, edges);
        const Image expected = conv.run(whole);
        Image arriving(whole.size(), 3, PixelType::U8), out;
        std::mutex m;
        std::vector<int> times(static_cast<size_t>(expected.width() * expected.height()), 0);
        int64_t wrong = 0;
        conv.run_reading(
            arriving, out, [&](const RowsArrived& a) { trickle(whole, arriving, a); }, nullptr, {},
            [&](const PixelRect& r) {
              const std::lock_guard<std::mutex> lock(m);
              for (int64_t y = r.y0; y < r.y1; ++y)
                for (int64_t x = r.x0; x < r.x1; ++x) {
                  ++times[static_cast<size_t>(y * expected.width() + x)];
                  wrong +=
                      std::memcmp(out.pixel(x, y), expected.pixel(x, y), out.pixel_bytes()) != 0;
                }
            });
        EXPECT_TRUE(out == expected) << what;
        EXPECT_EQ(wrong, 0) << what;
        const int want = fill ? 0 : 1;
        EXPECT_EQ(std::count(times.begin(), times.end(), want), static_cast<std::ptrdiff_t>(times.size())) << what;
      }
}

TEST(ReadWhileConverting, AFailedReadEndsTheRunWithItsError) {
  const Projection src = make("equirect", {1024, 512}), dst = make("cubemap", {6 * 128, 128});
  const Image whole = test::render(src, test::band_limited_scene(0.1, 1024), PixelType::U8);
  for (int threads : {1, 2, 3})
    for (int64_t fail_at : {0, 200, 511}) {
      const Converter conv = test::converter(src, dst, Eigen::Matrix3d::Identity(),
                                             Interp::Bilinear, Engine::Simd, threads);
      Image arriving(whole.size(), 3, PixelType::U8), out;
      try {
        conv.run_reading(arriving, out, [&](const RowsArrived& a) { trickle(whole, arriving, a, fail_at); });
        ADD_FAILURE() << "no error, " << threads << " threads, failing at row " << fail_at;
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cut"), std::string::npos) << e.what();
      }
    }
}

class RowsFromFiles : public test::TempDirTest {};

// An interlaced (Adam7) PNG, which libpng gives whole.
void write_interlaced_png(const Image& im, const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(im.width()), static_cast<png_uint_32>(im.height()), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_ADAM7, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  std::vector<png_bytep> rows(static_cast<size_t>(im.height()));
  for (int64_t y = 0; y < im.height(); ++y) rows[static_cast<size_t>(y)] = const_cast<png_bytep>(im.row(y));
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

TEST_F(RowsFromFiles, DecodersTellTheRowsInOrderAndDecodeWhatReadDoes) {
  const Projection p = make("equirect", {1200, 600});
  const Image im = test::render(p, test::band_limited_scene(0.1, 1200), PixelType::U8);
  write_image(im, path("baseline.jpg"), {});
  write_image(im, path("plain.png"), {});
  write_image(im, path("rgb.ppm"), {});
  write_interlaced_png(im, path("interlaced.png"));
  const std::string progressive = test::samples_dir() + "/jordan_pond_4096x2048.jpg";  // progressive 4:4:4
  for (const std::string& file : {path("baseline.jpg"), progressive, path("plain.png"), path("interlaced.png"), path("rgb.ppm")})
    for (int scale : {1, 2})
      for (auto [x0, y0, x1, y1] : {std::array<int64_t, 4>{0, 0, INT64_MAX, INT64_MAX}, {100, 37, 700, 421}}) {
        const std::string what = file + " at 1/" + std::to_string(scale);
        if (scale > 1 && file.find(".jpg") == std::string::npos) continue;
        RegionRead region(file, x0, y0, x1, y1, 0, 0, scale);
        std::vector<int64_t> told;
        region.read([&](int64_t k) { told.push_back(k); });
        ASSERT_FALSE(told.empty()) << what;
        for (size_t i = 1; i < told.size(); ++i) EXPECT_LT(told[i - 1], told[i]) << what;
        EXPECT_EQ(told.back(), region.image().height()) << what;
        const Image read = read_image_region(file, x0, y0, x1, y1, 0, 0, scale);
        EXPECT_TRUE(region.image() == read) << what;
        EXPECT_EQ(region.image().origin_y(), read.origin_y()) << what;
      }
}

// A JPEG output is encoded in blocks while the source is still decoded: its pixels are those of
// one encoder after the conversion (one thread), and those of an edge-filled conversion, which
// encodes after; a source cut short leaves no output.
TEST_F(RowsFromFiles, AJpegOutputEncodedWhileConvertingDecodesAsOneWrittenAfter) {
  const Projection p = make("equirect", {1024, 512});
  write_image(test::render(p, test::band_limited_scene(0.1, 1024), PixelType::U8), path("in.jpg"), {});
  auto convert = [&](const std::string& in, const std::string& out, int threads, bool soft) {
    // 1.5 Mpx: three columns of blocks, four bands; an edge fill (soft edges, black) or not.
    Arguments args = test::job_args("convert", {{"inputs", std::vector<std::string>{in}},
                                                {"output", path(out)},
                                                {"dst", std::string("cubemap")},
                                                {"size", std::string("3072x512")},
                                                {"threads", int64_t{threads}}});
    if (soft) args.set("fill", std::string("0,0,0"));
    test::run_job("convert", args);
  };
  convert(path("in.jpg"), "two.jpg", 2, false);
  convert(path("in.jpg"), "one.jpg", 1, false);
  convert(path("in.jpg"), "after.jpg", 2, true);
  const Image two = read_image(path("two.jpg"));
  EXPECT_TRUE(two == read_image(path("one.jpg")));
  auto file = [&](const std::string& name) {
    std::ifstream f(path(name), std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  };
  const std::string bytes = file("two.jpg");
  EXPECT_NE(bytes.find("\xFF\xDD"), std::string::npos);  // restart markers: blocks
  // An edge fill changes no pixel of a full sphere's cube (every pixel has a source).
  EXPECT_TRUE(two == read_image(path("after.jpg")));
  std::string cut = file("in.jpg");
  cut.resize(cut.size() * 2 / 3);
  std::ofstream(path("cut.jpg"), std::ios::binary) << cut;
  EXPECT_THROW(convert(path("cut.jpg"), "none.jpg", 2, false), Error);
  EXPECT_FALSE(std::filesystem::exists(path("none.jpg")));
}

}  // namespace
}  // namespace panoproj
