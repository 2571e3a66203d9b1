// Tile pyramids (jobs/tiles/tiles.hpp): each viewer's levels against its own rules (generate.py's
// flooring, Marzipano's multiples), every tile against its face rendered directly at its level,
// partial panoramas, parts in any order against the whole run, and the folder landing whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>

#include "io/atomic_output.hpp"
#include "io/codec.hpp"
#include "job_support.hpp"
#include "jobs/tiles/tile_layouts.hpp"
#include "jobs/tiles/tiles.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {
namespace fs = std::filesystem;
using namespace test;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

// Every file below dir, by relative path, with its bytes.
std::map<std::string, std::string> files_below(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return out;
}

// generate.py's numbers, as it computes them (cube 8 * int(W / pi / 8), levels by ceil(log2),
// each level int(size / 2) of the one above), for a full equirect W px wide.
std::vector<int64_t> generate_py_sizes(int64_t width, int64_t tile, int64_t& tile_out) {
  const int64_t cube = 8 * static_cast<int64_t>(static_cast<double>(width) / kPi / 8);
  tile_out = std::min(tile, cube);
  const int levels = static_cast<int>(std::ceil(std::log2(static_cast<double>(cube) / static_cast<double>(tile_out)))) + 1;
  std::vector<int64_t> sizes;
  for (int64_t size = cube, l = levels; l > 0; --l, size /= 2) sizes.insert(sizes.begin(), size);
  return sizes;
}

// The layout rows' defaults (the tiles job's rows).
TileSettings settings() {
  return {Viewer::Pannellum, 512, 0, 0, "jpg", 0, ""};
}

// The tiles job's arguments as these tests set them.
struct TilesJob {
  std::string input, output;
  std::optional<std::string> from;
  Viewer viewer = Viewer::Pannellum;
  int64_t tile = 512;
  std::string format = "jpg";
  double yaw = 0;
  bool overwrite = false;
  int64_t band_pixels = 0;
  Arguments args() const {
    Arguments a = job_args("tiles", {{"image", input},
                                     {"out_dir", output},
                                     {"viewer", std::string(name_of(viewer))},
                                     {"tile", tile},
                                     {"format", format},
                                     {"yaw", yaw},
                                     {"overwrite", overwrite}});
    if (from) a.set("src", *from);
    if (band_pixels) a.set("band_pixels", band_pixels);
    return a;
  }
  ConvertOptions options() const { return args().options(); }
};

// A run's pyramid and counts.
struct TilesRun {
  TilePyramid pyramid;
  int64_t written = 0, empty = 0;
};
TilesRun run_tiles(const TilesJob& job) {
  const Report r = run_job("tiles", job.args());
  return {tile_pyramid(job.args()), integer(r, "written"), integer(r, "empty")};
}

TEST(TileLayout, PannellumLevelsFollowGeneratePy) {
  for (int64_t width : {256, 1000, 4096, 8000, 10000, 32768, 100000})
    for (int tile : {256, 512, 1024}) {
      TileSettings job = settings();
      job.tile = tile;
      const TilePyramid p = make_pyramid(job, static_cast<double>(width) / (2 * kPi));
      int64_t t = 0;
      const std::vector<int64_t> want = generate_py_sizes(width, tile, t);
      ASSERT_EQ(p.tile, t) << width;
      ASSERT_EQ(p.levels.size(), want.size()) << width << " " << tile;
      int64_t count = 0;
      for (size_t l = 0; l < want.size(); ++l) {
        EXPECT_EQ(p.levels[l].size, want[l]) << width << " level " << l + 1;
        EXPECT_EQ(p.levels[l].name, static_cast<int>(l) + 1);
        const int64_t n = (want[l] + t - 1) / t;
        count += 6 * n * n;
      }
      EXPECT_EQ(p.tile_count(), count) << width;
      EXPECT_EQ(p.tile_path(want.size() - 1, 4, 2, 1), std::to_string(want.size()) + "/u2_1.jpg");
    }
}

TEST(TileLayout, MarzipanoLevelsAreMultiplesOfTheirTileAndTheirParent) {
  for (int64_t width : {300, 1000, 4096, 32768})
    for (int tile : {256, 384, 512}) {
      TileSettings job = settings();
      job.viewer = Viewer::Marzipano;
      job.tile = tile;
      const TilePyramid p = make_pyramid(job, static_cast<double>(width) / (2 * kPi));
      ASSERT_FALSE(p.levels.empty());
      // The preview level comes first: it and each level divide the next (Cube.js's checks).
      int64_t below = p.preview;
      for (const TileLevel& l : p.levels) {
        EXPECT_EQ(l.size % std::min<int64_t>(tile, l.size), 0) << width;
        EXPECT_EQ(l.size % below, 0) << width << ": " << l.size << " over " << below;
        below = l.size;
      }
      EXPECT_LE(p.preview, 256);
      EXPECT_EQ(p.tile_path(0, 2, 0, 0), "tiles/1/b/0/0.jpg");
      // The top level is the multiple nearest the source's resolution in scale.
      const double ratio = static_cast<double>(p.levels.back().size) / (static_cast<double>(width) / kPi);
      if (p.levels.back().size > tile) {
        EXPECT_TRUE(ratio > 0.7 && ratio < 1.42) << width << " " << ratio;
      }
    }
}

TEST(TileLayout, BadValuesAreRefusedNamingThem) {
  struct Case {
    void (*set)(TileSettings&);
    const char* needle;
  };
  const Case cases[] = {
      {[](TileSettings& j) { j.tile = 8; }, "--tile 8 is out of range"},
      {[](TileSettings& j) { j.tile = 100000; }, "--tile 100000 is out of range"},
      {[](TileSettings& j) { j.levels = 9; },
       "--levels 9: a 1296 px face in 512 px tiles has 3 levels"},
      {[](TileSettings& j) { j.levels = -1; }, "--levels -1 is out of range"},
      {[](TileSettings& j) { j.cube_size = 1 << 20; }, "--cube-size 1048576 is out of range"},
      {[](TileSettings& j) { j.viewer = Viewer::Marzipano, j.cube_size = 1000; },
       "--cube-size 1000 is not 512 x 2^k"},
      {[](TileSettings& j) { j.viewer = Viewer::Marzipano, j.preview = 100; },
       "--preview 100 does not divide"},
      {[](TileSettings& j) { j.format = "bmp"; },
       "--format bmp is not a format web viewers show (use jpg or png)"},
      {[](TileSettings& j) { j.script_url = "x\"onload=\"alert(1)"; },
       "has a character a page cannot hold"},
      {[](TileSettings& j) { j.cube_size = 65536; },
       "--cube-size 65536 is over 4x the source's resolution (1303 px a face)"},
  };
  for (const Case& c : cases) {
    TileSettings job = settings();
    c.set(job);
    try {
      make_pyramid(job, 4096 / (2 * kPi));
      ADD_FAILURE() << c.needle;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.needle), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse_viewer("krpano"), Error);
  // Millions of files: a 100000-px panorama in 16-px tiles.
  TileSettings job = settings();
  job.tile = 16;
  try {
    make_pyramid(job, 100000 / (2 * kPi));
    ADD_FAILURE() << "32 million tiles accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tiles (over 4194304 files: use larger tiles or fewer --levels)"), std::string::npos)
        << e.what();
  }
}

// The face letter in a tile's file name (Pannellum: <level>/<letter><row>_<col>; Marzipano:
// tiles/<z>/<letter>/...).
char letter(const TilePyramid& p, size_t level, int face) {
  const std::string path = p.tile_path(level, face, 0, 0);
  return p.viewer == Viewer::Pannellum ? path[path.find('/') + 1] : path[path.find('/', 6) + 1];
}

class Tiles : public TempDirTest {
 protected:
  // A band-limited equirect (detail at every level), or a partial one.
  std::string source(const std::string& spec, Size size) {
    const std::string path = this->path("src.png");
    const Projection p = make_projection(parse_spec(spec), size);
    WriteOptions w;
    w.overwrite = true;
    write_image(render(p, band_limited_scene(0.15, size.width), PixelType::U8), path, w);
    return path;
  }
  // The face rendered directly at size s (a 90-degree pinhole turned to the face, after the
  // job's own yaw), with the job's options.
  // The face is found by its letter in the tile's path; each letter's view, as both viewers
  // place their faces (Marzipano's Cube.js faceRotation, generate.py's nona views): yaw and pitch.
  Image face(const Image& src, const std::string& spec, const TilesJob& job, char letter, int64_t s, bool alpha) {
    const std::map<char, std::pair<double, double>> views{{'f', {0, 0}},   {'r', {90, 0}}, {'b', {180, 0}},
                                                          {'l', {-90, 0}}, {'u', {0, 90}}, {'d', {0, -90}}};
    ConvertOptions o = job.options();
    o.size = Size{s, s};
    o.yaw += views.at(letter).first, o.pitch += views.at(letter).second;
    if (alpha) o.add_alpha = true, o.edges.soft = true;
    return convert(src, parse_spec(spec), parse_spec("pinhole:hfov=90"), o);
  }
};

class EveryViewer : public Tiles, public ::testing::WithParamInterface<Viewer> {};

TEST_P(EveryViewer, EveryTileEqualsItsFaceRenderedDirectlyAtItsLevel) {
  TilesJob job;
  job.input = source("equirect", {1024, 512});
  job.output = path("out");
  job.viewer = GetParam();
  job.tile = 128;
  job.format = "png";
  job.yaw = 30;  // the front turned: faces turn with it (antialias: auto, the job's default)
  const TilesRun r = run_tiles(job);
  const Image src = read_image(job.input);
  ASSERT_GE(r.pyramid.levels.size(), 2u);
  EXPECT_EQ(r.written, r.pyramid.tile_count());
  EXPECT_EQ(r.empty, 0);
  int64_t checked = 0;
  for (size_t l = 0; l < r.pyramid.levels.size(); ++l) {
    const TileLevel& level = r.pyramid.levels[l];
    for (int f = 0; f < 6; ++f) {
      const Image want = face(src, "equirect", job, letter(r.pyramid, l, f), level.size, false);
      for (int64_t row = 0; row < level.tiles; ++row)
        for (int64_t col = 0; col < level.tiles; ++col) {
          const Image tile = read_image((fs::path(job.output) / r.pyramid.tile_path(l, f, row, col)).string());
          const int64_t x0 = col * r.pyramid.tile, y0 = row * r.pyramid.tile;
          ASSERT_EQ(tile.width(), std::min(r.pyramid.tile, level.size - x0));
          ASSERT_EQ(tile.height(), std::min(r.pyramid.tile, level.size - y0));
          double worst = 0;
          for (int64_t y = 0; y < tile.height(); ++y)
            for (int64_t x = 0; x < tile.width(); ++x)
              for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(get(tile, x, y, c) - get(want, x0 + x, y0 + y, c)));
          ASSERT_LE(worst, 1.0) << r.pyramid.tile_path(l, f, row, col);
          ++checked;
        }
    }
  }
  EXPECT_EQ(checked, r.pyramid.tile_count());
  // Exactly the tiles, the preview, config.json, index.html and the marker.
  const auto files = files_below(job.output);
  const size_t previews = job.viewer == Viewer::Pannellum ? 6 : 1;
  EXPECT_EQ(files.size(), static_cast<size_t>(r.pyramid.tile_count()) + previews + 3);
  EXPECT_TRUE(files.count("index.html") && files.count("config.json") && files.count(kFolderMarker));
}

// JPEG tiles hold the same pixels before encoding: each file is the JPEG encoding of the PNG
// run's tile (the encoder is deterministic), byte for byte.
TEST_F(Tiles, JpegTilesAreThePngTilesEncoded) {
  TilesJob job;
  job.input = source("equirect", {1024, 512});
  job.tile = 128;
  job.format = "png";
  job.output = path("png");
  const TilesRun r = run_tiles(job);
  job.format = "jpg";
  job.output = path("jpg");
  run_tiles(job);
  WriteOptions w;
  w.threads = 1;
  for (size_t l = 0; l < r.pyramid.levels.size(); ++l)
    for (int f = 0; f < 6; ++f) {
      const std::string name = r.pyramid.tile_path(l, f, 0, 0);
      const Image png = read_image(path("png") + "/" + name);
      const FileBytes want = encode_jpeg(png, "x.jpg", w, {});
      const std::string jpg_name = name.substr(0, name.size() - 3) + "jpg";
      EXPECT_EQ(slurp(path("jpg") + "/" + jpg_name), std::string(reinterpret_cast<const char*>(want.data()), want.size()))
          << jpg_name;
    }
}

INSTANTIATE_TEST_SUITE_P(Viewers, EveryViewer, ::testing::Values(Viewer::Pannellum, Viewer::Marzipano),
                         [](const auto& info) { return std::string(name_of(info.param)); });

TEST_F(Tiles, PartialPanoramasSkipEmptyTilesAndLimitTheView) {
  const std::string spec = "equirect:hfov=120,vfov=60";
  TilesJob job;
  job.input = source(spec, {600, 300});
  job.from = spec;
  job.output = path("out");
  job.tile = 64;
  job.format = "png";
  const TilesRun r = run_tiles(job);
  const Image src = read_image(job.input);
  EXPECT_GT(r.empty, 0);
  EXPECT_EQ(r.written + r.empty, r.pyramid.tile_count());
  for (size_t l = 0; l < r.pyramid.levels.size(); ++l) {
    const TileLevel& level = r.pyramid.levels[l];
    for (int f = 0; f < 6; ++f) {
      const Image want = face(src, spec, job, letter(r.pyramid, l, f), level.size, true);
      for (int64_t row = 0; row < level.tiles; ++row)
        for (int64_t col = 0; col < level.tiles; ++col) {
          bool covered = false;
          for (int64_t y = row * r.pyramid.tile; y < std::min(level.size, (row + 1) * r.pyramid.tile); ++y)
            for (int64_t x = col * r.pyramid.tile; x < std::min(level.size, (col + 1) * r.pyramid.tile); ++x)
              covered |= get(want, x, y, 3) > 0;
          const fs::path file = fs::path(job.output) / r.pyramid.tile_path(l, f, row, col);
          ASSERT_EQ(fs::exists(file), covered) << file;
          if (!covered) continue;
          // Flattened over black: colour times coverage.
          const Image tile = read_image(file.string());
          double worst = 0;
          for (int64_t y = 0; y < tile.height(); ++y)
            for (int64_t x = 0; x < tile.width(); ++x) {
              const int64_t fx = col * r.pyramid.tile + x, fy = row * r.pyramid.tile + y;
              for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(get(tile, x, y, c) - get(want, fx, fy, c) * get(want, fx, fy, 3) / 255));
            }
          EXPECT_LE(worst, 1.0) << file;
        }
    }
  }
  // The view's limits: the field's yaw and pitch range (within a degree).
  const std::string config = slurp(fs::path(job.output) / "config.json");
  auto value = [&](const std::string& key) {
    const size_t at = config.find("\"" + key + "\": ");
    EXPECT_NE(at, std::string::npos) << key << " in " << config;
    return at == std::string::npos ? NAN : std::stod(config.substr(at + key.size() + 4));
  };
  EXPECT_NEAR(value("minYaw"), -60, 1);
  EXPECT_NEAR(value("maxYaw"), 60, 1);
  EXPECT_NEAR(value("minPitch"), -30, 1);
  EXPECT_NEAR(value("maxPitch"), 30, 1);
  EXPECT_NE(config.find("\"avoidShowingBackground\": true"), std::string::npos);
}

TEST_F(Tiles, PartsInAnyOrderEqualTheWholeRun) {
  TilesJob job;
  job.input = source("equirect", {1024, 512});
  job.output = path("whole");
  job.viewer = Viewer::Marzipano;
  job.tile = 64;
  run_tiles(job);
  job.output = path("parts");
  job.band_pixels = 64 * 64 * 3;  // small bands: many parts, each its own region
  const JobDef& tiles = job_named("tiles");
  const Staged s = tiles.begin(job.args());
  ASSERT_GT(s.parts, 12);
  std::vector<int64_t> work(static_cast<size_t>(s.parts));
  std::iota(work.begin(), work.end(), 0);
  std::shuffle(work.begin(), work.end(), std::mt19937(3));
  PartCounts counts;
  for (size_t i = 0; i < work.size(); i += 5) {
    const std::vector<int64_t> some(
        work.begin() + static_cast<std::ptrdiff_t>(i),
        work.begin() + static_cast<std::ptrdiff_t>(std::min(work.size(), i + 5)));
    const PartCounts c = tiles.render(job.args(), s.folder, some);
    counts.written += c.written, counts.empty += c.empty;
  }
  const Report r = tiles.finish(job.args(), s.folder, counts);
  EXPECT_EQ(integer(r, "written"), tile_pyramid(job.args()).tile_count());
  EXPECT_THROW(tiles.render(job.args(), s.folder, {s.parts}), Error);  // no such part
  EXPECT_FALSE(fs::exists(s.folder.path));
  EXPECT_EQ(files_below(path("parts")), files_below(path("whole")));
}

TEST_F(Tiles, TheFolderLandsWholeOrNotAtAll) {
  TilesJob job;
  job.input = source("equirect", {512, 256});
  job.output = path("out");
  fs::create_directory(job.output);
  std::ofstream(fs::path(job.output) / "mine.txt") << "keep";
  // A folder panoproj did not make is replaced neither without overwrite nor with it.
  for (const bool overwrite : {false, true}) {
    job.overwrite = overwrite;
    try {
      run_tiles(job);
      ADD_FAILURE() << "an existing folder was replaced, overwrite " << overwrite;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Exists);
      EXPECT_NE(std::string(e.what()).find(overwrite ? "was not made by panoproj" : "--overwrite"), std::string::npos) << e.what();
    }
    EXPECT_EQ(slurp(fs::path(job.output) / "mine.txt"), "keep");
  }
  // One it made (its marker at the root): a source that fails while decoding leaves nothing and
  // the old folder intact.
  job.output = path("pyramid");
  job.overwrite = false;
  run_tiles(job);
  EXPECT_EQ(slurp(fs::path(job.output) / kFolderMarker), "{\"made_by\": \"panoproj\", \"job\": \"tiles\"}\n");
  std::ofstream(fs::path(job.output) / "mine.txt") << "keep";
  const size_t before = files_below(job.output).size();
  const std::string bytes = slurp(job.input);
  const std::string broken = path("broken.png");
  std::ofstream(broken, std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
  job.input = broken;
  job.overwrite = true;
  EXPECT_THROW(run_tiles(job), Error);
  EXPECT_EQ(files_below(job.output).size(), before);
  for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().filename().string().rfind(".panoproj-", 0), std::string::npos) << e.path();
  // With overwrite a good source replaces it whole.
  job.input = path("src.png");
  const TilesRun r = run_tiles(job);
  EXPECT_FALSE(fs::exists(fs::path(job.output) / "mine.txt"));
  EXPECT_EQ(static_cast<int64_t>(files_below(job.output).size()), r.pyramid.tile_count() + 6 + 3);
  for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().filename().string().rfind(".panoproj-", 0), std::string::npos) << e.path();
}

}  // namespace
}  // namespace panoproj
