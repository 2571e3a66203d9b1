// Image files: every format and depth round-trips, types are kept, writes are atomic and refuse
// to clobber, damaged files give one clear error.
#include "panoproj/io.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include <OpenImageIO/imageio.h>

#include "io/atomic_output.hpp"
#include "panoproj/error.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

namespace fs = std::filesystem;

class Io : public test::TempDirTest {
 protected:
  std::vector<std::string> listing() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(dir_)) v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
  }
};

WriteOptions with_type(PixelType t) {
  WriteOptions w;
  w.type = t;
  return w;
}
WriteOptions replacing() {
  WriteOptions w;
  w.overwrite = true;
  return w;
}

using test::pattern;

TEST_F(Io, LosslessFormatsRoundTripExactlyAndKeepTheirType) {
  struct F {
    const char* name;
    int nc;
    PixelType type;
    int alpha;
  };
  for (const F& f : {F{"a.png", 3, PixelType::U8, -1}, F{"b.png", 4, PixelType::U8, 3},
                     F{"c.png", 1, PixelType::U8, -1}, F{"d.png", 4, PixelType::U16, 3},
                     F{"e.tif", 3, PixelType::U8, -1}, F{"f.tif", 3, PixelType::U16, -1},
                     F{"g.exr", 4, PixelType::F16, 3}, F{"h.exr", 3, PixelType::F32, -1},
                     F{"i.tif", 2, PixelType::U16, 1}}) {
    const Image im = pattern({37, 23}, f.nc, f.type, f.alpha);
    write_image(im, path(f.name), {});
    const Image back = read_image(path(f.name));
    EXPECT_EQ(back.type(), f.type) << f.name;
    EXPECT_EQ(back.alpha_channel(), f.alpha) << f.name;
    EXPECT_TRUE(back == im) << f.name;
  }
}

TEST_F(Io, HdrAndJpegRoundTripWithinTheirFormats) {
  // Radiance HDR: shared-exponent RGB, 8-bit mantissas (relative error < 1%), any magnitude.
  Image hdr({16, 8}, 3, PixelType::F32);
  for (int64_t y = 0; y < 8; ++y)
    for (int64_t x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) test::set(hdr, x, y, c, std::pow(10.0, (x - 8) / 2.0) * (c + 1));
  write_image(hdr, path("a.hdr"), {});
  const Image h = read_image(path("a.hdr"));
  EXPECT_EQ(h.type(), PixelType::F32);
  for (int64_t x = 0; x < 16; ++x)
    EXPECT_NEAR(test::get(h, x, 3, 2), test::get(hdr, x, 3, 2), 0.01 * test::get(hdr, x, 3, 2));
  // JPEG (quality 95): lossy, alpha dropped; a smooth picture comes back close.
  Image im({64, 48}, 4, PixelType::U8, 3);
  for (int64_t y = 0; y < 48; ++y)
    for (int64_t x = 0; x < 64; ++x)
      for (int c = 0; c < 4; ++c) test::set(im, x, y, c, c == 3 ? 1.0 : 0.5 + 0.4 * std::sin(0.1 * x + 0.07 * y + c));
  write_image(im, path("a.jpg"), {});
  const Image j = read_image(path("a.jpg"));
  EXPECT_EQ(j.channels(), 3);
  EXPECT_GT(test::psnr(j, im), 30.0);
}

TEST_F(Io, DepthConversionOnWrite) {
  const Image im = pattern({8, 8}, 3, PixelType::U8, -1);
  write_image(im, path("a.exr"), with_type(PixelType::F32));
  const Image f = read_image(path("a.exr"));
  ASSERT_EQ(f.type(), PixelType::F32);
  EXPECT_FLOAT_EQ(test::get(f, 3, 4, 1), test::get(im, 3, 4, 1) / 255.0);
  write_image(f, path("b.png"), with_type(PixelType::U16));
  EXPECT_EQ(test::get(read_image(path("b.png")), 3, 4, 1), test::get(im, 3, 4, 1) * 257);
}

TEST_F(Io, RefusesToClobberAndLeavesNothingBehindOnFailure) {
  const Image im = pattern({8, 8}, 3, PixelType::U8, -1);
  write_image(im, path("a.png"), {});
  const auto before = fs::file_size(path("a.png"));
  const Image other = pattern({9, 9}, 3, PixelType::U8, -1);
  try {
    write_image(other, path("a.png"), {});
    FAIL() << "overwrote";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "output " + path("a.png") + " exists (pass --overwrite to replace it)");
  }
  EXPECT_EQ(fs::file_size(path("a.png")), before);
  write_image(other, path("a.png"), replacing());
  EXPECT_EQ(read_image(path("a.png")).width(), 9);
  // An extension no format has: an error and no file, not even a temporary one.
  EXPECT_THROW(write_image(im, path("b.xyz"), {}), Error);
  EXPECT_THROW(write_image(im, path("missing/b.png"), {}), Error);
  EXPECT_EQ(listing(), std::vector<std::string>{"a.png"});
}

// A signal during a commit waits for its renames and its count (landed), so that the batch's line
// names every file that landed: here the signal comes before the count, and the line says 1.
TEST_F(Io, ASignalDuringACommitWaitsForItsRenamesAndItsCount) {
  GTEST_FLAG_SET(death_test_style, "fast");  // (the child forked: the same folder)
  const std::string a = path("a.txt"), b = path("b.txt");
  EXPECT_EXIT(
      {
        install_signal_cleanup();
        set_batch_progress(0, 3);
        OutputSet set(false);
        set.add(a, "a");
        set.add(b, "b");
        set.commit([] {
          std::raise(SIGINT);
          set_batch_progress(1, 3);
        });
        std::_Exit(0);  // (not reached: the signal acts once the commit is done)
      },
      ::testing::KilledBySignal(SIGINT), "interrupted after 1 of 3; 1 written, each whole");
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.txt", "b.txt"}));
  // A signal while a file is written: its temporary is removed, nothing lands.
  EXPECT_EXIT(
      {
        install_signal_cleanup();
        OutputSet set(false);
        const int fd = set.open(path("c.txt"));
        (void)!::write(fd, "c", 1);
        std::raise(SIGTERM);
        std::_Exit(0);
      },
      ::testing::KilledBySignal(SIGTERM), "");
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.txt", "b.txt"}));
}

TEST_F(Io, MetadataArraysAndRationalsReadBackElementByElement) {
  // A float array (an EXR's chromaticities) and GPS rationals come back value by value (OpenImageIO's
  // get_float takes a default, not an index: reading with it repeated the first value).
  const std::vector<double> chroma{0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290};
  WriteOptions w;
  w.metadata = {{"chromaticities", chroma}};
  write_image(pattern({8, 8}, 3, PixelType::F32, -1), path("c.exr"), w);
  const Metadata m = read_metadata(path("c.exr"));
  bool found = false;
  for (const Attribute& a : m)
    if (a.name == "chromaticities") {
      found = true;
      const auto& v = std::get<std::vector<double>>(a.value);
      ASSERT_EQ(v.size(), chroma.size());
      for (size_t i = 0; i < v.size(); ++i) EXPECT_NEAR(v[i], chroma[i], 1e-6) << i;
    }
  EXPECT_TRUE(found);
  // GPS degrees, minutes, seconds: rationals in the JPEG's EXIF.
  w.metadata = {{"GPS:Latitude", std::vector<double>{44.0, 19.0, 55.8}}};
  write_image(pattern({8, 8}, 3, PixelType::U8, -1), path("g.jpg"), w);
  found = false;
  for (const Attribute& a : read_metadata(path("g.jpg")))
    if (a.name == "GPS:Latitude") {
      found = true;
      const auto& v = std::get<std::vector<double>>(a.value);
      ASSERT_EQ(v.size(), 3u);
      EXPECT_NEAR(v[0], 44.0, 1e-6);
      EXPECT_NEAR(v[1], 19.0, 1e-6);
      EXPECT_NEAR(v[2], 55.8, 1e-5);
    }
  EXPECT_TRUE(found);
}

TEST_F(Io, DamagedFilesGiveOneClearError) {
  auto write_bytes = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(path(name), std::ios::binary) << bytes;
  };
  write_image(pattern({64, 64}, 3, PixelType::U8, -1), path("ok.png"), {});
  std::ifstream in(path("ok.png"), std::ios::binary);
  const std::string png((std::istreambuf_iterator<char>(in)), {});
  write_bytes("truncated.png", png.substr(0, png.size() / 2));
  write_bytes("garbage.jpg", std::string(4000, '\x5a'));
  for (const char* name : {"truncated.png", "garbage.jpg", "nothing.png"}) {
    try {
      read_image(path(name));
      FAIL() << name;
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(path(name)), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
}

// A header declaring more pixels than memory holds (12 TB here) is a clear error, not a crash or
// an out-of-memory kill; the region read says the same. (A header the file's bytes cannot fill is
// refused before the memory budget is asked: test_robustness.py has both.)
TEST_F(Io, HeadersDeclaringMoreThanMemoryAreAClearError) {
  std::ofstream(path("huge.hdr"), std::ios::binary) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1000000 +X 1000000\n";
  EXPECT_EQ(read_image_size(path("huge.hdr")), (Size{1000000, 1000000}));
  for (int region = 0; region < 2; ++region) {
    try {
      if (region) {
        read_image_region(path("huge.hdr"), 0, 0, 1000000, 600000);
      } else {
        read_image(path("huge.hdr"));
      }
      FAIL() << region;
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("1000000x1000000"), std::string::npos) << m;
      EXPECT_NE(m.find(region ? "7.2 TB in the part needed" : "(12 TB)"), std::string::npos) << m;
      EXPECT_NE(m.find("the file has 57 bytes, too few to hold them"), std::string::npos) << m;
    }
  }
}

// Truncates a file to a fraction of its bytes.
void truncate_file(const std::string& path, double fraction) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  in.close();
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      << bytes.substr(0, static_cast<size_t>(static_cast<double>(bytes.size()) * fraction));
}

TEST_F(Io, RegionReadsNeedOnlyTheirPartOfADamagedFile) {
  const Image full = pattern({512, 256}, 3, PixelType::U8, -1);
  // JPEG (scanlines, decoded in order): the lower part is cut off. (OpenImageIO's PNG reader
  // decodes a whole PNG before handing out rows, so PNG gains nothing from region reads.)
  write_image(full, path("a.jpg"), {});
  write_image(full, path("intact.jpg"), {});
  truncate_file(path("a.jpg"), 0.6);
  const Image intact = read_image(path("intact.jpg"));
  const Image top = read_image_region(path("a.jpg"), 0, 0, 512, 80);
  ASSERT_EQ(top.origin_y(), 0);
  ASSERT_EQ(top.frame_size(), full.size());
  for (int64_t y = 0; y < 80; ++y) ASSERT_EQ(0, std::memcmp(top.at(0, y), intact.pixel(0, y), full.row_bytes())) << y;
  EXPECT_THROW(read_image(path("a.jpg")), Error);
  EXPECT_THROW(read_image_region(path("a.jpg"), 0, 200, 512, 256), Error);
  // A middle band keeps only its rows and columns, at their frame position.
  const Image band = read_image_region(path("intact.jpg"), 10, 100, 20, 130);
  EXPECT_EQ(band.size(), (Size{10, 30}));
  EXPECT_EQ(band.origin_x(), 10);
  EXPECT_EQ(band.origin_y(), 100);
  for (int64_t y = 100; y < 130; ++y) ASSERT_EQ(0, std::memcmp(band.at(10, y), intact.pixel(10, y), 30)) << y;
}

TEST_F(Io, TiledFilesDecodeOnlyTheTilesTheRegionTouches) {
  const Image full = pattern({512, 256}, 3, PixelType::U8, -1);
  {
    auto out = OIIO::ImageOutput::create(path("t.tif"));
    OIIO::ImageSpec spec(512, 256, 3, OIIO::TypeDesc::UINT8);
    spec.tile_width = spec.tile_height = 64;
    spec.attribute("compression", "none");
    ASSERT_TRUE(out->open(path("t.tif"), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, full.data()));
    out->close();
  }
  // Tiles are stored row by row: cut the file inside the third row of tiles.
  truncate_file(path("t.tif"), 0.55);
  const Image win = read_image_region(path("t.tif"), 100, 10, 300, 100);
  EXPECT_EQ(win.origin_x(), 64);  // tile-aligned
  EXPECT_EQ(win.origin_y(), 0);
  EXPECT_EQ(win.width(), 256);
  for (int64_t y = 10; y < 100; ++y) ASSERT_EQ(0, std::memcmp(win.at(100, y), full.pixel(100, y), 200 * 3)) << y;
  EXPECT_THROW(read_image_region(path("t.tif"), 0, 200, 512, 256), Error);
}

// Radiance HDR decodes at 1/2, 1/4 and 1/8 as the mean of each block (fewer pixels at the right
// and bottom edges), rows read in bands: the region's rows of the scaled frame, every column.
TEST_F(Io, HdrDecodesAtAScaleAsTheMeanOfEachBlock) {
  Image src({101, 37}, 3, PixelType::F32);
  for (int64_t y = 0; y < 37; ++y)
    for (int64_t x = 0; x < 101; ++x)
      for (int c = 0; c < 3; ++c) test::set(src, x, y, c, std::pow(2.0, std::sin(0.3 * x + 0.7 * y + c)));
  write_image(src, path("s.hdr"), {});
  const Image full = read_image(path("s.hdr"));  // as stored (RGBE)
  EXPECT_TRUE(read_image_info(path("s.hdr")).scalable);
  for (int scale : {2, 4, 8}) {
    const int64_t w = (101 + scale - 1) / scale, h = (37 + scale - 1) / scale;
    const Image win = read_image_region(path("s.hdr"), 1, 1, 2, h - 1, 0, 0, scale);
    ASSERT_EQ(win.width(), w) << scale;
    ASSERT_EQ(win.origin_y(), 1) << scale;
    ASSERT_EQ(win.height(), h - 2) << scale;
    double worst = 0;
    for (int64_t y = 1; y < h - 1; ++y)
      for (int64_t x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          double sum = 0;
          int n = 0;
          for (int64_t j = y * scale; j < std::min<int64_t>(37, (y + 1) * scale); ++j)
            for (int64_t i = x * scale; i < std::min<int64_t>(101, (x + 1) * scale); ++i, ++n) sum += test::get(full, i, j, c);
          const auto* px = reinterpret_cast<const float*>(win.at(x, y));
          worst = std::max(worst, std::fabs(px[c] - sum / n) / (sum / n));
        }
    EXPECT_LT(worst, 1e-6) << "scale " << scale;
  }
}

TEST_F(Io, CubeFacesRoundTripAndMustMatch) {
  Image strip = pattern({6 * 16, 16}, 3, PixelType::U8, -1);
  write_cube_faces(strip, path("f{index}_{face}.png"), {});
  EXPECT_EQ(listing(), (std::vector<std::string>{"f0_front.png", "f1_right.png", "f2_back.png",
                                                  "f3_left.png", "f4_up.png", "f5_down.png"}));
  EXPECT_TRUE(read_cube_faces(path("f{index}_{face}.png")) == strip);
  write_image(pattern({15, 15}, 3, PixelType::U8, -1), path("f3_left.png"), replacing());
  try {
    read_cube_faces(path("f{index}_{face}.png"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "cube face " + path("f3_left.png") + " is 15x15 3ch uint8, but " +
                                         path("f0_front.png") + " is 16x16 3ch uint8 (all six faces must match)");
  }
}

}  // namespace
}  // namespace panoproj
