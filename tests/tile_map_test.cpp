// The tile mapper against the exact per-pixel map, for every projection on both sides:
// position error within 1/256 source pixel (kMapTolerance is checked at 5 points per cell;
// this measures every pixel), and the same valid pixels except within that distance of a field
// edge.
#include "geometry/tile_map.hpp"

#include <gtest/gtest.h>

#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

struct Pair {
  const char* src;
  Size src_size;
  const char* dst;
  Size dst_size;
  double yaw, pitch, roll;
};
void PrintTo(const Pair& c, std::ostream* os) { *os << c.src << " to " << c.dst; }

class TileMapAccuracy : public ::testing::TestWithParam<Pair> {};

TEST_P(TileMapAccuracy, MatchesTheExactMap) {
  const Pair& c = GetParam();
  const Projection src = make_projection(parse_spec(c.src), c.src_size);
  const Projection dst = make_projection(parse_spec(c.dst), c.dst_size);
  const Eigen::Matrix3d r = rotation_from_ypr(c.yaw, c.pitch, c.roll);
  test::MapComparison cmp;
  int64_t cells = 0, interpolated = 0;
  TileMap tm;
  const int64_t tile = 64;
  for (int64_t ty = 0; ty < c.dst_size.height; ty += tile)
    for (int64_t tx = 0; tx < c.dst_size.width; tx += tile) {
      const PixelRect rect{tx, ty, std::min(tx + tile, c.dst_size.width),
                           std::min(ty + tile, c.dst_size.height)};
      map_tile(src, dst, r, rect, tm);
      cells += tm.exact_cells + tm.interpolated_cells;
      interpolated += tm.interpolated_cells;
      test::compare_with_exact(src, dst, r, rect, tm, 1.0 / 256, cmp);
    }
  const double max_err = cmp.worst;
  const int64_t valid = cmp.valid, mismatched = cmp.differ;
  std::printf("[tile_map] %-34s -> %-34s max error %.2e px, %5.1f%% cells interpolated, %lld of %lld "
              "pixels differ in validity\n",
              c.src, c.dst, max_err, 100.0 * interpolated / cells, static_cast<long long>(mismatched),
              static_cast<long long>(valid));
  EXPECT_LE(max_err, 1.0 / 256);
  EXPECT_LE(mismatched, valid / 10000 + 2);
}

const Pair kPairs[] = {
    {"equirect", {4096, 2048}, "fisheye:fov=180", {1024, 1024}, 0, 0, 0},
    {"equirect", {4096, 2048}, "fisheye:fov=360,model=equisolid", {1024, 1024}, 30, 20, 10},
    {"equirect", {4096, 2048}, "cubemap", {6 * 512, 512}, 0, 0, 0},
    {"cubemap", {6 * 512, 512}, "equirect", {2048, 1024}, 0, 0, 0},
    {"cubemap:layout=cross", {4 * 512, 3 * 512}, "pinhole:hfov=120", {800, 600}, 45, 35, 0},
    {"equirect", {4096, 2048}, "pinhole:hfov=90", {960, 540}, 180, 80, 5},
    {"equirect", {4096, 2048}, "equirect", {2048, 1024}, 10, 60, 30},
    {"equirect", {4096, 2048}, "cylindrical:vfov=120", {2048, 900}, 0, 0, 0},
    {"equirect", {4096, 2048}, "aitoff", {2048, 1024}, 0, 0, 0},
    {"equirect", {4096, 2048}, "eckert-greifendorff", {2048, 946}, 0, 0, 0},
    {"equirect", {4096, 2048}, "bonne:phi1=45", {1392, 1321}, 0, 0, 0},
    {"aitoff", {2048, 1024}, "equirect", {2048, 1024}, 0, 0, 0},
    {"bonne:phi1=0", {2048, 1024}, "pinhole:hfov=100", {800, 800}, 170, -30, 0},
    {"hammer", {2048, 1024}, "fisheye:fov=200", {800, 800}, 0, 0, 0},
    {"fisheye:fov=210", {512, 512}, "equirect", {1024, 512}, 0, -90, 0},
    {"fisheye:fov=180,clip=none", {1200, 800}, "pinhole:hfov=150", {1000, 700}, 10, 0, 0},
    {"pinhole:hfov=60", {1024, 768}, "equirect", {2048, 1024}, 20, 10, 0},
    {"cylindrical", {4096, 1400}, "fisheye:fov=180", {1024, 1024}, 0, 90, 0},
};

INSTANTIATE_TEST_SUITE_P(Pairs, TileMapAccuracy, ::testing::ValuesIn(kPairs), [](const auto& info) {
  return test::case_name(info.index, std::string(info.param.src) + " to " + info.param.dst);
});

}  // namespace
}  // namespace panoproj
