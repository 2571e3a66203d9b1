// Perspective views (jobs/views/views.hpp): rig texts parsed to the views they name, bad rigs
// refused naming the value, every view equal to convert() to its pinhole, the camera files'
// numbers, and the folder landing whole. (The cameras through independent readers, pycolmap and
// nerfstudio's convention, against the panorama: python/tests/test_views.py.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "job_support.hpp"
#include "jobs/views/views.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {
namespace fs = std::filesystem;
using namespace test;

TEST(RigText, CubeRingsSumsAndYamlNameTheirViews) {
  const auto cube = parse_rig("cube");
  ASSERT_EQ(cube.size(), 6u);
  const char* names[6] = {"front", "right", "back", "left", "up", "down"};
  const double angles[6][2] = {{0, 0}, {90, 0}, {180, 0}, {-90, 0}, {0, 90}, {0, -90}};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(cube[i].name, names[i]);
    EXPECT_EQ(cube[i].yaw, angles[i][0]);
    EXPECT_EQ(cube[i].pitch, angles[i][1]);
    EXPECT_EQ(cube[i].hfov, 90);
  }
  const auto ring = parse_rig("ring:n=8,fov=70,pitch=-20,yaw=10");
  ASSERT_EQ(ring.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    const double yaw = 10 + 45.0 * i;
    EXPECT_NEAR(std::remainder(ring[i].yaw - yaw, 360), 0, 1e-12);
    EXPECT_EQ(ring[i].pitch, -20);
    EXPECT_EQ(ring[i].hfov, 70);
  }
  EXPECT_EQ(ring[0].name, "y010_p-20");
  EXPECT_EQ(ring[7].name, "y325_p-20");
  EXPECT_EQ(parse_rig("cube+ring:n=4,pitch=45").size(), 10u);
  const auto yaml = parse_rig(
      "views:   # a comment\n"
      "  - name: a\n"
      "    yaw: 12.5\n"
      "    roll: -3\n"
      "    fov: 60\n"
      "    size: 640x480\n"
      "  - {name: b, pitch: 30, hfov: 100, vfov: 80}\n");
  ASSERT_EQ(yaml.size(), 2u);
  EXPECT_EQ(yaml[0].name, "a");
  EXPECT_EQ(yaml[0].yaw, 12.5);
  EXPECT_EQ(yaml[0].roll, -3);
  EXPECT_EQ(yaml[0].hfov, 60);
  EXPECT_EQ(yaml[0].width, 640);
  EXPECT_EQ(yaml[0].height, 480);
  EXPECT_EQ(yaml[1].pitch, 30);
  EXPECT_EQ(yaml[1].vfov, 80);
}

TEST(RigText, BadRigsAreRefusedNamingTheValue) {
  struct Case {
    std::string rig, needle;
  };
  const Case cases[] = {
      {"", "rig: empty"},
      {"sphere", "rig: 'sphere' (expected cube"},
      {"ring:n=0", "n: 0 (expected a whole number from 1 to 360)"},
      {"ring:n=2.5", "n: 2.5 (expected a whole number"},
      {"ring:fov=180", "hfov 180 (expected more than 0, at most 179"},
      {"ring:fov=nan", "fov: 'nan' (expected a finite number)"},
      {"ring:pitch=1e400", "pitch: '1e400' (expected a finite number)"},
      {"ring:tilt=3", "unknown key 'tilt'"},
      {"ring:n", "'n' (expected key=value"},
      {"cube+cube", "two views named front"},
      {"- {name: a/b}", "name 'a/b' (expected 1 to 64 letters"},
      {"- {name: a, yaw: 400}", "yaw 400 (expected -360 to 360"},
      {"- {name: a, size: 0x10}", "size: 0x10 (expected WxH with positive integers"},
      {"- {name: a, size: 100000x10}", "size 100000x10 (expected 1 to 65536 pixels a side)"},
      {"- {name: a, height: 10}", "a height without a width"},
      {"- {name: a, vfov: 40, size: 10x10}", "both vfov and a height"},
      {"- {name: a, name: b}", "'name' given twice"},
      {"- {name: a, zoom: 2}", "unknown key 'zoom'"},
      {"- {name: a", "a flow mapping ends with '}'"},
      {"- {yaw: 3}", "view 1 has no name"},
      {"views:\n  -\n\tname: a", "line 3: a tab"},
      {"@/nonexistent/rig.yaml",
       "the rig file /nonexistent/rig.yaml does not exist (check the path)"},
      {"@/dev/null",
       "cannot read the rig file /dev/null: a device (expected a YAML list of views after @)"},
  };
  for (const Case& c : cases) {
    try {
      parse_rig(c.rig);
      ADD_FAILURE() << "accepted: " << c.rig;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.needle), std::string::npos) << c.rig << " -> " << e.what();
    }
  }
  std::string many = "cube";
  for (int i = 0; i < 170; ++i) many += "+ring:n=6,yaw=" + std::to_string(i);
  EXPECT_THROW(parse_rig(many), Error);  // over 1000 views
}

class Views : public TempDirTest {
 protected:
  std::string source(const std::string& name, const std::string& spec, Size size) {
    const std::string path = this->path(name);
    WriteOptions w;
    w.overwrite = true;
    write_image(render(make_projection(parse_spec(spec), size), band_limited_scene(0.15, size.width), PixelType::U8), path, w);
    return path;
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
  }
};

// The views a run's report lists.
std::vector<ViewCamera> views_of(const Report& r) {
  std::vector<ViewCamera> out;
  for (const ReportValue& v : list(r, "views")) {
    const Report& c = item(v);
    ViewCamera cam{text(c, "name"), size(c, "size"), std::get<double>(field(c, "focal").value), {}};
    const auto& rows = list(c, "world_from_camera");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        cam.world_from_camera(i, j) =
            std::get<double>(std::get<std::vector<ReportValue>>(rows[i].value)[j].value);
    out.push_back(cam);
  }
  return out;
}

TEST_F(Views, EachViewIsTheConversionToItsPinholeTurnedByItsAngles) {
  const std::string input = source("pano.png", "equirect", {1024, 512});
  const std::string rig =
      "- {name: a, yaw: 30, pitch: 20, roll: -10, hfov: 80, size: 200x150}\n- {name: b, yaw: -150, "
      "pitch: -70, hfov: 60}";
  const std::vector<ViewCamera> views =
      views_of(run_job("views", job_args("views", {{"images", std::vector<std::string>{input}},
                                                   {"out_dir", path("out")},
                                                   {"rig", rig},
                                                   {"format", std::string("png")}})));
  ASSERT_EQ(views.size(), 2u);
  const Image src = read_image(input);
  for (const ViewCamera& c : views) {
    const ViewSpec v = parse_rig(rig)[c.name == "a" ? 0 : 1];
    ConvertOptions o;
    o.size = c.size;
    o.yaw = v.yaw, o.pitch = v.pitch, o.roll = v.roll;
    const Image want = convert(src, parse_spec("equirect"), parse_spec("pinhole:hfov=" + std::to_string(v.hfov)), o);
    const Image got = read_image(path("out/images/pano_" + c.name + ".png"));
    ASSERT_EQ(got.size(), want.size()) << c.name;
    EXPECT_EQ(got, want) << c.name;
    // The focal: hfov spans the width; b's size from the source's resolution (W / 2 pi per radian).
    EXPECT_NEAR(2 * std::atan(0.5 * static_cast<double>(c.size.width) / c.focal) * 180 / kPi, v.hfov, 1e-9);
    if (c.name == "b") {
      EXPECT_EQ(c.size.width, std::lround(2 * (1024 / (2 * kPi)) * std::tan(30 * kPi / 180)));
    }
    EXPECT_TRUE(c.world_from_camera.isApprox(rotation_from_ypr(v.yaw, v.pitch, v.roll), 1e-15));
  }
  // The camera files: PINHOLE with cx = W/2 (COLMAP's convention), the rig's sensors.
  std::istringstream cams(slurp(path("out/sparse/0/cameras.txt")));
  std::string line;
  int n = 0;
  while (std::getline(cams, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream l(line);
    int id;
    std::string model;
    double w, h, fx, fy, cx, cy;
    l >> id >> model >> w >> h >> fx >> fy >> cx >> cy;
    const ViewCamera& c = views[static_cast<size_t>(id - 1)];
    EXPECT_EQ(model, "PINHOLE");
    EXPECT_EQ(w, static_cast<double>(c.size.width));
    EXPECT_EQ(fx, c.focal);
    EXPECT_EQ(fy, c.focal);
    EXPECT_EQ(cx, w / 2);
    EXPECT_EQ(cy, h / 2);
    ++n;
  }
  EXPECT_EQ(n, 2);
  for (const char* f : {"images.txt", "points3D.txt", "rigs.txt", "frames.txt"}) EXPECT_TRUE(fs::exists(path("out/sparse/0/") + f));
  EXPECT_TRUE(fs::exists(path("out/transforms.json")));
}

TEST_F(Views, NothingLandsWhenAFrameFails) {
  struct {
    std::vector<std::string> inputs;
    std::string output;
    bool overwrite = false;
  } job;
  const auto run_views = [&](const auto& j) {
    return run_job("views", job_args("views", {{"images", j.inputs},
                                               {"out_dir", j.output},
                                               {"size", std::string("32x32")},
                                               {"overwrite", j.overwrite}}));
  };
  job.inputs = {source("a.png", "equirect", {256, 128}), source("b.png", "equirect", {256, 128})};
  job.output = path("out");
  // b's pixels damaged after its header was checked: the job fails at frame 2, nothing lands.
  std::string bytes = slurp(job.inputs[1]);
  bytes.resize(bytes.size() / 2);
  std::ofstream(job.inputs[1], std::ios::binary) << bytes;
  EXPECT_THROW(run_views(job), Error);
  EXPECT_FALSE(fs::exists(job.output));
  for (const auto& e : fs::directory_iterator(path("")))
    EXPECT_TRUE(e.path().extension() == ".png") << e.path();  // no temporary folder left
  // A second input of another size is refused before anything is rendered.
  job.inputs[1] = source("c.png", "equirect", {512, 256});
  try {
    run_views(job);
    ADD_FAILURE() << "two sizes accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a rig's frames need one size and projection"), std::string::npos) << e.what();
  }
  // An input inside the folder that --overwrite would replace.
  fs::create_directories(path("out"));
  job.inputs = {source("out/in.png", "equirect", {256, 128})};
  job.overwrite = true;
  EXPECT_THROW(run_views(job), Error);
  EXPECT_TRUE(fs::exists(path("out/in.png")));
}

}  // namespace
}  // namespace panoproj
