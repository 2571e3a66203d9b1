// The panoproj command end to end: a good run writes its output; every kind of bad input gives
// one line on stderr naming the value, a non-zero exit, and writes nothing (inputs untouched).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "panoproj/io.hpp"
#include "panoproj/photo_sphere.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int code;
  std::string out, err;
};

class Cli : public test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    Image e({64, 32}, 3, PixelType::U8);
    for (size_t i = 0; i < e.byte_size(); ++i) e.data()[i] = static_cast<unsigned char>(i % 251);
    write_image(e, p("pano.png"), {});
    Image sq({40, 40}, 3, PixelType::U8);
    write_image(sq, p("square.png"), {});
  }
  std::string p(const std::string& name) const { return path(name); }

  CliRun run(const std::string& args) const {
    const std::string cmd = std::string(PANOPROJ_CLI) + " " + args + " >" + p(".stdout") + " 2>" + p(".stderr");
    const int status = std::system(cmd.c_str());
    auto slurp = [](const std::string& f) {
      std::ifstream in(f);
      std::stringstream s;
      s << in.rdbuf();
      return s.str();
    };
    CliRun r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(p(".stdout")), slurp(p(".stderr"))};
    fs::remove(p(".stdout"));
    fs::remove(p(".stderr"));
    return r;
  }

  // Names and sizes of the folder's files.
  std::map<std::string, uintmax_t> snapshot() const {
    std::map<std::string, uintmax_t> m;
    for (const auto& e : fs::recursive_directory_iterator(dir_))
      if (e.is_regular_file()) m[fs::relative(e.path(), dir_).string()] = e.file_size();
    return m;
  }

  // A bad invocation: exit != 0, exactly one stderr line containing `needle`, nothing written.
  void expect_refused(const std::string& args, const std::string& needle) {
    const auto before = snapshot();
    const CliRun r = run(args);
    EXPECT_NE(r.code, 0) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("panoproj: error: ", 0), 0u) << r.err;
    EXPECT_EQ(snapshot(), before) << args;
  }
};

TEST_F(Cli, ConvertsAndReports) {
  const CliRun r = run("convert " + p("pano.png") + " " + p("fish.png") + " --to fisheye:fov=180 --threads 2");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fisheye:fov=180"), std::string::npos);
  const Image out = read_image(p("fish.png"));
  EXPECT_EQ(out.width(), 32);  // 64 / 2 pi px/rad * pi
  EXPECT_EQ(out.height(), 32);
  // Cube faces as files, then back.
  ASSERT_EQ(run("convert " + p("pano.png") + " '" + p("c_{face}.png") + "' --to cubemap:layout=files --size 16x16").code, 0);
  EXPECT_TRUE(fs::exists(p("c_down.png")));
  EXPECT_EQ(read_image(p("c_up.png")).width(), 16);
  const CliRun back = run("convert '" + p("c_{face}.png") + "' " + p("back.png") + " --to equirect --size 64x32 -q");
  ASSERT_EQ(back.code, 0) << back.err;
  EXPECT_EQ(back.out, "");
}

TEST_F(Cli, OutputsKeepTheInputsMetadataButNotItsOrientation) {
  // A photo with camera EXIF, an ICC profile and an orientation flag.
  Image e({64, 32}, 3, PixelType::U8);
  WriteOptions w;
  const std::vector<uint8_t> icc(200, 7);
  w.metadata = {{"Make", std::string("TestCam")}, {"ExposureTime", 0.004}, {"ICCProfile", icc},
                {"Orientation", int64_t{6}}};
  write_image(e, p("tagged.jpg"), w);
  auto find = [](const Metadata& m, const std::string& name) -> const Attribute* {
    for (const Attribute& a : m)
      if (a.name == name) return &a;
    return nullptr;
  };
  ASSERT_NE(find(read_metadata(p("tagged.jpg")), "Orientation"), nullptr);  // the input has them
  ASSERT_EQ(run("convert " + p("tagged.jpg") + " " + p("kept.jpg") + " --to fisheye -q").code, 0);
  const Metadata kept = read_metadata(p("kept.jpg"));
  const Attribute* make = find(kept, "Make");
  ASSERT_NE(make, nullptr);
  EXPECT_EQ(std::get<std::string>(make->value), "TestCam");
  const Attribute* profile = find(kept, "ICCProfile");
  ASSERT_NE(profile, nullptr);
  EXPECT_EQ(std::get<std::vector<uint8_t>>(profile->value), icc);
  EXPECT_NE(find(kept, "ExposureTime"), nullptr);
  // The conversion worked on the stored pixels: orientation reset (1, top-left) or absent.
  const Attribute* orientation = find(kept, "Orientation");
  if (orientation) {
    EXPECT_EQ(std::get<int64_t>(orientation->value), 1);
  }
  // The dimensions, where EXIF has them, are the output's.
  const Size out = read_image_size(p("kept.jpg"));
  if (const Attribute* w = find(kept, "Exif:PixelXDimension")) {
    EXPECT_EQ(std::get<int64_t>(w->value), out.width);
  }
  if (const Attribute* h = find(kept, "Exif:PixelYDimension")) {
    EXPECT_EQ(std::get<int64_t>(h->value), out.height);
  }
  // --no-metadata writes none of them.
  ASSERT_EQ(run("convert " + p("tagged.jpg") + " " + p("bare.jpg") + " --to fisheye -q --no-metadata").code, 0);
  const Metadata bare = read_metadata(p("bare.jpg"));
  EXPECT_EQ(find(bare, "Make"), nullptr);
  EXPECT_EQ(find(bare, "ICCProfile"), nullptr);
}

TEST_F(Cli, PartialPanoramasArePlacedByTheirPhotoSphereMetadata) {
  // A partial equirect written as JPEG carries GPano; being 2:1 it would pass for a full
  // equirect, but read back without --from it is placed by its crop.
  ASSERT_EQ(run("convert " + p("pano.png") + " " + p("part.jpg") + " --to equirect:hfov=180,vfov=90,lon0=90 --size 32x16 -q")
                .code,
            0);
  const auto ps = read_photo_sphere(p("part.jpg"));
  ASSERT_TRUE(ps.has_value());
  EXPECT_EQ(ps->full_width, 64);
  EXPECT_EQ(ps->crop_left, 32);
  EXPECT_EQ(ps->crop_top, 8);
  const CliRun back = run("convert " + p("part.jpg") + " " + p("back.png") + " --to equirect --size 64x32");
  ASSERT_EQ(back.code, 0) << back.err;
  EXPECT_NE(back.out.find("equirect:hfov=180,vfov=90,lon0=90,lat0=0"), std::string::npos) << back.out;
  const Image b = read_image(p("back.png"));
  EXPECT_EQ(b.pixel(10, 16)[0], 0);   // outside the crop (longitudes left of 0)
  EXPECT_NE(b.pixel(48, 16)[0], 0);   // inside it
  // --no-metadata writes no GPano.
  ASSERT_EQ(run("convert " + p("pano.png") + " " + p("bare_part.jpg") + " --to equirect:hfov=180,vfov=90 --size 32x16 -q --no-metadata")
                .code,
            0);
  EXPECT_FALSE(read_photo_sphere(p("bare_part.jpg")).has_value());
}

TEST_F(Cli, TiltedPhotoSpheresAreLevelledByTheirPose) {
  // The same JPEG pixels with and without a GPano pose: levelling by the pose is the view turned
  // back by it (pitch alone: --pitch -P; roll alone: --roll -R); --from ignores the metadata.
  ASSERT_EQ(run("convert " + p("pano.png") + " " + p("plain.jpg") + " --to equirect --size 128x64 -q --no-metadata").code, 0);
  const Equirect full = std::get<Equirect>(make_projection(parse_spec("equirect"), {128, 64}));
  auto posed = [&](const std::string& name, double pitch, double roll) {
    std::ifstream plain(p("plain.jpg"), std::ios::binary);
    const std::string bytes{std::istreambuf_iterator<char>(plain), {}};
    PhotoSphere ps = photo_sphere_of(full);
    ps.pose_pitch = pitch, ps.pose_roll = roll;
    write_bytes(with_xmp(bytes, photo_sphere_xmp(ps)), p(name), false);
  };
  posed("pitched.jpg", 10, 0);
  posed("rolled.jpg", 0, 7);
  const std::string view = " --to pinhole:hfov=100 --size 48x40 ";
  const CliRun a = run("convert " + p("pitched.jpg") + " " + p("a.png") + view);
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_NE(a.out.find("levelled by its Photo Sphere pose: pitch 10, roll 0"), std::string::npos) << a.out;
  ASSERT_EQ(run("convert " + p("plain.jpg") + " " + p("b.png") + view + "--pitch -10 -q").code, 0);
  EXPECT_EQ(read_image(p("a.png")), read_image(p("b.png")));
  ASSERT_EQ(run("convert " + p("rolled.jpg") + " " + p("c.png") + " --to equirect --size 96x48 -q").code, 0);
  ASSERT_EQ(run("convert " + p("plain.jpg") + " " + p("d.png") + " --to equirect --size 96x48 --roll -7 -q").code, 0);
  EXPECT_EQ(read_image(p("c.png")), read_image(p("d.png")));
  ASSERT_EQ(run("convert " + p("pitched.jpg") + " " + p("e.png") + view + "--yaw 30 --from equirect -q").code, 0);
  ASSERT_EQ(run("convert " + p("plain.jpg") + " " + p("f.png") + view + "--yaw 30 -q").code, 0);
  EXPECT_EQ(read_image(p("e.png")), read_image(p("f.png")));
  posed("wild.jpg", 120, 0);
  expect_refused("convert " + p("wild.jpg") + " " + p("o.png") + " --to equirect", "GPano:PosePitchDegrees=120");
}

TEST_F(Cli, StereoPhotoSpheresReadTheirLayout) {
  // A top-bottom frame written with one eye's GPano fields and GSpherical:StereoMode converts
  // without --from as it does with --from equirect:stereo=tb; a wrong mode is refused by name.
  ASSERT_EQ(run("convert " + p("pano.png") + " " + p("tb.jpg") + " --to equirect:stereo=tb --size 128x128 -q").code, 0);
  const CliRun a = run("convert " + p("tb.jpg") + " " + p("a.png") + " --to fisheye:fov=180 --size 48x48");
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_NE(a.out.find("stereo=tb"), std::string::npos) << a.out;
  ASSERT_EQ(run("convert " + p("tb.jpg") + " " + p("b.png") + " --to fisheye:fov=180 --size 48x48 -q --from equirect:stereo=tb").code, 0);
  EXPECT_EQ(read_image(p("a.png")), read_image(p("b.png")));
  std::ifstream in(p("tb.jpg"), std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), {}};
  const size_t at = bytes.find("top-bottom");
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, 10, "bottom-top");
  write_bytes(bytes, p("bad.jpg"), false);
  expect_refused("convert " + p("bad.jpg") + " " + p("o.png") + " --to fisheye", "GSpherical:StereoMode is \"bottom-top\"");
}

TEST_F(Cli, BatchBuildsOneMapAndMatchesSingleConversions) {
  for (int k = 0; k < 3; ++k) {
    Image e({64, 32}, 3, PixelType::U8);
    for (size_t i = 0; i < e.byte_size(); ++i) e.data()[i] = static_cast<unsigned char>((i * (k + 3)) % 251);
    write_image(e, p("frame" + std::to_string(k) + ".png"), {});
  }
  mkdir(p("out").c_str(), 0755);
  const CliRun r = run("convert " + p("frame0.png") + " " + p("frame1.png") + " " + p("frame2.png") + " '" +
                       p("out/{stem}_{n}.png") + "' --to fisheye:fov=200 --interp bicubic");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // no progress bar when stderr is not a terminal
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 3);
  for (int k = 0; k < 3; ++k) {
    const std::string single = p("single" + std::to_string(k) + ".png");
    ASSERT_EQ(run("convert " + p("frame" + std::to_string(k) + ".png") + " " + single +
                  " --to fisheye:fov=200 --interp bicubic -q").code, 0);
    EXPECT_TRUE(read_image(p("out/frame" + std::to_string(k) + "_" + std::to_string(k) + ".png")) ==
                read_image(single));
  }
}

// A batch of files goes through the pipeline (frames decoded ahead, written behind): its files
// are the bytes of single runs, for a JPEG encoded as it is made, a PPM written from the image's
// rows and six face files encoded at once; one thread (one frame after another) gives the same.
TEST_F(Cli, PipelinedBatchWritesTheBytesOfSingleRuns) {
  auto bytes = [](const std::string& f) {
    std::ifstream in(f, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  std::string frames;
  for (int k = 0; k < 5; ++k) {
    Image e({256, 128}, 3, PixelType::U8);
    for (int64_t y = 0; y < 128; ++y)
      for (int64_t x = 0; x < 256; ++x)
        for (int c = 0; c < 3; ++c) e.pixel(x, y)[c] = static_cast<unsigned char>((x * (k + 2) + y * 3 + c * 80) % 256);
    write_image(e, p("f" + std::to_string(k) + ".jpg"), {});
    frames += p("f" + std::to_string(k) + ".jpg") + " ";
  }
  const std::vector<std::pair<std::string, std::string>> outputs = {
      {"{stem}.jpg", " --to cubemap --size 384x64"},
      // (JPEG scans over 2 MB: the encoders' buffers pass from frame to frame, pixel_buffers.hpp)
      {"{stem}.jpg", " --to cubemap --size 4608x768"},
      {"{stem}.ppm", " --to pinhole:hfov=100 --size 96x64 --yaw 30"},
      {"{stem}_{face}.png", " --to cubemap:layout=files --size 32x32"}};
  for (const auto& [pattern, args] : outputs)
    for (const char* threads : {"2", "1"}) {
      fs::remove_all(p("out")), fs::remove_all(p("one"));
      mkdir(p("out").c_str(), 0755), mkdir(p("one").c_str(), 0755);
      const CliRun r = run("convert " + frames + "'" + p("out/" + pattern) + "'" + args + " --threads " + threads);
      ASSERT_EQ(r.code, 0) << r.err;
      EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 5) << r.out;
      for (int k = 0; k < 5; ++k) {
        const std::string f = "f" + std::to_string(k), one = p("one/" + f + pattern.substr(6));
        // (the same threads: a JPEG of 1 Mpx or more on several is encoded in blocks, with restarts)
        ASSERT_EQ(run("convert " + p(f + ".jpg") + " '" + one + "'" + args + " --threads " + threads + " -q").code, 0);
        for (const auto& [name, size] : snapshot())
          if (name.rfind("one/" + f, 0) == 0) {
            ASSERT_TRUE(fs::exists(p("out/" + name.substr(4)))) << name;
            EXPECT_EQ(bytes(p("out/" + name.substr(4))), bytes(p(name))) << name << " " << threads << " threads";
          }
      }
      size_t files = 0;
      for (const auto& [name, size] : snapshot()) files += name.rfind("out/", 0) == 0 || name.rfind("one/", 0) == 0;
      EXPECT_EQ(files, 2 * 5 * (pattern.find("{face}") != std::string::npos ? 6u : 1u)) << "no temporaries left";
    }
}

// A frame that fails to decode in the middle of a pipelined batch: the frames before it are
// written whole (the bytes of single runs), none after it, no temporaries; one line names it.
TEST_F(Cli, ABatchStopsAtADamagedFrame) {
  std::string frames;
  for (int k = 0; k < 6; ++k) {
    Image e({256, 128}, 3, PixelType::U8);
    for (size_t i = 0; i < e.byte_size(); ++i) e.data()[i] = static_cast<unsigned char>((i * (k + 5)) % 253);
    write_image(e, p("f" + std::to_string(k) + ".jpg"), {});
    frames += p("f" + std::to_string(k) + ".jpg") + " ";
  }
  // Frame 3's entropy-coded data overwritten (its header intact: the batch starts).
  std::fstream f3(p("f3.jpg"), std::ios::in | std::ios::out | std::ios::binary);
  f3.seekg(0, std::ios::end);
  const std::streamoff size = f3.tellg();
  f3.seekp(size / 2);
  for (int i = 0; i < 200; ++i) f3.put(i % 2 ? '\xD9' : '\xFF');
  f3.close();
  mkdir(p("out").c_str(), 0755);
  const CliRun r = run("convert " + frames + "'" + p("out/{stem}.jpg") + "' --to cubemap --size 384x64 --threads 2");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("cannot read " + p("f3.jpg")), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  std::map<std::string, uintmax_t> written;
  for (const auto& [name, size] : snapshot())
    if (name.rfind("out/", 0) == 0) written[name] = size;
  ASSERT_EQ(written.size(), 3u) << "frames 0 to 2, nothing else";
  for (int k = 0; k < 3; ++k) {
    const std::string f = "f" + std::to_string(k);
    ASSERT_EQ(run("convert " + p(f + ".jpg") + " " + p(f + "_one.jpg") + " --to cubemap --size 384x64 -q").code, 0);
    EXPECT_TRUE(read_image(p("out/" + f + ".jpg")) == read_image(p(f + "_one.jpg"))) << f;
  }
}

TEST_F(Cli, BatchIsCheckedBeforeAnythingIsWritten) {
  write_image(Image({64, 32}, 3, PixelType::U8), p("a.png"), {});
  expect_refused("convert " + p("a.png") + " " + p("pano.png") + " " + p("out.png") + " --to equirect",
                 "names one file for 2 inputs");
  expect_refused("convert " + p("a.png") + " " + p("square.png") + " '" + p("{stem}_o.png") + "' --to equirect",
                 "a batch shares one size");
  mkdir(p("sub").c_str(), 0755);
  write_image(Image({64, 32}, 3, PixelType::U8), p("sub/a.png"), {});
  expect_refused("convert " + p("a.png") + " " + p("sub/a.png") + " '" + p("{stem}_o.png") + "' --to equirect",
                 "would be written twice");
  // Two texts, one file.
  mkdir(p("sub0").c_str(), 0755);
  mkdir(p("sub1").c_str(), 0755);
  expect_refused("convert " + p("a.png") + " " + p("sub/a.png") + " '" + p("sub{n}/../o.png") + "' --to equirect",
                 "would be written twice");
}

TEST_F(Cli, AViewReadsOnlyTheSourceRowsItNeeds) {
  // A 2:1 panorama whose lower part is cut off: a view of the sky converts, and matches the same
  // view from the intact file; a view of the ground cannot.
  Image e({1024, 512}, 3, PixelType::U8);
  for (int64_t y = 0; y < 512; ++y)
    for (int64_t x = 0; x < 1024; ++x)
      for (int c = 0; c < 3; ++c) e.pixel(x, y)[c] = static_cast<unsigned char>((x * 3 + y * 5 + c * 70) % 256);
  // JPEG decodes rows in order and stops after the region's last.
  write_image(e, p("intact.jpg"), {});
  std::ifstream in(p("intact.jpg"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::ofstream(p("cut.jpg"), std::ios::binary) << bytes.substr(0, bytes.size() * 55 / 100);
  const std::string view = " --to pinhole:hfov=60 --pitch 60 --size 200x200";
  const CliRun a = run("convert " + p("cut.jpg") + " " + p("sky_cut.png") + view);
  ASSERT_EQ(a.code, 0) << a.err;
  // The view reaches the pole, so it needs full rows from the top: about a third of them.
  const auto at = a.out.find("decoded ");
  ASSERT_NE(at, std::string::npos) << a.out;
  const int percent = std::atoi(a.out.c_str() + at + 8);
  EXPECT_GT(percent, 20) << a.out;
  EXPECT_LT(percent, 50) << a.out;
  ASSERT_EQ(run("convert " + p("intact.jpg") + " " + p("sky.png") + view).code, 0);
  EXPECT_TRUE(read_image(p("sky_cut.png")) == read_image(p("sky.png")));
  expect_refused("convert " + p("cut.jpg") + " " + p("ground.png") + " --to pinhole:hfov=60 --pitch -60",
                 "cannot read " + p("cut.jpg"));
}

TEST_F(Cli, DualFisheyeBothWays) {
  // Default size: two circles of the source's 64 / 2 pi px/rad over 100 degrees (r = 17.8 px),
  // side by side, halves of whole pixels.
  const CliRun r = run("convert " + p("pano.png") + " " + p("dual.png") + " --to dual-fisheye:fov=200 -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const Image dual = read_image(p("dual.png"));
  EXPECT_EQ(dual.width(), 72);
  EXPECT_EQ(dual.height(), 36);
  const CliRun back = run("convert " + p("dual.png") + " " + p("back.png") + " --from dual-fisheye:fov=200 --to equirect --size 64x32 -q");
  ASSERT_EQ(back.code, 0) << back.err;
  EXPECT_EQ(read_image(p("back.png")).width(), 64);
  expect_refused("convert " + p("dual.png") + " " + p("o.png") + " --from dual-fisheye:fov=200,feather=30 --to equirect",
                 "feather=30 is wider than the lenses' overlap of 20 deg");
  Image odd({71, 36}, 3, PixelType::U8);
  write_image(odd, p("odd.png"), {});
  expect_refused("convert " + p("odd.png") + " " + p("o.png") + " --from dual-fisheye --to equirect",
                 "layout=side-by-side needs an even width to split into two lenses; got 71x36");
  expect_refused("convert " + p("dual.png") + " " + p("o.png") + " --from dual-fisheye:fov=200 --to equirect --antialias mip",
                 "antialias mip does not blend the lenses");
}

TEST_F(Cli, AlphaAndFillAtTheFieldsEdge) {
  ASSERT_EQ(run("convert " + p("pano.png") + " " + p("a.png") + " --to fisheye:fov=180 --size 41x41 --alpha -q").code, 0);
  const Image a = read_image(p("a.png"));
  ASSERT_EQ(a.channels(), 4);
  EXPECT_EQ(a.pixel(0, 0)[3], 0);     // outside the circle
  EXPECT_EQ(a.pixel(20, 20)[3], 255);  // inside
  int partial = 0;
  for (int64_t x = 0; x < 41; ++x) partial += a.pixel(x, 3)[3] > 0 && a.pixel(x, 3)[3] < 255;
  EXPECT_GT(partial, 0);  // the rim, antialiased
  ASSERT_EQ(run("convert " + p("pano.png") + " " + p("f.png") + " --to fisheye:fov=180 --size 41x41 --fill '#ff0000' -q").code, 0);
  const Image f = read_image(p("f.png"));
  ASSERT_EQ(f.channels(), 3);
  EXPECT_EQ(f.pixel(0, 0)[0], 255);
  EXPECT_EQ(f.pixel(0, 0)[1], 0);
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to fisheye --fill red", "fill colour 'red' is not R,G,B[,A]");
}

TEST_F(Cli, InfoListsEveryProjection) {
  const CliRun r = run("info");
  ASSERT_EQ(r.code, 0);
  for (const auto& d : projection_catalog()) {
    EXPECT_NE(r.out.find(std::string("  ") + d.name + " - "), std::string::npos) << d.name;
    for (const auto& prm : d.params) EXPECT_NE(r.out.find(std::string(prm.key) + "="), std::string::npos);
  }
}

TEST_F(Cli, UnknownProjection) {
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to fishey", "unknown projection 'fishey'");
}

TEST_F(Cli, BadParameters) {
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to fisheye:fov=nan", "fov=nan is not finite");
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to fisheye:fov=-5", "fov=-5 is out of range");
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to fisheye:fov=400", "fov=400 is out of range");
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to pinhole:hfov=180", "hfov=180 is out of range");
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to equirect --yaw nan", "yaw: nan");
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to equirect --size 0x5", "size: 0x5");
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to equirect --interp cubic", "interpolator 'cubic'");
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to equirect --antialias 40", "antialias '40'");
  expect_refused("convert " + p("pano.png") + " " + p("o.png") + " --to equirect --engine reference --antialias auto",
                 "needs the simd or scalar engine");
}

TEST_F(Cli, AccuracyReportsErrorAgainstTime) {
  // A small sweep: the table, CSV, JSON and plot; antialiasing beats none on the shrunk chart.
  const std::string base = "accuracy --from-size 512x256 --to fisheye:fov=180 --size 64x64 --runs 1 --threads 2 "
                           "--interp bilinear --truth-supersample 6 ";
  const CliRun r = run(base + "--csv " + p("a.csv") + " --json " + p("a.json") + " --plot " + p("a.png"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| memory | bilinear | auto | simd |"), std::string::npos) << r.out;
  std::ifstream csv(p("a.csv"));
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "source,kernel,antialias,engine,median_ms,psnr_db,rmse,max_abs,ssim,pixels,pareto");
  std::map<std::string, double> psnr;
  int rows = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    ASSERT_EQ(f.size(), 11u) << line;
    psnr[f[2] + "/" + f[3]] = std::stod(f[5]);
    ++rows;
  }
  EXPECT_EQ(rows, 5);  // off, auto, mip, 4 on simd; off on reference
  EXPECT_GT(psnr["auto/simd"], psnr["off/simd"] + 3) << r.out;
  EXPECT_GT(psnr["4/simd"], psnr["off/simd"] + 3) << r.out;
  EXPECT_GT(psnr["mip/simd"], psnr["off/simd"] + 3) << r.out;
  EXPECT_NEAR(psnr["off/reference"], psnr["off/simd"], 0.05) << "exact and float geometry agree";
  std::ifstream json(p("a.json"));
  const std::string js((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_EQ(std::count(js.begin(), js.end(), '{'), 6) << js;
  EXPECT_NE(js.find("\"about\": \"scene chart, equirect 512x256 -> fisheye:fov=180 64x64"), std::string::npos) << js;
  EXPECT_EQ(read_image(p("a.png")).width(), 960);
  // Existing outputs are kept unless --overwrite; bad lists name the item.
  expect_refused(base + "--csv " + p("a.csv"), "a.csv exists");
  expect_refused(base + "--antialias off,sometimes", "antialias 'sometimes'");
  expect_refused(base + "--scene clouds", "scene 'clouds'");
  expect_refused(base + "--type keep", "type: keep");
}

// The chart shrunk 8 times (mip levels): the source as a file decoded whole, or at 1/4 (which the
// view allows: still twice the detail the output holds), within a dB of the source in memory: a
// JPEG (quality 95) for uint8, a Radiance HDR (block means) for float.
TEST_F(Cli, AccuracyWeighsScaledDecodes) {
  const std::string base = "accuracy --from-size 1024x512 --to equirect --size 128x64 --runs 1 --threads 2 "
                           "--interp bilinear --antialias mip --engine simd --truth-supersample 6 ";
  for (const std::string file : {"jpeg", "hdr"}) {
    const std::string type = file == "jpeg" ? "uint8" : "float";
    const CliRun r = run(base + "--type " + type + " --decode-scale memory,1,4 --csv " + p(file + ".csv"));
    ASSERT_EQ(r.code, 0) << r.err;
    std::ifstream csv(p(file + ".csv"));
    std::map<std::string, double> psnr;
    std::string line;
    std::getline(csv, line);  // the header
    while (std::getline(csv, line)) {
      std::vector<std::string> f;
      std::stringstream ss(line);
      for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
      psnr[f[0]] = std::stod(f[5]);
    }
    ASSERT_EQ(psnr.size(), 3u) << r.out;
    EXPECT_NEAR(psnr[file], psnr["memory"], 1.0) << r.out;
    EXPECT_NEAR(psnr[file + " 1/4"], psnr[file], 1.0) << r.out;
    EXPECT_NE(r.out.find("| " + file + " 1/4 | bilinear | mip | simd |"), std::string::npos) << r.out;
  }
  expect_refused(base + "--decode-scale 3", "--decode-scale: 3 (expected memory, 1, 2, 4 or 8");
  expect_refused(base + "--decode-scale 4 --type uint16",
                 "no file format decodes uint16 samples at 1/2 to 1/8 scale (JPEG: uint8, Radiance "
                 "HDR: float)");
  expect_refused("accuracy --from-size 500x250 --to fisheye --size 32x32 --runs 1 --decode-scale 4",
                 "needs the source's sides (500x250) to be multiples of it");
}

TEST_F(Cli, StabilityReportPasses) {
  const CliRun r = run("stability");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("| fisheye:fov=359.99,model=equisolid | 40000x40000 |"), std::string::npos);
  EXPECT_NE(r.out.find(" 0 outside their bounds"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("| NO |"), std::string::npos) << r.out;
}

TEST_F(Cli, MissingFile) {
  expect_refused("convert " + p("nope.png") + " " + p("o.png") + " --to equirect", "nope.png does not exist");
}

TEST_F(Cli, CorruptFile) {
  std::ifstream in(p("pano.png"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::ofstream(p("cut.png"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::ofstream(p("junk.jpg"), std::ios::binary) << std::string(3000, 'x');
  expect_refused("convert " + p("cut.png") + " " + p("o.png") + " --to equirect", "cannot read " + p("cut.png"));
  expect_refused("convert " + p("junk.jpg") + " " + p("o.png") + " --to equirect", "cannot read " + p("junk.jpg"));
}

TEST_F(Cli, MismatchedCubeFaces) {
  for (int f = 0; f < 6; ++f) write_image(Image({f == 4 ? 12 : 16, f == 4 ? 12 : 16}, 3, PixelType::U8), p("m_" + std::to_string(f) + ".png"), {});
  expect_refused("convert '" + p("m_{index}.png") + "' " + p("o.png") + " --to equirect", "all six faces must match");
}

TEST_F(Cli, OutputIsInputOrExists) {
  expect_refused("convert " + p("pano.png") + " " + p("pano.png") + " --to equirect", "is the input");
  expect_refused("convert " + p("pano.png") + " " + p("./pano.png") + " --to equirect --overwrite", "is the input");
  expect_refused("convert " + p("pano.png") + " " + p("square.png") + " --to equirect", "exists (pass --overwrite");
  ASSERT_EQ(run("convert " + p("pano.png") + " " + p("square.png") + " --to equirect --overwrite").code, 0);
  EXPECT_EQ(read_image(p("square.png")).width(), 64);
}

TEST_F(Cli, NeedsFromUnlessTwoToOne) {
  expect_refused("convert " + p("square.png") + " " + p("o.png") + " --to equirect", "give --from SPEC");
  ASSERT_EQ(run("convert " + p("square.png") + " " + p("o.png") + " --from fisheye:fov=180 --to equirect").code, 0);
}

}  // namespace
}  // namespace panoproj
