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

}  // namespace
}  // namespace panoproj
