// The SIMD geometry against the exact double map, on every Highway target here, for every pair it
// takes: positions within 1e-9 px where it runs in double, within SimdGeometry::kFloatTolerance
// per axis where float lanes are allowed (modulo the identities: seam, poles, shared cube edges);
// validity identical but for a few rim pixels; and it takes (90% of) the tiles that have pixels.
// The same with the grid (cubic interpolation between exact nodes, SimdGeometry::grid), on the
// widest and the narrowest target: within the same bound, validity the same, and near 1:1 scale
// it interpolates most cells.
#include "simd/geometry.hpp"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <limits>
#include <numeric>

#include "panoproj/rotation.hpp"
#include "projections/module.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

struct Pair {
  const char* src;
  Size ss;
  const char* dst;
  Size ds;
  double yaw, pitch, roll;
  bool mostly_grid = false;  // near 1:1 scale: the grid interpolates most cells
};

// One pair's sweep over the target's tiles, with or without the grid.
struct PairRun {
  test::MapComparison cmp;
  int64_t taken = 0, tiles = 0;         // tiles: those with a valid pixel
  int64_t interpolated = 0, cells = 0;  // the grid's cells in tiles with a pixel
  int64_t gridded = 0;                  // tiles the grid may take
  bool floats = false;
};

PairRun run_pair(const Projection& sp, const Projection& dp, const Eigen::Matrix3d& r, bool grid) {
  PairRun run;
  const Size ds = size_of(dp);
  TileMap tm;
  for (int64_t ty = 0; ty < ds.height; ty += kTile)
    for (int64_t tx = 0; tx < ds.width; tx += kTile) {
      const PixelRect rect{tx, ty, std::min(tx + kTile, ds.width), std::min(ty + kTile, ds.height)};
      bool any = false;
      for (int64_t j = 0; j < rect.height() && !any; j += 4)
        for (int64_t i = 0; i < rect.width() && !any; i += 4)
          any = contains(dp, tx + i + 0.5, ty + j + 0.5);
      run.tiles += any;
      SimdGeometry g;
      if (!simd_geometry_for(sp, dp, r, rect, g)) continue;
      ++run.taken;
      run.floats = g.use_float;
      simd_map_tile(g, rect, tm, grid);
      run.gridded += g.grid && any;
      if (grid && g.grid && any) {
        run.interpolated += tm.interpolated_cells;
        run.cells += tm.interpolated_cells + tm.exact_cells;
      }
      test::compare_with_exact(sp, dp, r, rect, tm, 1e-9, run.cmp);
    }
  return run;
}

// Positions within 1e-9 px in double lanes, kFloatTolerance per axis in float lanes (the
// distance within sqrt(2) of it); validity the same but for a few rim pixels.
void expect_close(const PairRun& run, const std::string& name) {
  EXPECT_LE(run.cmp.worst, run.floats ? std::sqrt(2.0) * SimdGeometry::kFloatTolerance : 1e-9) << name;
  EXPECT_LE(run.cmp.differ, run.cmp.valid / 5000 + 4) << name;
}

TEST(SimdGeometry, MatchesTheExactMapOnEveryTarget) {
  const Pair pairs[] = {
      {"equirect", {4096, 2048}, "cubemap", {6 * 512, 512}, 0, 0, 0},
      {"equirect", {4096, 2048}, "cubemap:layout=cross", {4 * 512, 3 * 512}, 20, 30, 10},
      {"equirect", {32768, 16384}, "pinhole:hfov=90", {700, 500}, 170, 80, 5},
      {"equirect", {40000, 20000}, "cubemap", {6 * 256, 256}, 0, 30, 0},
      {"equirect", {4096, 2048}, "fisheye:fov=180", {600, 600}, 0, 0, 0},
      // Grid pairs (a sphere to a convex target) near 1:1 scale, at the extremes: a pole inside,
      // the seam across the middle, an 8K source (a smaller float budget), a tilted cube face.
      {"equirect", {2048, 1024}, "fisheye:fov=180", {1024, 1024}, 0, 90, 0, true},
      {"equirect", {2048, 1024}, "fisheye:fov=200", {1152, 1152}, 180, 10, 0, true},
      {"equirect", {8192, 4096}, "fisheye:fov=180,model=equisolid", {1024, 1024}, 40, -30, 0},
      {"cubemap", {6 * 1024, 1024}, "pinhole:hfov=100", {1000, 700}, 45, 35, 10, true},
      {"equirect", {4096, 2048}, "fisheye:fov=360,model=equisolid", {600, 600}, 30, -20, 0},
      {"equirect", {4096, 2048}, "fisheye:fov=120,model=orthographic", {400, 400}, 0, 45, 0},
      {"equirect", {4096, 2048}, "fisheye:fov=300,model=stereographic", {400, 400}, 0, -45, 0},
      {"equirect:vfov=101.25,lat0=-39.375", {2048, 512}, "pinhole:hfov=100", {500, 400}, 0, -20, 0},
      {"equirect", {4096, 2048}, "equirect", {1024, 512}, 10, 60, 30},
      {"cubemap", {6 * 512, 512}, "equirect", {1024, 512}, 0, 0, 0},
      {"cubemap:layout=cross", {4 * 512, 3 * 512}, "pinhole:hfov=120", {600, 400}, 45, 35, 0},
      {"cubemap", {6 * 512, 512}, "fisheye:fov=200", {500, 500}, 0, 90, 0},
      // Float lanes near the poles of rotated views, and the largest sources that allow them.
      {"equirect", {8192, 4096}, "pinhole:hfov=100", {600, 500}, 30, 75, 20},
      {"equirect", {4096, 2048}, "equirect", {2048, 1024}, 0, 89.99, 0},
      {"cubemap", {6 * 2048, 2048}, "equirect", {1024, 512}, 10, 20, 30},
      {"equirect", {2048, 1024}, "fisheye:fov=180,model=orthographic", {400, 400}, 0, 0, 0},
      {"equirect", {4096, 2048}, "fisheye:fov=360", {500, 500}, 0, 30, 0},
      // Partial and cylindrical sources and targets, unclipped fisheyes (frame corners beyond
      // the circle, and beyond the orthographic law's domain).
      {"equirect:hfov=200,vfov=100,lon0=30", {1000, 500}, "pinhole:hfov=100", {400, 300}, 20, 10, 0},
      {"cylindrical:vfov=100", {2048, 1000}, "pinhole:hfov=90", {400, 300}, 170, 20, 0},
      {"cylindrical:hfov=180,vfov=150", {1024, 1200}, "equirect", {800, 400}, 0, 0, 0},
      {"equirect", {2048, 1024}, "cylindrical:vfov=120", {1000, 500}, 0, 30, 10},
      {"cubemap", {6 * 256, 256}, "cylindrical:hfov=300,vfov=160", {900, 700}, 0, 0, 0},
      {"equirect", {2048, 1024}, "fisheye:fov=200,clip=none", {600, 400}, 0, 20, 0},
      {"equirect", {2048, 1024}, "fisheye:fov=170,model=orthographic,clip=none", {500, 400}, 0, 0, 0},
      {"equirect", {20000, 10000}, "fisheye:fov=250,model=stereographic,clip=none", {300, 300}, 10, 80, 0},
      {"equirect", {2048, 1024}, "hammer", {800, 400}, 30, 20, 0},
      {"equirect", {2048, 1024}, "eckert-greifendorff:lon0=40", {800, 400}, 0, 0, 0},
      {"hammer", {2000, 1000}, "pinhole:hfov=120", {500, 400}, 175, -30, 0},
      {"hammer:lon0=-60", {1000, 500}, "equirect", {800, 400}, 0, 0, 0},
      {"pinhole:hfov=100", {1600, 1200}, "equirect", {1000, 500}, 10, 5, 0},
      {"pinhole:hfov=150", {3000, 2000}, "cubemap", {6 * 128, 128}, 0, 0, 0},
      {"fisheye:fov=210", {2048, 2048}, "equirect", {1000, 500}, 0, -90, 0},
      // (Rotated a little: unrotated, a run of output pixel centres falls exactly on the frame
      // edge, where float rounding decides validity either way.)
      {"fisheye:fov=180,model=equisolid,clip=none", {1500, 1000}, "equirect", {1000, 500}, 3, 2, 0},
      {"fisheye:fov=360,model=equisolid", {1024, 1024}, "cubemap", {6 * 128, 128}, 0, 30, 0},
      {"fisheye:fov=170,model=orthographic", {1024, 1024}, "pinhole:hfov=120", {400, 300}, 0, 0, 0},
      {"fisheye:fov=270,model=stereographic", {1024, 1024}, "equirect", {800, 400}, 0, 0, 0},
      // Turned about the vertical only: the separable form (column tables, one arctangent).
      {"equirect", {4096, 2048}, "pinhole:hfov=100", {600, 500}, 75, 0, 0},
      {"equirect", {2048, 1024}, "pinhole:hfov=150", {800, 400}, -120, 0, 0},
      {"equirect:hfov=200,vfov=100,lon0=30", {1000, 500}, "pinhole:hfov=100", {400, 300}, 20, 0, 0},
      {"cylindrical:vfov=100", {2048, 1000}, "cubemap", {6 * 128, 128}, 33, 0, 0},
      {"equirect", {8192, 4096}, "cubemap", {6 * 256, 256}, 45, 0, 0},
      {"equirect", {40000, 20000}, "pinhole:hfov=60", {300, 200}, 10, 0, 0},
      {"cubemap", {6 * 256, 256}, "equirect", {1000, 500}, 130, 0, 0},  // the turn in the longitudes
      {"fisheye:fov=200", {1024, 1024}, "cylindrical:hfov=270", {900, 500}, -95, 0, 0},
      // Aitoff and Bonne sources (every form: phi1 regular, small, zero, southern, Werner's),
      // Bonne targets; rotated over the poles and the antipode of the centre.
      {"aitoff", {2048, 1024}, "pinhole:hfov=120", {500, 400}, 175, -30, 0},
      {"aitoff:lon0=60", {1024, 512}, "equirect", {800, 400}, 0, 0, 0},
      {"aitoff", {4096, 2048}, "cubemap", {6 * 128, 128}, 10, 80, 0},
      {"bonne", {2048, 1500}, "fisheye:fov=200", {500, 500}, 30, 50, 0},
      {"bonne:phi1=5,lon0=-20", {1024, 700}, "equirect", {800, 400}, 0, 0, 0},
      {"bonne:phi1=0", {1024, 600}, "cubemap", {6 * 128, 128}, 0, -60, 0},
      {"bonne:phi1=-60", {1024, 900}, "equirect", {800, 400}, 170, 0, 10},
      {"bonne:phi1=90", {1024, 900}, "pinhole:hfov=140", {500, 400}, 0, 85, 0},
      {"equirect", {2048, 1024}, "bonne", {800, 600}, 30, 20, 0},
      {"cubemap", {6 * 256, 256}, "bonne:phi1=5", {800, 500}, 0, 0, 0},
      {"equirect", {2048, 1024}, "bonne:phi1=0", {800, 500}, 0, -89, 0},
      {"fisheye:fov=220", {1024, 1024}, "bonne:phi1=-30,lon0=45", {700, 600}, 0, 90, 0},
      {"bonne:phi1=90", {1024, 900}, "bonne:phi1=20", {700, 600}, 0, 0, 0},
  };
  const auto targets = hwy::SupportedAndGeneratedTargets();
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    for (const Pair& c : pairs) {
      const Projection sp = make_projection(parse_spec(c.src), c.ss), dp = make_projection(parse_spec(c.dst), c.ds);
      const Eigen::Matrix3d r = rotation_from_ypr(c.yaw, c.pitch, c.roll);
      int64_t gridded = 0;  // tiles the grid may take (the first pass counts them)
      for (bool grid : {false, true}) {
        if (grid && gridded == 0) continue;  // the same as without
        // The grid's code differs between targets by lane count only: the widest (one vector per
        // cell row) and the narrowest (several) cover it at less of the CI's time.
        if (grid && target != targets.front() && target != targets.back()) continue;
        const PairRun run = run_pair(sp, dp, r, grid);
        if (!grid) gridded = run.gridded;
        const std::string name = std::string(c.src) + " -> " + c.dst + (grid ? " (grid)" : "") + " " + hwy::TargetName(target);
        if (target == targets.front())
          std::printf("[simd_geometry] %-34s -> %-36s %s%s max error %.2e px, %lld of %lld tiles, %lld of %lld "
                      "pixels differ in validity\n", c.src, c.dst, run.floats ? "float " : "double", grid ? " grid" : "",
                      run.cmp.worst, static_cast<long long>(run.taken), static_cast<long long>(run.tiles),
                      static_cast<long long>(run.cmp.differ), static_cast<long long>(run.cmp.valid));
        EXPECT_GT(run.taken * 10, run.tiles * 9) << name;
        expect_close(run, name);
        // Most cells interpolated (the rest: rims, poles, seams, face edges).
        if (grid && c.mostly_grid) {
          EXPECT_GT(run.interpolated * 2, run.cells) << name << ": " << run.interpolated << " of " << run.cells << " cells";
        }
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The forms with vector lanes (lib/src/simd/), as a source and as a target.
// A fisheye but Thoby's (its law has no vector form).
bool vector_fisheye(const Projection& p) {
  const auto* f = std::get_if<Fisheye>(&p);
  return f && f->model() != FisheyeModel::Thoby;
}
// A cube but FFmpeg's EAC frame (uneven cells: tile maps).
bool vector_cube(const Projection& p) {
  const auto* c = std::get_if<Cubemap>(&p);
  return c && c->uniform();
}
bool has_vector_source(const Projection& p) {
  return std::holds_alternative<Pinhole>(p) || vector_fisheye(p) || std::holds_alternative<Equirect>(p) ||
         std::holds_alternative<Cylindrical>(p) || vector_cube(p) || std::holds_alternative<Aitoff>(p) ||
         std::holds_alternative<Hammer>(p) || std::holds_alternative<Bonne>(p);
}
bool has_vector_target(const Projection& p) {
  return std::holds_alternative<Pinhole>(p) || vector_fisheye(p) ||
         std::holds_alternative<DualFisheye>(p) || std::holds_alternative<Equirect>(p) ||
         std::holds_alternative<Cylindrical>(p) || vector_cube(p) || std::holds_alternative<Hammer>(p) ||
         std::holds_alternative<Bonne>(p);
}

// A table row's pair: taken where the form has vector lanes (most tiles; every tile with pixels
// when the frame has few), and then close to the exact map; else never taken. report: print it.
void check_row_run(const PairRun& run, bool vector_form, const std::string& name, bool report) {
  if (!vector_form) {
    EXPECT_EQ(run.taken, 0) << name << ": a form with vector lanes? (has_vector_source/target)";
    return;
  }
  if (report) {
    std::printf("[simd_geometry] %-80s %s max error %.2e px, %lld of %lld tiles, %lld of %lld pixels differ\n",
                name.c_str(), run.floats ? "float " : "double", run.cmp.worst, static_cast<long long>(run.taken),
                static_cast<long long>(run.tiles), static_cast<long long>(run.cmp.differ),
                static_cast<long long>(run.cmp.valid));
  }
  EXPECT_GT(run.taken * 10, run.tiles * 9) << name;
  expect_close(run, name);
}

// A frame of p's aspect with at most 256 px on its longer side (or its smallest whole ratio);
// cube faces of one tile (a tile across two faces has no vector form).
Size small_frame(const Projection& p) {
  const Size s = size_of(p);
  if (const auto* c = std::get_if<Cubemap>(&p)) return {s.width / c->face_size() * kTile, s.height / c->face_size() * kTile};
  const int64_t g = std::gcd(s.width, s.height), w = s.width / g, h = s.height / g;
  const int64_t k = std::max<int64_t>(1, 256 / std::max(w, h));
  return {w * k, h * k};
}

// Every row of every projection's case table (projections/module.hpp): at each of its sizes as
// the source of a turned 256 x 128 equirect, and on a small frame of its largest size's aspect
// as the target of a turned 2048 x 1024 equirect. Where the form has vector lanes they are
// taken and agree with the exact map as the pairs above; elsewhere no tile is taken.
TEST(SimdGeometry, EveryCaseTableRowMatchesTheExactMapOnEveryTarget) {
  const Eigen::Matrix3d r = rotation_from_ypr(20, 30, 10);
  const Projection equirect = make_projection(parse_spec("equirect"), {256, 128});
  const Projection sphere = make_projection(parse_spec("equirect"), {2048, 1024});
  const auto targets = hwy::SupportedAndGeneratedTargets();
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    const bool report = target == targets.front();
    for (const ProjectionCase& row : projection_cases()) {
      Size largest = row.sizes.front();
      for (Size s : row.sizes) {
        if (s.width * s.height > largest.width * largest.height) largest = s;
        const Projection sp = make_projection(parse_spec(row.spec), s);
        const PairRun run = run_pair(sp, equirect, r, false);
        const std::string name = row.spec + " " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                                 " -> equirect " + hwy::TargetName(target);
        check_row_run(run, has_vector_source(sp), name, report);
      }
      const Projection big = make_projection(parse_spec(row.spec), largest);
      // (FFmpeg's EAC frame does not rescale to whole cells: made at the small frame instead.)
      const auto* cube = std::get_if<Cubemap>(&big);
      const Projection dp = cube && !cube->uniform() ? make_projection(parse_spec(row.spec), small_frame(big))
                                                     : rescaled(big, small_frame(big));
      const PairRun run = run_pair(sphere, dp, r, false);
      const Size ds = size_of(dp);
      check_row_run(run, has_vector_target(dp),
                    "equirect -> " + row.spec + " " + std::to_string(ds.width) + "x" + std::to_string(ds.height) + " " +
                        hwy::TargetName(target),
                  report);
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(SimdGeometry, SeparableFormOnlyForTurnsAboutTheVertical) {
  const Projection e = make_projection(parse_spec("equirect"), {2048, 1024});
  const Projection pin = make_projection(parse_spec("pinhole"), {256, 256});
  const Projection cube = make_projection(parse_spec("cubemap"), {6 * 64, 64});
  const Projection fish = make_projection(parse_spec("fisheye"), {256, 256});
  const PixelRect first{0, 0, 64, 64}, up{4 * 64, 0, 5 * 64, 64};  // the front and the up face
  auto separable = [&](const Projection& dst, const PixelRect& rect, double yaw, double pitch,
                       double roll) {
    SimdGeometry g;
    EXPECT_TRUE(simd_geometry_for(e, dst, rotation_from_ypr(yaw, pitch, roll), rect, g));
    return g.separable;
  };
  EXPECT_TRUE(separable(pin, first, 0, 0, 0));
  EXPECT_TRUE(separable(pin, first, 123, 0, 0));
  EXPECT_FALSE(separable(pin, first, 0, 10, 0));
  EXPECT_FALSE(separable(pin, first, 0, 0, 5));
  EXPECT_TRUE(separable(cube, first, 30, 0, 0));
  EXPECT_FALSE(separable(cube, up, 30, 0, 0));
  EXPECT_FALSE(separable(cube, first, 30, 1, 0));
  EXPECT_FALSE(separable(fish, first, 0, 0, 0));
}

// "Unbounded" limits (an unclipped stereographic fisheye's law, an unclipped source's psi_max)
// are 1e300 in double lanes and infinity in float lanes, never a converted overflow.
TEST(SimdGeometry, UnboundedLimitsStayUnboundedInFloatLanes) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(simd::lane<float>(1e300), inf);
  EXPECT_EQ(simd::lane<float>(-1e300), -inf);
  EXPECT_EQ(simd::lane<float>(0.1), 0.1f);
  EXPECT_EQ(simd::lane<double>(1e300), 1e300);
  const Projection e = make_projection(parse_spec("equirect"), {512, 256});
  const Projection stereo = make_projection(parse_spec("fisheye:fov=300,model=stereographic,clip=none"), {256, 256});
  SimdGeometry g;
  ASSERT_TRUE(simd_geometry_for(e, stereo, Eigen::Matrix3d::Identity(), {0, 0, 64, 64}, g));
  EXPECT_EQ(g.lf.target.fisheye.law_max, inf);
  EXPECT_EQ(g.ld.target.fisheye.law_max, 1e300);
  ASSERT_TRUE(simd_geometry_for(stereo, e, Eigen::Matrix3d::Identity(), {0, 0, 64, 64}, g));
  EXPECT_EQ(g.lf.source.fisheye.psi_max, inf);
}

}  // namespace
}  // namespace panoproj
