// Spherical video metadata (jobs/video_spherical.hpp) written by the convert job and read
// back by two independent readers (ffprobe's side data, exiftool's sv3d tags), and read by the
// job: a file with metadata converts as with the --from and pose it says. Poses and bad boxes are
// made by patching the boxes of an MP4 panoproj wrote (same sizes, so the file stays valid).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <functional>

#include "io/container_spherical.hpp"
#include "io/video_plugin.hpp"
#include "job_support.hpp"
#include "panoproj/error.hpp"
#include "panoproj/jobs.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

namespace fs = std::filesystem;

using test::shell;

class Spherical : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("panoproj_spherical_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::string cmd =
        "ffmpeg -v error -y -f lavfi -i "
        "'testsrc2=size=256x128:rate=10:duration=0.5,gblur=sigma=1.5' "
        "-pix_fmt yuv420p -c:v libx264 '" +
        p("in.mp4") + "'";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string p(const std::string& name) const { return (dir_ / name).string(); }

  // Converts in to out (FFV1 where out is .mkv: lossless), returning the warnings.
  std::vector<std::string> convert(const std::string& in, const std::string& out,
                                   const std::string& dst, const std::string& size,
                                   std::vector<std::pair<const char*, OptionValue>> more = {}) {
    std::vector<std::pair<const char*, OptionValue>> args = {
        {"inputs", std::vector<std::string>{in}}, {"output", out}, {"dst", dst}, {"size", size}};
    if (out.ends_with(".mkv")) args.push_back({"codec", std::string("ffv1")});
    for (auto& a : more) args.push_back(std::move(a));
    std::vector<std::string> warnings;
    JobEvents events;
    events.warning = [&](const std::string& w) { warnings.push_back(w); };
    job_named("convert").run(test::job_args("convert", std::move(args)), events);
    return warnings;
  }

  static std::string side_data(const std::string& file) {
    return shell(
        "ffprobe -v error -select_streams v -show_entries stream_side_data -of "
        "default=nw=1 '" +
        file + "'");
  }
  std::string frames_md5(const std::string& file) const {
    return shell("ffmpeg -v error -i '" + file + "' -f framemd5 - | grep -v '^#'");
  }

  // Overwrites the bytes after box `type`'s header (and its version and flags) with `bytes`.
  static void patch_box(const std::string& file, const char* type,
                        const std::vector<uint8_t>& bytes) {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const size_t at = all.find(type);
    ASSERT_NE(at, std::string::npos) << type << " not in " << file;
    f.seekp(static_cast<std::streamoff>(at + 8));
    f.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  }
  static std::vector<uint8_t> be32(std::vector<int64_t> values) {
    std::vector<uint8_t> out;
    for (int64_t v : values)
      for (int s = 24; s >= 0; s -= 8)
        out.push_back(static_cast<uint8_t>(static_cast<uint32_t>(v) >> s));
    return out;
  }

  fs::path dir_;
};

TEST_F(Spherical, EquirectsFullAndCroppedAreReadByFfprobeAndExiftool) {
  for (const char* ext : {".mp4", ".mkv"}) {
    const std::string full = p(std::string("full") + ext), crop = p(std::string("crop") + ext);
    EXPECT_TRUE(convert(p("in.mp4"), full, "equirect", "256x128").empty());
    const std::string f = side_data(full);
    EXPECT_NE(
        f.find(
            "side_data_type=Spherical Mapping\nprojection=equirectangular\nyaw=0\npitch=0\nroll=0"),
        std::string::npos)
        << f;
    // 180 x 90 degrees centred at longitude 45: 96 px of 256 off the left, 32 off the right, 32
    // off the top and the bottom (ffprobe's pixels round up: +-1).
    EXPECT_TRUE(convert(p("in.mp4"), crop, "equirect:hfov=180,vfov=90,lon0=45", "128x64").empty());
    const std::string c = side_data(crop);
    EXPECT_NE(c.find("projection=tiled equirectangular"), std::string::npos) << c;
    for (auto [key, px] : {std::pair{"bound_left=", 96},
                           {"bound_right=", 32},
                           {"bound_top=", 32},
                           {"bound_bottom=", 32}}) {
      const size_t at = c.find(key);
      ASSERT_NE(at, std::string::npos) << key << c;
      EXPECT_NEAR(std::atoi(c.c_str() + at + std::strlen(key)), px, 1) << key << " " << ext;
    }
  }
  // exiftool's reading of the MP4's boxes: the bounds as fractions.
  const std::string x =
      shell("exiftool -n -s -ProjectionBounds* -PoseYawDegrees '" + p("crop.mp4") + "'");
  for (auto [key, v] : {std::pair{"ProjectionBoundsLeft", 0.375},
                        {"ProjectionBoundsRight", 0.125},
                        {"ProjectionBoundsTop", 0.25},
                        {"ProjectionBoundsBottom", 0.25}}) {
    const size_t at = x.find(std::string(key) + " ");
    ASSERT_NE(at, std::string::npos) << key << "\n" << x;
    EXPECT_NEAR(std::atof(x.c_str() + x.find(':', at) + 1), v, 1e-9) << key;
  }
}

TEST_F(Spherical, StereoAndCubesAreWrittenWhereTheBoxesSayThemAndOthersSayWhyNot) {
  for (const char* ext : {".mp4", ".mkv"}) {
    const std::string tb = p(std::string("tb") + ext), sbs = p(std::string("sbs") + ext);
    convert(p("in.mp4"), tb, "equirect:stereo=tb", "128x128");
    convert(p("in.mp4"), sbs, "equirect:stereo=sbs,hfov=180", "256x128");
    EXPECT_NE(side_data(tb).find("side_data_type=Stereo 3D\ntype=top and bottom\ninverted=0"),
              std::string::npos)
        << side_data(tb);
    EXPECT_NE(side_data(sbs).find("side_data_type=Stereo 3D\ntype=side by side\ninverted=0"),
              std::string::npos)
        << side_data(sbs);
    const std::string cube = p(std::string("cube") + ext);
    EXPECT_TRUE(convert(p("in.mp4"), cube, "cubemap:layout=3x2,order=rludfb", "192x128").empty());
    EXPECT_NE(side_data(cube).find("projection=cubemap"), std::string::npos) << side_data(cube);
  }
  // A cube in another order, an EAC, a pinhole, a .mov: no box, one warning saying why.
  for (auto [dst, out, size, why] :
       {std::tuple{"cubemap:layout=3x2", "c.mp4", "192x128", "only a 3x2 cube in layout 0's order"},
        {"cubemap:layout=eac", "eac.mp4", "192x128", "mshp"},
        {"pinhole:hfov=90", "pin.mkv", "64x64", "equirects and cubes only"},
        {"equirect", "e.mov", "256x128", "not mov"}}) {
    const auto w = convert(p("in.mp4"), p(out), dst, size);
    ASSERT_EQ(w.size(), 1u) << dst;
    EXPECT_NE(w[0].find("no spherical metadata written"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find(why), std::string::npos) << w[0];
    EXPECT_EQ(side_data(p(out)).find("Spherical"), std::string::npos) << dst;
  }
}

TEST_F(Spherical, AFileWithMetadataConvertsAsWithTheFromItSays) {
  struct Case {
    const char* ext;
    const char* spec;
    const char* size;
  };
  for (const Case& c : {Case{".mkv", "equirect:hfov=180,vfov=90,lon0=45", "128x64"},
                        Case{".mp4", "equirect:hfov=180,vfov=90,lon0=45", "128x64"},
                        Case{".mkv", "equirect:stereo=tb", "128x128"},
                        Case{".mkv", "equirect:stereo=sbs,hfov=180", "256x128"},
                        Case{".mkv", "cubemap:layout=3x2,order=rludfb", "192x128"}}) {
    const std::string in = p(std::string("meta") + c.ext);
    fs::remove(in);
    convert(p("in.mp4"), in, c.spec, c.size);
    const std::string a = p("a.mkv"), b = p("b.mkv");
    fs::remove(a), fs::remove(b);
    // (A fisheye output has no metadata: one warning saying so.)
    const auto says = [](const std::vector<std::string>& w) {
      std::string all;
      for (const std::string& line : w)
        if (line.find("no spherical metadata written") == std::string::npos) all += line;
      return all;
    };
    EXPECT_EQ(says(convert(in, a, "fisheye:fov=180", "96x96")), "") << c.spec;
    EXPECT_EQ(says(convert(in, b, "fisheye:fov=180", "96x96", {{"src", std::string(c.spec)}})), "")
        << c.spec;
    EXPECT_EQ(frames_md5(a), frames_md5(b)) << c.spec;
    // Another --from wins, with a warning naming what the metadata says.
    const std::string other =
        says(convert(in, p("c.mkv"), "fisheye:fov=180", "96x96",
                     {{"src", std::string("pinhole:hfov=100")}, {"overwrite", true}}));
    EXPECT_NE(other.find("is used; its spherical metadata says"), std::string::npos) << other;
  }
}

TEST_F(Spherical, ThePoseLevelsTheFrames) {
  // FFmpeg's pose (libavutil/spherical.h): the frame's sphere turned by R_y(yaw) R_x(pitch)
  // R_z(roll), positive yaw to the right; levelling undoes it, as the view's opposite turn.
  convert(p("in.mp4"), p("level.mp4"), "equirect", "256x128");
  for (auto [yaw, pitch, roll, option, value] : {std::tuple{30, 0, 0, "yaw", -30.0},
                                                 {0, 20, 0, "pitch", -20.0},
                                                 {0, 0, 15, "roll", -15.0}}) {
    const std::string posed = p("posed.mp4");
    fs::copy_file(p("level.mp4"), posed, fs::copy_options::overwrite_existing);
    patch_box(posed, "prhd", be32({yaw * 65536, pitch * 65536, roll * 65536}));
    EXPECT_NE(side_data(posed).find("yaw=" + std::to_string(yaw)), std::string::npos);
    const std::string a = p("a.mkv"), b = p("b.mkv");
    fs::remove(a), fs::remove(b);
    convert(posed, a, "pinhole:hfov=100", "96x64");
    convert(p("level.mp4"), b, "pinhole:hfov=100", "96x64", {{option, value}});
    EXPECT_EQ(frames_md5(a), frames_md5(b)) << option;
    EXPECT_NE(frames_md5(a), frames_md5(p("level.mp4"))) << option;
    if (yaw == 0) continue;
    // The views of its frames too (SfM from a posed clip): a ring turned by the pose's opposite.
    const auto views = [&](const std::string& in, const std::string& out, const std::string& rig) {
      test::run_job("views", test::job_args("views", {{"images", std::vector<std::string>{in}},
                                                      {"out_dir", p(out)},
                                                      {"size", std::string("32x32")},
                                                      {"format", std::string("png")},
                                                      {"rig", rig},
                                                      {"every", int64_t{4}}}));
      std::map<std::string, std::string> files;
      for (const auto& e : fs::directory_iterator(p(out) + "/images")) {
        std::ifstream f(e.path(), std::ios::binary);
        files[e.path().filename().string()] =
            std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
      }
      fs::remove_all(p(out));
      return files;
    };
    const auto va = views(posed, "va", "ring:n=4");
    fs::copy_file(p("level.mp4"), posed, fs::copy_options::overwrite_existing);  // (same names)
    const auto vb = views(posed, "vb", "ring:n=4,yaw=-30");
    EXPECT_EQ(va.size(), 8u);
    // (Named by their yaw in the ring: y000 posed, y330 level; in the same order.)
    std::vector<std::string> ia, ib;
    for (const auto& [name, bytes] : va) ia.push_back(bytes);
    for (const auto& [name, bytes] : vb) ib.push_back(bytes);
    std::rotate(ib.begin(), ib.begin() + 3, ib.begin() + 4);
    std::rotate(ib.begin() + 4, ib.begin() + 7, ib.end());
    EXPECT_TRUE(ia == ib);
  }
}

TEST_F(Spherical, MetadataPanoprojDoesNotReadIsRefusedInOneLine) {
  // A right-left stereo frame (Matroska's StereoMode 11; libavformat 5.1 drops an MP4's st3d
  // mode 4 unread).
  convert(p("in.mp4"), p("sbs.mkv"), "equirect:stereo=sbs", "256x64");
  {
    std::fstream f(p("sbs.mkv"), std::ios::in | std::ios::out | std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const size_t at = all.find("\x53\xB8\x81\x01");
    ASSERT_NE(at, std::string::npos);
    f.seekp(static_cast<std::streamoff>(at + 3));
    f.put('\x0B');
  }
  try {
    convert(p("sbs.mkv"), p("o.mkv"), "equirect", "256x128");
    ADD_FAILURE() << "converted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("its spherical metadata says stereo layout"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(p("o.mkv")));
}

// panoproj's own reader and writer of the MP4 boxes (io/container_spherical.hpp, for video through
// PyAV) against libavformat's, the second parser of the files the plugin writes.
SphericalVideo libavformat_reads(const std::string& file) {
  return video_backend("reading " + file).open(file, -1, false)->info().spherical;
}

void expect_same(const SphericalVideo& a, const SphericalVideo& b, const std::string& what) {
  EXPECT_EQ(static_cast<int>(a.kind), static_cast<int>(b.kind)) << what;
  EXPECT_EQ(a.name, b.name) << what;
  for (auto [x, y] : {std::pair{a.top, b.top},
                      {a.bottom, b.bottom},
                      {a.left, b.left},
                      {a.right, b.right},
                      {a.yaw, b.yaw},
                      {a.pitch, b.pitch},
                      {a.roll, b.roll}})
    EXPECT_EQ(x, y) << what;
  EXPECT_EQ(a.padding, b.padding) << what;
  EXPECT_EQ(static_cast<int>(a.stereo), static_cast<int>(b.stereo)) << what;
  EXPECT_EQ(a.stereo_name, b.stereo_name) << what;
}

TEST_F(Spherical, PanoprojsOwnReaderReadsWhatLibavformatReads) {
  const std::vector<std::pair<const char*, const char*>> files = {
      {"equirect", "256x128"},
      {"equirect:hfov=180,vfov=90,lon0=45", "128x64"},
      {"cubemap:layout=3x2,order=rludfb", "192x128"},
      {"equirect:stereo=tb", "256x256"},
      {"equirect:stereo=sbs,hfov=180", "256x128"}};
  for (const char* ext : {".mp4", ".mkv"})
    for (size_t i = 0; i < files.size(); ++i) {
      const std::string f = p("f" + std::to_string(i) + ext);
      convert(p("in.mp4"), f, files[i].first, files[i].second);
      if (i == 0 && std::string(ext) == ".mp4")
        patch_box(f, "prhd", be32({30 << 16, -(10 << 16) - 32768, 5 << 16}));
      const SphericalVideo theirs = libavformat_reads(f);
      ASSERT_TRUE(theirs.any()) << files[i].first << ext;
      expect_same(std::string(ext) == ".mp4" ? spherical_of_moov(read_moov(f), 0, f)
                                             : read_matroska_spherical(f, 0, f),
                  theirs, files[i].first + std::string(ext));
    }
  // Matroska's right-left StereoMode (11), and a pose in its Projection (as floats).
  std::ifstream in(p("f4.mkv"), std::ios::binary);
  std::string mkv((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t stereo = mkv.find("\x53\xb8\x81\x01");
  ASSERT_NE(stereo, std::string::npos);
  mkv[stereo + 3] = '\x0b';
  // (the Projection's 20-byte ProjectionPrivate, 23 bytes with its header, made a PoseYaw of 8
  // bytes, a PosePitch of 4 and a Void element: the same length, so nothing else moves)
  const size_t priv = mkv.find("\x76\x72\x94", mkv.find("\x76\x70"));
  ASSERT_NE(priv, std::string::npos);
  std::string pose = "\x76\x73\x88" + std::string(8, '\0') + "\x76\x74\x84" + std::string(4, '\0') +
                     "\xec\x83" + std::string(3, '\0');
  const double yaw = 12.3;
  const float pitch = -4.5f;
  uint64_t y;
  uint32_t q;
  std::memcpy(&y, &yaw, 8), std::memcpy(&q, &pitch, 4);
  for (int k = 0; k < 8; ++k)
    pose[3 + static_cast<size_t>(k)] = static_cast<char>(y >> (56 - 8 * k));
  for (int k = 0; k < 4; ++k)
    pose[14 + static_cast<size_t>(k)] = static_cast<char>(q >> (24 - 8 * k));
  ASSERT_EQ(pose.size(), 23u);
  mkv.replace(priv, 23, pose);
  const std::string rl = p("right_left.mkv");
  std::ofstream(rl, std::ios::binary).write(mkv.data(), static_cast<std::streamsize>(mkv.size()));
  expect_same(read_matroska_spherical(rl, 0, rl), libavformat_reads(rl), "right-left");
  EXPECT_EQ(read_matroska_spherical(rl, 0, rl).stereo_name, "side by side (inverted)");
  EXPECT_NEAR(read_matroska_spherical(rl, 0, rl).yaw, 12.3, 1 / 65536.0);
  EXPECT_EQ(read_matroska_spherical(rl, 0, rl).pitch, -4.5);
  EXPECT_FALSE(spherical_of_moov(read_moov(p("in.mp4")), 0, "in.mp4").any());
}

TEST_F(Spherical, BoxesPanoprojWritesAreReadByLibavformatAndExiftool) {
  convert(p("in.mp4"), p("plain.mp4"), "equirect", "256x128", {{"no_metadata", true}});
  SphericalVideo crop;
  crop.kind = SphericalVideo::Kind::Equirect, crop.name = "tiled equirectangular";
  crop.top = 0.25, crop.bottom = 0.125, crop.left = 0.375, crop.right = 0.0625;
  crop.yaw = 12.5, crop.pitch = -3.25, crop.roll = 181;
  SphericalVideo cube;
  cube.kind = SphericalVideo::Kind::Cubemap, cube.name = "cubemap", cube.padding = 2;
  SphericalVideo tb;
  tb.kind = SphericalVideo::Kind::Equirect, tb.name = "equirectangular";
  tb.stereo = SphericalVideo::Stereo::TopBottom, tb.stereo_name = "top and bottom";
  const std::string frames = frames_md5(p("plain.mp4"));
  for (const SphericalVideo& v : {crop, cube, tb}) {
    const std::string f = p(v.name + ".mp4");
    fs::copy_file(p("plain.mp4"), f, fs::copy_options::overwrite_existing);
    const int fd = ::open(f.c_str(), O_WRONLY);  // (as the job's temporary: for writing only)
    ASSERT_GE(fd, 0);
    write_mp4_spherical(fd, f, v);
    ::close(fd);
    SphericalVideo read = libavformat_reads(f);
    for (double* x : {&read.top, &read.bottom, &read.left, &read.right})
      *x = std::round(*x * 1e6) / 1e6;                        // (0.32 fixed point, floored)
    read.roll = read.roll < 0 ? read.roll + 360 : read.roll;  // (16.16: -179 for 181)
    expect_same(read, v, v.name);
    expect_same(spherical_of_moov(read_moov(f), 0, f), libavformat_reads(f),
                v.name + ", read back");
    EXPECT_EQ(frames_md5(f), frames) << v.name;
  }
  const std::string x =
      shell("exiftool -n -s -ProjectionBoundsLeft -PoseYawDegrees -PosePitchDegrees '" +
            p("tiled equirectangular.mp4") + "'");
  for (auto [key, want] : {std::pair{"ProjectionBoundsLeft", 0.375},
                           {"PoseYawDegrees", 12.5},
                           {"PosePitchDegrees", -3.25}}) {
    const size_t at = x.find(std::string(key) + " ");
    ASSERT_NE(at, std::string::npos) << key << "\n" << x;
    EXPECT_NEAR(std::atof(x.c_str() + x.find(':', at) + 1), want, 1e-9) << key;
  }
}

// An MP4 with Spherical Video V1's uuid box (its XML) put into its video trak after tkhd (its
// moov ends the file: no chunk offset moves).
void put_v1(const std::string& file, const std::string& xml) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const auto size_at = [&](size_t at) {
    return static_cast<size_t>(static_cast<unsigned char>(all[at])) << 24 |
           static_cast<size_t>(static_cast<unsigned char>(all[at + 1])) << 16 |
           static_cast<size_t>(static_cast<unsigned char>(all[at + 2])) << 8 |
           static_cast<unsigned char>(all[at + 3]);
  };
  const auto set_size = [&](size_t at, size_t v) {
    for (int i = 0; i < 4; ++i)
      all[at + static_cast<size_t>(i)] = static_cast<char>(v >> (24 - 8 * i));
  };
  const size_t moov = all.rfind("moov") - 4, trak = all.find("trak", moov) - 4,
               tkhd = all.find("tkhd", trak) - 4;
  ASSERT_EQ(moov + size_at(moov), all.size()) << "moov is not last in " << file;
  const std::string uuid("\xff\xcc\x82\x63\xf8\x55\x4a\x93\x88\x14\x58\x7a\x02\x52\x1f\xdd", 16);
  const std::string box = std::string(4, '\0') + "uuid" + uuid + xml;
  all.insert(tkhd + size_at(tkhd), box);
  set_size(tkhd + size_at(tkhd), box.size());
  set_size(trak, size_at(trak) + box.size());
  set_size(moov, size_at(moov) + box.size());
  f.seekp(0);
  f.write(all.data(), static_cast<std::streamsize>(all.size()));
}

TEST_F(Spherical, SphericalVideoV1IsReadAsLibavformatReadsIt) {
  const std::string xml_head =
      "<?xml version=\"1.0\"?><rdf:SphericalVideo xmlns:rdf=\"http://www.w3.org/1999/02/"
      "22-rdf-syntax-ns#\" xmlns:GSpherical=\"http://ns.google.com/videos/1.0/spherical/\">"
      "<GSpherical:Spherical>true</GSpherical:Spherical><GSpherical:Stitched>true</"
      "GSpherical:Stitched><GSpherical:StitchingSoftware>panoproj's test</"
      "GSpherical:StitchingSoftware><GSpherical:ProjectionType>equirectangular</"
      "GSpherical:ProjectionType>";
  const std::vector<std::string> bodies = {
      "<GSpherical:InitialViewHeadingDegrees>90</GSpherical:InitialViewHeadingDegrees>",
      "<GSpherical:StereoMode>top-bottom</GSpherical:StereoMode>"
      "<GSpherical:InitialViewPitchDegrees>-20</GSpherical:InitialViewPitchDegrees>",
      "<GSpherical:StereoMode>left-right</GSpherical:StereoMode>"};
  convert(p("in.mp4"), p("plain.mp4"), "equirect", "256x128", {{"no_metadata", true}});
  for (size_t i = 0; i < bodies.size(); ++i) {
    const std::string f = p("v1_" + std::to_string(i) + ".mp4");
    fs::copy_file(p("plain.mp4"), f, fs::copy_options::overwrite_existing);
    put_v1(f, xml_head + bodies[i] + "</rdf:SphericalVideo>");
    const SphericalVideo theirs = libavformat_reads(f);
    ASSERT_EQ(static_cast<int>(theirs.kind), static_cast<int>(SphericalVideo::Kind::Equirect))
        << bodies[i];
    expect_same(spherical_of_moov(read_moov(f), 0, f), theirs, bodies[i]);
  }
  // (The initial view's heading is where a viewer starts looking, not a pose: 0 in both.)
  EXPECT_EQ(libavformat_reads(p("v1_0.mp4")).yaw, 0);
  EXPECT_EQ(static_cast<int>(libavformat_reads(p("v1_1.mp4")).stereo),
            static_cast<int>(SphericalVideo::Stereo::TopBottom));
  // Without StitchingSoftware neither reads it.
  const std::string f = p("v1_no.mp4");
  fs::copy_file(p("plain.mp4"), f, fs::copy_options::overwrite_existing);
  put_v1(
      f,
      "<GSpherical:Spherical>true</GSpherical:Spherical><GSpherical:Stitched>true</"
      "GSpherical:Stitched><GSpherical:ProjectionType>equirectangular</GSpherical:ProjectionType>");
  EXPECT_FALSE(libavformat_reads(f).any());
  EXPECT_FALSE(spherical_of_moov(read_moov(f), 0, f).any());
}

TEST_F(Spherical, MalformedOrMisplacedBoxesAreRefusedInOneLine) {
  convert(p("in.mp4"), p("e.mp4"), "equirect", "256x128");
  const std::string moov = read_moov(p("e.mp4"));
  ASSERT_FALSE(moov.empty());
  const auto refused = [&](const std::function<void()>& f, const std::string& needle) {
    try {
      f();
      ADD_FAILURE() << "not refused: " << needle;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  };
  std::string past = moov;
  const size_t trak = past.find("trak") - 4;
  past[trak] = '\x7f';  // (a trak of 2 GB in a moov of kB)
  refused([&] { spherical_of_moov(past, 0, "e.mp4"); }, "e.mp4: its box trak runs past its parent");
  std::string crossed = moov;
  const size_t equi = crossed.find("equi") + 8;
  crossed.replace(equi, 8, "\xff\xff\xff\x00\x00\x00\x01\x00", 8);
  refused([&] { spherical_of_moov(crossed, 0, "e.mp4"); }, "equi bounds cross");
  SphericalVideo v;
  v.kind = SphericalVideo::Kind::Equirect;
  refused([&] { moov_with_spherical(moov, v); }, "its video track has a sv3d box already");
  // A moov before the frames (faststart) cannot grow in place: refused, the file as it was.
  convert(p("in.mp4"), p("plain.mp4"), "equirect", "256x128", {{"no_metadata", true}});
  shell("ffmpeg -v error -i '" + p("plain.mp4") + "' -c copy -movflags +faststart '" +
        p("fast.mp4") + "'");
  const std::string before = shell("md5sum < '" + p("fast.mp4") + "'");
  const int fd = ::open(p("fast.mp4").c_str(), O_WRONLY);
  refused([&] { write_mp4_spherical(fd, "fast.mp4", v); },
          "cannot write fast.mp4: its spherical metadata cannot be written: its moov box does not "
          "end the file");
  ::close(fd);
  EXPECT_EQ(shell("md5sum < '" + p("fast.mp4") + "'"), before);
}

}  // namespace
}  // namespace panoproj
