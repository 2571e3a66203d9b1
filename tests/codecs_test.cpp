// The built-in codecs (lib/src/io): JPEG region and scaled decodes against the whole decode, PNG
// and PPM regions, damaged files, the JPEG writer's options, EXIF carried to outputs, and the
// lean path (no OpenImageIO for JPEG, PNG and PPM).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <thread>

#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "io/codec.hpp"
#include "io/exif.hpp"
#include "io/oiio_plugin.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

using test::get;
using test::set;

class Codecs : public test::TempDirTest {
 protected:
  std::string bytes_of_file(const std::string& p) const {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  void put_file(const std::string& p, const std::string& b) const { std::ofstream(p, std::ios::binary) << b; }
};

// A photo-like picture: smooth gradients, sharp edges and texture, so that chroma upsampling and
// the IDCT have something to differ on.
Image photo(Size s, int channels) {
  Image im(s, channels, PixelType::U8);
  for (int64_t y = 0; y < s.height; ++y)
    for (int64_t x = 0; x < s.width; ++x)
      for (int c = 0; c < channels; ++c) {
        double v = 0.5 + 0.3 * std::sin(0.05 * x + 0.031 * y + 2.0 * c) + ((x / 7 + y / 5 + c) % 3 == 0 ? 0.15 : 0.0);
        v += 0.05 * std::sin(1.3 * x * (c + 1)) * std::cos(0.9 * y);
        set(im, x, y, c, std::clamp(v, 0.0, 1.0));
      }
  return im;
}

// Every pixel of `region` (a window of the frame) equals the same pixel of `whole`.
void expect_region_equal(const Image& region, const Image& whole, int64_t x0, int64_t y0, int64_t x1, int64_t y1,
                         const std::string& what) {
  ASSERT_EQ(region.origin_x(), x0) << what;
  ASSERT_EQ(region.origin_y(), y0) << what;
  ASSERT_EQ(region.size(), (Size{x1 - x0, y1 - y0})) << what;
  ASSERT_EQ(region.frame_size(), whole.size()) << what;
  for (int64_t y = y0; y < y1; ++y)
    ASSERT_EQ(0, std::memcmp(region.at(x0, y), whole.pixel(x0, y), static_cast<size_t>(x1 - x0) * whole.pixel_bytes()))
        << what << ": row " << y;
}

struct Layout {
  const char* name;
  int channels;
  ChromaSubsampling subsampling;
};
constexpr Layout kLayouts[] = {{"420", 3, ChromaSubsampling::S420},
                               {"422", 3, ChromaSubsampling::S422},
                               {"444", 3, ChromaSubsampling::S444},
                               {"gray", 1, ChromaSubsampling::S420}};

// Regions on and off the iMCU grid (8 and 16 px), at the frame's edges, one pixel, random ones.
std::vector<std::array<int64_t, 4>> regions(Size s, uint32_t seed) {
  std::vector<std::array<int64_t, 4>> r = {
      {0, 0, s.width, s.height}, {1, 1, 2, 2},     {15, 15, 17, 17},    {16, 16, 32, 32},
      {8, 9, 40, 41},            {0, 5, 3, s.height}, {s.width - 3, 0, s.width, 20}, {17, s.height - 1, 60, s.height}};
  std::mt19937 rng(seed);
  for (int i = 0; i < 40; ++i) {
    std::uniform_int_distribution<int64_t> x(0, s.width - 1), y(0, s.height - 1);
    int64_t x0 = x(rng), x1 = x(rng), y0 = y(rng), y1 = y(rng);
    if (x0 > x1) std::swap(x0, x1);
    if (y0 > y1) std::swap(y0, y1);
    r.push_back({x0, y0, x1 + 1, y1 + 1});
  }
  for (auto& [x0, y0, x1, y1] : r) {  // within the frame, at least one pixel
    x0 = std::min(x0, s.width - 1), y0 = std::min(y0, s.height - 1);
    x1 = std::clamp(x1, x0 + 1, s.width), y1 = std::clamp(y1, y0 + 1, s.height);
  }
  return r;
}

TEST_F(Codecs, JpegRegionsEqualTheWholeDecodeAtEveryScaleAndChromaLayout) {
  const Size s{203, 157};  // no side a multiple of the iMCU
  for (const Layout& l : kLayouts) {
    WriteOptions w;
    w.subsampling = l.subsampling;
    write_image(photo(s, l.channels), path(std::string(l.name) + ".jpg"), w);
    for (int scale : {1, 2, 4, 8}) {
      const std::string file = path(std::string(l.name) + ".jpg");
      const Image whole = read_image_region(file, 0, 0, INT64_MAX, INT64_MAX, 0, 0, scale);
      ASSERT_EQ(whole.size(), (Size{(s.width + scale - 1) / scale, (s.height + scale - 1) / scale}));
      for (const auto& [x0, y0, x1, y1] : regions(whole.size(), 7u * scale)) {
        const Image r = read_image_region(file, x0, y0, x1, y1, 0, 0, scale);
        expect_region_equal(r, whole, x0, y0, x1, y1,
                            std::string(l.name) + " 1/" + std::to_string(scale) + " " + std::to_string(x0) + "," +
                                std::to_string(y0) + ".." + std::to_string(x1) + "," + std::to_string(y1));
      }
    }
  }
}

// A progressive JPEG (the Jordan Pond sample, 4:4:4) crops and skips like a baseline one.
TEST_F(Codecs, ProgressiveJpegRegionsEqualTheWholeDecode) {
  const std::string file = std::string(PANOPROJ_SOURCE_DIR) + "/samples/images/jordan_pond_4096x2048.jpg";
  const Image whole = read_image(file);
  const auto some = regions(whole.size(), 3);
  for (const auto& [x0, y0, x1, y1] : std::vector(some.begin(), some.begin() + 16))
    expect_region_equal(read_image_region(file, x0, y0, x1, y1), whole, x0, y0, x1, y1, "progressive");
}

// A 1024x512 part of the Jordan Pond sample (real content: smooth chroma, sharp luma), as a
// standalone image of 3 channels or (its green) 1.
Image real_photo(int channels) {
  const Image part = read_image_region(std::string(PANOPROJ_SOURCE_DIR) + "/samples/images/jordan_pond_4096x2048.jpg",
                                       1024, 512, 2048, 1024);
  Image out({1024, 512}, channels, PixelType::U8);
  for (int64_t y = 0; y < 512; ++y)
    for (int64_t x = 0; x < 1024; ++x)
      for (int c = 0; c < channels; ++c) out.pixel(x, y)[c] = part.at(1024 + x, 512 + y)[channels == 1 ? 1 : c];
  return out;
}

// At 1/s each pixel comes from its s x s block's low DCT coefficients (at 1/8 the DC term alone:
// the block's mean before rounding and chroma upsampling), so it stays within a few levels of the
// whole decode averaged over the block. Measured on real content (max / mean over all samples,
// levels of 255): gray within 1.8 / 0.22, 4:4:4 within 5.3 / 0.31, 4:2:0 within 16 / 0.32 and
// 4:2:2 within 30 / 0.81 (chroma upsampled from blocks twice as wide, at edges); the bounds below
// leave some room.
TEST_F(Codecs, ScaledJpegDecodesAreTheWholeDecodeAveraged) {
  for (const Layout& l : kLayouts) {
    WriteOptions w;
    w.subsampling = l.subsampling;
    const std::string file = path(std::string(l.name) + ".jpg");
    write_image(real_photo(l.channels), file, w);
    const Image whole = read_image(file);
    for (int scale : {2, 4, 8}) {
      const Image scaled = read_image_region(file, 0, 0, INT64_MAX, INT64_MAX, 0, 0, scale);
      const Image box = test::area_downsample(whole, scale);
      double worst = 0, sum = 0;
      for (int64_t y = 0; y < scaled.height(); ++y)
        for (int64_t x = 0; x < scaled.width(); ++x)
          for (int c = 0; c < l.channels; ++c) {
            const double d = std::abs(get(scaled, x, y, c) - 255 * get(box, x, y, c));  // in levels
            worst = std::max(worst, d), sum += d;
          }
      const double mean = sum / static_cast<double>(scaled.width() * scaled.height() * l.channels);
      const bool full_chroma = l.channels == 1 || l.subsampling == ChromaSubsampling::S444;
      EXPECT_LE(worst, full_chroma ? 6.0 : 32.0) << l.name << " 1/" << scale;
      EXPECT_LE(mean, full_chroma ? 0.4 : 1.0) << l.name << " 1/" << scale;
      std::printf("%s 1/%d: max %.2f, mean %.3f levels\n", l.name, scale, worst, mean);
    }
  }
}

TEST_F(Codecs, ScalesOtherThanAJpegsAreRefused) {
  write_image(photo({32, 16}, 3), path("a.png"), {});
  write_image(photo({32, 16}, 3), path("a.jpg"), {});
  EXPECT_THROW(read_image_region(path("a.png"), 0, 0, 32, 16, 0, 0, 2), Error);
  EXPECT_THROW(read_image_region(path("a.jpg"), 0, 0, 32, 16, 0, 0, 3), Error);
  EXPECT_TRUE(read_image_info(path("a.jpg")).scalable);
  EXPECT_FALSE(read_image_info(path("a.png")).scalable);
}

TEST_F(Codecs, PngAndPpmRegionsEqualTheWholeDecode) {
  const Size s{97, 61};
  struct F {
    const char* name;
    int channels;
    PixelType type;
    int alpha;
  };
  for (const F& f : {F{"a.png", 3, PixelType::U8, -1}, F{"b.png", 4, PixelType::U16, 3}, F{"c.png", 2, PixelType::U8, 1},
                     F{"d.ppm", 3, PixelType::U8, -1}, F{"e.ppm", 3, PixelType::U16, -1}, F{"f.pgm", 1, PixelType::U16, -1}}) {
    const Image im = test::pattern(s, f.channels, f.type, f.alpha);
    write_image(im, path(f.name), {});
    const Image whole = read_image(path(f.name));
    ASSERT_TRUE(whole == im) << f.name;  // lossless
    for (const auto& [x0, y0, x1, y1] : regions(s, 11))
      expect_region_equal(read_image_region(path(f.name), x0, y0, x1, y1), whole, x0, y0, x1, y1, f.name);
  }
}

// Rows after the region are never read: a file cut below it still gives the region, and the
// whole file is an error naming it. (A progressive JPEG reads every scan first: no region of a
// cut one decodes.)
TEST_F(Codecs, RegionsAboveACutDecodeAndTheWholeFileIsAnError) {
  const Image im = photo({512, 512}, 3);
  for (const char* name : {"a.jpg", "a.png", "a.ppm"}) {
    write_image(im, path(name), {});
    const Image whole = read_image(path(name));
    const std::string b = bytes_of_file(path(name));
    put_file(path(name), b.substr(0, b.size() * 6 / 10));
    expect_region_equal(read_image_region(path(name), 3, 0, 200, 30), whole, 3, 0, 200, 30, name);
    try {
      read_image(path(name));
      FAIL() << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path(name)), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos) << e.what();
    }
  }
  const std::string pond = bytes_of_file(std::string(PANOPROJ_SOURCE_DIR) + "/samples/images/jordan_pond_4096x2048.jpg");
  put_file(path("p.jpg"), pond.substr(0, pond.size() * 9 / 10));
  EXPECT_THROW(read_image_region(path("p.jpg"), 0, 0, 64, 64), Error);
}

// Corrupt entropy-coded data (an end-of-image marker in the middle of the scan, a restart marker
// out of order) is an error, not grey rows.
TEST_F(Codecs, CorruptJpegDataIsAnError) {
  write_image(photo({256, 256}, 3), path("ok.jpg"), {});
  const std::string b = bytes_of_file(path("ok.jpg"));
  const size_t mid = b.size() / 2;
  put_file(path("eoi.jpg"), b.substr(0, mid) + "\xFF\xD9" + b.substr(mid + 2));
  put_file(path("rst.jpg"), b.substr(0, mid) + "\xFF\xD3" + b.substr(mid + 2));
  std::string sof = b;
  const size_t at = sof.find("\xFF\xC0");
  ASSERT_NE(at, std::string::npos);
  sof[at + 5] = sof[at + 6] = 0;  // height 0
  put_file(path("sof.jpg"), sof);
  for (const char* name : {"eoi.jpg", "rst.jpg", "sof.jpg"}) {
    try {
      read_image(path(name));
      FAIL() << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path(name)), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
}

// Hand-made PPM/PGM headers: comments, other maxvals (scaled to the full range), and bad ones.
TEST_F(Codecs, PpmHeadersAndMaxvals) {
  put_file(path("a.pgm"), std::string("P5\n# a comment\n3 1\n# another\n100\n") + std::string("\x00\x32\x64", 3));
  const Image a = read_image(path("a.pgm"));
  EXPECT_EQ(a.size(), (Size{3, 1}));
  EXPECT_EQ(a.pixel(0, 0)[0], 0);
  EXPECT_EQ(a.pixel(1, 0)[0], 128);  // 50/100 of 255, rounded
  EXPECT_EQ(a.pixel(2, 0)[0], 255);
  put_file(path("b.pgm"), std::string("P5 2 1 1000 ") + std::string("\x01\xF4\x03\xE8", 4));
  const Image b = read_image(path("b.pgm"));
  EXPECT_EQ(b.type(), PixelType::U16);
  uint16_t v[2];
  std::memcpy(v, b.data(), 4);
  EXPECT_EQ(v[0], 32768);  // 500/1000 of 65535, rounded
  EXPECT_EQ(v[1], 65535);
  for (const std::string& bad : {std::string("P6\n0 1\n255\n"), std::string("P6\n1 1\n70000\n"),
                                 std::string("P6\n99999999999 1\n255\n"), std::string("P6\n1 1\n255"),
                                 std::string("P6\n# only a comment")}) {
    put_file(path("bad.ppm"), bad + std::string(8, 'x'));
    EXPECT_THROW(read_image(path("bad.ppm")), Error) << bad;
  }
  put_file(path("short.ppm"), "P6\n100 100\n255\n" + std::string(10, 'x'));  // the file cannot hold it
  EXPECT_THROW(read_image(path("short.ppm")), Error);
}

// The JPEG writer's options: quality orders the file sizes; the subsampling is the frame
// header's sampling factors; out-of-range values are refused before anything is written.
TEST_F(Codecs, JpegQualityAndSubsamplingAreWritten) {
  const Image im = photo({128, 96}, 3);
  size_t last = 0;
  for (int q : {30, 60, 90, 100}) {
    WriteOptions w;
    w.quality = q;
    write_image(im, path("q" + std::to_string(q) + ".jpg"), w);
    const size_t n = bytes_of_file(path("q" + std::to_string(q) + ".jpg")).size();
    EXPECT_GT(n, last) << q;
    last = n;
  }
  for (const Layout& l : kLayouts) {
    if (l.channels != 3) continue;
    WriteOptions w;
    w.subsampling = l.subsampling;
    write_image(im, path(std::string("s") + l.name + ".jpg"), w);
    const std::string b = bytes_of_file(path(std::string("s") + l.name + ".jpg"));
    const size_t sof = b.find("\xFF\xC0");
    ASSERT_NE(sof, std::string::npos);
    const auto luma = static_cast<unsigned char>(b[sof + 11]);  // H << 4 | V of component 1
    const unsigned char expected = l.subsampling == ChromaSubsampling::S420 ? 0x22
                                   : l.subsampling == ChromaSubsampling::S422 ? 0x21 : 0x11;
    EXPECT_EQ(luma, expected) << l.name;
  }
  for (int q : {0, 101, -5}) {
    WriteOptions w;
    w.quality = q;
    EXPECT_THROW(write_image(im, path("bad.jpg"), w), Error) << q;
  }
  EXPECT_FALSE(std::filesystem::exists(path("bad.jpg")));
  EXPECT_THROW(parse_subsampling("411"), Error);
}

// The restart markers of a JPEG's scan in order, RST0 to RST7 and again, and their count.
int64_t restarts_in_order(const std::string& b) {
  int64_t n = 0;
  for (size_t at = b.find("\xFF\xDA"); at != std::string::npos && at + 1 < b.size(); ++at) {
    at = b.find('\xFF', at);
    if (at == std::string::npos || at + 1 >= b.size()) break;
    const auto m = static_cast<unsigned char>(b[at + 1]);
    if (m >= 0xD0 && m <= 0xD7 && m != 0xD0 + n++ % 8) return -1;
  }
  return n;
}

// A large image encodes in blocks (columns of at least 1024 px where they divide the MCU row,
// bands of 128 rows), joined at restart markers: the file differs from one encoder's, its pixels
// do not, for every chroma layout and sizes whose edges cut MCUs; a damaged join (a segment out
// of place, a marker misnumbered) would show in any decoder.
TEST_F(Codecs, BlockedJpegEncodesDecodeAsOneEncoder) {
  // 1100: one column (69 MCUs of 16 px have no divisor leaving 1024 px); 2552: two of 4:2:0 and
  // 4:2:2 (160 MCUs, the last cut), one of 4:4:4 and gray (319 of 8 px); 4100: 4:4:4 and gray in
  // three (513 of 8 px: 3 x 171). 1000 and 1030 rows: not multiples of 16.
  for (const Size size : {Size{1100, 1000}, Size{2552, 1000}, Size{4100, 1030}}) {
    const Image colour = photo(size, 3), gray = photo(size, 1);
    for (const Layout& l : kLayouts) {
      const std::string what = l.name + std::string(" ") + std::to_string(size.width);
      WriteOptions one, two;
      one.subsampling = two.subsampling = l.subsampling;
      one.threads = 1;
      const Image& src = l.channels == 1 ? gray : colour;
      write_image(src, path("one.jpg"), one);
      write_image(src, path("two.jpg"), two);
      const std::string a = bytes_of_file(path("one.jpg")), b = bytes_of_file(path("two.jpg"));
      EXPECT_NE(a, b) << what;
      EXPECT_EQ(a.find("\xFF\xDD"), std::string::npos) << what;  // one encoder: no DRI
      EXPECT_NE(b.find("\xFF\xDD"), std::string::npos) << what;  // DRI: restart markers
      // A restart at every MCU row at least (more where the rows are cut into columns).
      const int64_t mcu_h = l.channels == 3 && l.subsampling == ChromaSubsampling::S420 ? 16 : 8;
      EXPECT_GE(restarts_in_order(b), (size.height + mcu_h - 1) / mcu_h - 1) << what;
      EXPECT_TRUE(read_image(path("one.jpg")) == read_image(path("two.jpg"))) << what;
      std::filesystem::remove(path("one.jpg")), std::filesystem::remove(path("two.jpg"));
    }
  }
}

// Parts reported as they are final, in any order and from two threads at once, give the file
// that encoding at the end gives; so does a picture of noise at quality 100, whose blocks
// overflow the shared buffer sized for a quarter of the samples.
TEST_F(Codecs, JpegBlocksEncodedAsTheirPartsArriveGiveTheSameFile) {
  std::mt19937 rng(7);
  Image noise({2552, 1000}, 3, PixelType::U8, -1, Image::Unfilled{});
  for (size_t i = 0; i < noise.byte_size(); ++i) noise.data()[i] = static_cast<unsigned char>(rng());
  struct Picture {
    const Image image;
    int quality;
    ChromaSubsampling subsampling;
  };
  const Picture pictures[] = {{photo({2552, 1000}, 3), 95, ChromaSubsampling::S420},
                              {photo({4100, 1030}, 1), 90, ChromaSubsampling::S420},
                              {noise, 100, ChromaSubsampling::S444}};
  for (const Picture& p : pictures) {
    WriteOptions w;
    w.quality = p.quality, w.subsampling = p.subsampling;
    EmbeddedMetadata meta;
    meta.xmp = "<x:xmpmeta/>";
    const FileBytes at_end = JpegBlockEncoder(p.image.size(), p.image.channels(), "a.jpg", w, meta).finish(p.image);
    std::vector<PixelRect> parts;  // 64 px tiles, shuffled
    for (int64_t y = 0; y < p.image.height(); y += 64)
      for (int64_t x = 0; x < p.image.width(); x += 64)
        parts.push_back({x, y, std::min(x + 64, p.image.width()), std::min(y + 64, p.image.height())});
    std::shuffle(parts.begin(), parts.end(), rng);
    JpegBlockEncoder streamed(p.image.size(), p.image.channels(), "a.jpg", w, meta);
    std::thread other([&] {
      for (size_t i = 0; i < parts.size(); i += 2) streamed.done(p.image, parts[i]);
    });
    for (size_t i = 1; i < parts.size(); i += 2) streamed.done(p.image, parts[i]);
    other.join();
    const FileBytes arrived = streamed.finish(p.image);
    EXPECT_TRUE(at_end == arrived) << p.quality;
    std::ofstream(path("b.jpg"), std::ios::binary).write(reinterpret_cast<const char*>(arrived.data()),
                                                       static_cast<std::streamsize>(arrived.size()));
    WriteOptions one = w;
    one.threads = 1;
    write_image(p.image, path("one.jpg"), one);
    EXPECT_TRUE(read_image(path("b.jpg")) == read_image(path("one.jpg"))) << p.quality;
    if (p.quality == 100) {
      EXPECT_GT(arrived.size(), p.image.byte_size() / 4);  // (the buffer overflowed)
    }
    std::filesystem::remove(path("b.jpg")), std::filesystem::remove(path("one.jpg"));
  }
}

// libjpeg's own errors come back as exceptions, never exit(): a side over its 65500 (which
// write_image refuses before encoding) reaches it here directly.
TEST_F(Codecs, EncoderErrorsAreExceptions) {
  const Image wide({70000, 1}, 1, PixelType::U8);
  try {
    encode_jpeg(wide, path("wide.jpg"), {}, {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write " + path("wide.jpg") + ": "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("65500"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_image(wide, path("wide.jpg"), {}), Error);
  EXPECT_FALSE(std::filesystem::exists(path("wide.jpg")));
}

// A TIFF-structured EXIF block, little- or big-endian: IFD0 with Orientation (SHORT) and the
// EXIF IFD pointer; the EXIF IFD with PixelXDimension (SHORT) and PixelYDimension (LONG); IFD1.
std::string exif_block(bool little) {
  std::string b;
  auto u16 = [&](uint32_t v) { little ? (b += char(v & 255), b += char(v >> 8)) : (b += char(v >> 8), b += char(v & 255)); };
  auto u32 = [&](uint32_t v) { little ? (u16(v & 0xFFFF), u16(v >> 16)) : (u16(v >> 16), u16(v & 0xFFFF)); };
  b += little ? "II" : "MM";
  u16(42), u32(8);
  // IFD0 at 8 (2 entries, to 38), the EXIF IFD at 38 (2 entries, to 68), IFD1 at 68 (empty).
  u16(2);
  u16(0x0112), u16(3), u32(1), u16(6), u16(0);
  u16(0x8769), u16(4), u32(1), u32(38);
  u32(68);
  u16(2);
  u16(0xA002), u16(3), u32(1), u16(4000), u16(0);
  u16(0xA003), u16(4), u32(1), u32(3000);
  u32(0);
  u16(0), u32(0);
  return b;
}

TEST(Exif, OrientationResetDimensionsRewrittenThumbnailUnlinked) {
  for (bool little : {true, false}) {
    const std::string in = exif_block(little);
    const std::string out = exif_for_output(in, {70000, 200});
    ASSERT_EQ(out.size(), in.size());
    auto u16 = [&](size_t at) {
      const auto* p = reinterpret_cast<const unsigned char*>(out.data() + at);
      return little ? p[0] | p[1] << 8 : p[0] << 8 | p[1];
    };
    auto u32 = [&](size_t at) { return little ? u16(at) | u16(at + 2) << 16 : u16(at) << 16 | u16(at + 2); };
    EXPECT_EQ(u16(8 + 2 + 8), 1) << little;            // Orientation
    EXPECT_EQ(u32(8 + 2 + 24), 0u) << little;          // no IFD1
    EXPECT_EQ(u16(38 + 2 + 2), 4) << little;           // 70000 > 65535: PixelXDimension became a LONG
    EXPECT_EQ(u32(38 + 2 + 8), 70000u) << little;
    EXPECT_EQ(u32(38 + 2 + 12 + 8), 200u) << little;   // PixelYDimension
  }
}

// Every truncation and every single corrupted byte of a block gives a block or "" without
// reading outside it (ASan and the fuzz target check the reads).
TEST(Exif, DamagedBlocksAreDroppedOrEditedInPlace) {
  const std::string in = exif_block(true);
  for (size_t n = 0; n < in.size(); ++n) {
    const std::string out = exif_for_output(in.substr(0, n), {10, 10});
    EXPECT_TRUE(out.empty() || out.size() == n) << n;
  }
  for (size_t i = 0; i < in.size(); ++i)
    for (int v : {0x00, 0xFF, 0x7F}) {
      std::string b = in;
      b[i] = static_cast<char>(v);
      const std::string out = exif_for_output(b, {10, 10});
      EXPECT_TRUE(out.empty() || out.size() == b.size()) << i;
    }
  EXPECT_EQ(exif_for_output("MM\0*garbage", {1, 1}), "");
}

// The attributes of a block holding each value type: ASCII (Make, with its NUL), SHORT (Orientation,
// ResolutionUnit as OpenImageIO's text), LONG, RATIONAL, SRATIONAL (negative), UNDEFINED
// (ExifVersion), three RATIONALs (GPS latitude), values stored after the IFDs; an entry pointing
// outside the block and one of an unread type are left out.
TEST(Exif, AttributesByOpenImageIONames) {
  for (bool little : {true, false}) {
    std::string b;
    auto u16 = [&](uint32_t v) { little ? (b += char(v & 255), b += char(v >> 8)) : (b += char(v >> 8), b += char(v & 255)); };
    auto u32 = [&](uint32_t v) { little ? (u16(v & 0xFFFF), u16(v >> 16)) : (u16(v >> 16), u16(v & 0xFFFF)); };
    auto entry = [&](uint32_t tag, uint32_t type, uint32_t count, uint32_t value) { u16(tag), u16(type), u32(count), u32(value); };
    auto short_entry = [&](uint32_t tag, uint32_t v) { u16(tag), u16(3), u32(1), u16(v), u16(0); };
    b += little ? "II" : "MM";
    u16(42), u32(8);
    // IFD0 at 8: 6 entries (to 86); Exif IFD at 86: 4 entries (to 140); GPS IFD at 140: 1 entry
    // (to 158); then the values: "Acme\0" at 158, 1/250 at 163, -7/10 at 171, lat at 179.
    u16(6);
    entry(0x010F, 2, 5, 158);
    short_entry(0x0112, 6);
    short_entry(0x0128, 3);
    entry(0x0110, 2, 5, 100000);  // Model: outside the block
    entry(0x8769, 4, 1, 86);
    entry(0x8825, 4, 1, 140);
    u32(0);
    u16(4);
    entry(0x829A, 5, 1, 163);
    entry(0x9204, 10, 1, 171);
    u16(0x9000), u16(7), u32(4), b += "0232";
    entry(0xA002, 12, 1, 0);  // a DOUBLE: not read
    u32(0);
    u16(1);
    entry(0x0002, 5, 3, 179);
    u32(0);
    b += std::string("Acme\0", 5);
    u32(1), u32(250);
    u32(static_cast<uint32_t>(-7)), u32(10);
    u32(44), u32(1), u32(21), u32(1), u32(30), u32(4);
    ASSERT_EQ(b.size(), 179u + 24u);
    std::map<std::string, Attribute::Value> got;
    for (const Attribute& a : exif_attributes(b)) got[a.name] = a.value;
    const std::map<std::string, Attribute::Value> expected = {
        {"Make", std::string("Acme")},
        {"Orientation", int64_t{6}},
        {"ResolutionUnit", std::string("cm")},
        {"ExposureTime", double(float(1.0 / 250))},
        {"Exif:ExposureBiasValue", double(float(-0.7))},
        {"Exif:ExifVersion", std::string("0232")},
        {"GPS:Latitude", std::vector<double>{44, 21, 7.5}}};
    EXPECT_EQ(got, expected) << little;
    for (size_t n = 0; n < b.size(); ++n) (void)exif_attributes(b.substr(0, n));  // (ASan: no read outside)
  }
}

// A well-formed ICC profile (libpng checks one before writing or reading it).
std::string icc_profile() {
  std::ifstream in(std::string(PANOPROJ_SOURCE_DIR) + "/samples/icc/srgb_lcms2.icc", std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// JPEG and PNG inputs carry their EXIF, ICC profile and (non-Photo-Sphere) XMP to JPEG and PNG
// outputs as stored, EXIF edited for the output.
TEST_F(Codecs, EmbeddedBlocksAreCarriedAsStored) {
  WriteOptions w;
  w.embedded.exif = exif_block(true);
  w.embedded.icc = icc_profile();
  ASSERT_GT(w.embedded.icc.size(), 128u);
  w.embedded.xmp = "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\"><!-- a note --></x:xmpmeta>";
  for (const char* name : {"a.jpg", "a.png"}) {
    write_image(photo({40, 20}, 3), path(name), w);
    const EmbeddedMetadata m = read_embedded_metadata(path(name));
    EXPECT_EQ(m.exif, exif_for_output(w.embedded.exif, {40, 20})) << name;
    EXPECT_EQ(m.icc, w.embedded.icc) << name;
    EXPECT_EQ(m.xmp, w.embedded.xmp) << name;
  }
  // A Photo Sphere packet described the input's projection: not carried.
  w.embedded.xmp = "<x:xmpmeta GPano:ProjectionType=\"equirectangular\"/>";
  write_image(photo({40, 20}, 3), path("b.jpg"), w);
  EXPECT_EQ(read_embedded_metadata(path("b.jpg")).xmp, "");
  EXPECT_FALSE(oiio_loaded());  // none of this needed OpenImageIO
}

// The lean path: the command converts JPEG, PNG and PPM with the plugin made unavailable;
// TIFF then fails in one line naming the plugin and what needs it.
TEST_F(Codecs, JpegPngAndPpmNeedNoOpenImageIO) {
  const std::string cli = std::string("PANOPROJ_OIIO_PLUGIN=") + path("none.so") + " " + PANOPROJ_CLI + " convert ";
  write_image(photo({128, 64}, 3), path("e.jpg"), {});
  for (const char* out : {"c.jpg", "c.png", "c.ppm"}) {
    const std::string cmd = cli + path("e.jpg") + " " + path(out) + " --to cubemap -q";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  EXPECT_EQ(std::system((cli + path("c.ppm") + " " + path("d.png") + " --from cubemap --to equirect -q").c_str()), 0);
  const std::string cmd = cli + path("e.jpg") + " " + path("c.tif") + " --to cubemap -q 2> " + path("err.txt");
  EXPECT_NE(std::system(cmd.c_str()), 0);
  const std::string err = bytes_of_file(path("err.txt"));
  EXPECT_NE(err.find("needs OpenImageIO"), std::string::npos) << err;
  EXPECT_NE(err.find("not found"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(path("c.tif")));
}

// The finest step is the least singular value of the map's Jacobian: exactly the shrink factor of
// an equirect to a smaller one, the smaller one's of an anisotropic shrink; a view that enlarges
// anywhere allows no scale; a scale must divide the source's sides.
TEST(DecodeScale, FollowsTheFinestStepOfTheView) {
  ConvertOptions o;
  auto step = [&](const char* from, Size src, const char* to, Size out) {
    o.size = out;
    return finest_source_step(make_geometry(src, parse_spec(from), parse_spec(to), o));
  };
  auto scale = [&](const char* from, Size src, const char* to, Size out) {
    o.size = out;
    const ConversionGeometry g = make_geometry(src, parse_spec(from), parse_spec(to), o);
    return coarsest_decode_scale(g, finest_source_step(g));
  };
  EXPECT_NEAR(step("equirect", {4096, 2048}, "equirect", {512, 256}), 8.0, 1e-6);
  EXPECT_NEAR(step("equirect", {4096, 2048}, "equirect", {1024, 128}), 4.0, 1e-6);
  // Stopping below 4 (as the command does): a view that allows no scale returns early, others whole.
  o.size = Size{2048, 1024};
  EXPECT_LT(finest_source_step(make_geometry({4096, 2048}, parse_spec("equirect"), parse_spec("equirect"), o), 4), 4.0);
  o.size = Size{512, 256};
  EXPECT_NEAR(finest_source_step(make_geometry({4096, 2048}, parse_spec("equirect"), parse_spec("equirect"), o), 4), 8.0, 1e-6);
  EXPECT_EQ(scale("equirect", {4096, 2048}, "equirect", {512, 256}), 4);   // 2 x 4 <= 8 < 2 x 8
  EXPECT_EQ(scale("equirect", {4096, 2048}, "equirect", {256, 128}), 8);
  EXPECT_EQ(scale("equirect", {4096, 2048}, "equirect", {2048, 1024}), 1);  // 2 px steps: 1/2 would lose half
  EXPECT_EQ(scale("equirect", {4096, 2048}, "equirect", {1000, 500}), 2);
  EXPECT_EQ(scale("equirect", {4100, 2050}, "equirect", {256, 128}), 2);  // 4100 = 4 x 1025: 8 and 4 do not divide
  // A narrow pinhole view enlarges its centre: full scale, however small the output.
  EXPECT_EQ(scale("equirect", {4096, 2048}, "pinhole:hfov=10", {64, 64}), 1);
  // Nothing of the source in view (a view straight up; the source's field ends at 45 degrees).
  o.pitch = 90;
  EXPECT_TRUE(std::isinf(step("equirect:hfov=90,vfov=90", {1024, 1024}, "pinhole:hfov=30", {64, 64})));
}

// The command: a JPEG overview decodes at the coarsest scale its view allows, says so, and stays
// within 40 dB of the whole decode's; --decode-scale fixes it, and refuses what cannot be.
TEST_F(Codecs, OverviewsOfJpegsDecodeScaledAndCloseToTheWholeDecode) {
  write_image(real_photo(3), path("half.jpg"), {});  // 1024x512
  auto run = [&](const std::string& args, const std::string& input = "half.jpg") {
    const std::string cmd = std::string(PANOPROJ_CLI) + " convert " + path(input) + " " + args + " > " +
                            path("out.txt") + " 2>&1";
    const int code = std::system(cmd.c_str());
    return std::pair{code, bytes_of_file(path("out.txt"))};
  };
  const auto [code, out] = run(path("s.png") + " --to equirect --size 128x64");
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("(1024x512, equirect)"), std::string::npos) << out;  // the file's size
  EXPECT_NE(out.find("decoded 100% of the source (jpeg at 1/4 scale)"), std::string::npos) << out;
  ASSERT_EQ(run(path("f.png") + " --to equirect --size 128x64 --decode-scale 1").first, 0);
  EXPECT_GE(test::psnr(read_image(path("s.png")), read_image(path("f.png"))), 40.0);
  for (const auto& [input, args, why] :
       {std::tuple<std::string, std::string, std::string>{"half.jpg", "--decode-scale 3", "expected auto, 1, 2, 4 or 8"},
        {"f.png", "--decode-scale 8", "only JPEG sources"}}) {
    const auto [c, o] = run(path("x.png") + " --to equirect --size 128x64 " + args, input);
    EXPECT_NE(c, 0) << args;
    EXPECT_NE(o.find(why), std::string::npos) << o;
  }
  write_image(test::pattern({1000, 500}, 3, PixelType::U8, -1), path("odd.jpg"), {});
  const auto [c, o] = run(path("x.png") + " --to equirect --size 100x50 --decode-scale 8", "odd.jpg");
  EXPECT_NE(c, 0);
  EXPECT_NE(o.find("1000x500 is not a multiple of 8"), std::string::npos) << o;
  EXPECT_FALSE(std::filesystem::exists(path("x.png")));
}

}  // namespace
}  // namespace panoproj
