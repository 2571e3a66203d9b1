// Kept planned taps (Keep::MapsAndTaps, sampling/planned_taps.hpp): a run that replays the taps
// an earlier run planned gives the bytes a converter that keeps nothing gives, on every SIMD
// target, for every kernel, pixel type and alpha, with the footprint kernel; only sources of the
// planned layout replay; tiles with many misses are not kept; concurrent first runs share one
// plan.
#include "panoproj/convert.hpp"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <array>
#include <cstring>
#include <thread>

#include "geometry/tile_map.hpp"
#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

Projection make(const char* spec, Size size) { return make_projection(parse_spec(spec), size); }

// The scene as uint8 with nc channels, no alpha (1: its first channel; 4: a fourth, colour data).
Image frame(const Projection& p, uint32_t seed, int nc = 3) {
  const Image rgb = test::render(p, test::band_limited_scene(0.15, 512, seed), PixelType::U8);
  if (nc == 3) return rgb;
  Image out(rgb.size(), nc, PixelType::U8, -1);
  for (int64_t y = 0; y < out.height(); ++y)
    for (int64_t x = 0; x < out.width(); ++x)
      for (int c = 0; c < nc; ++c) out.pixel(x, y)[c] = rgb.pixel(x, y)[c % 3] ^ static_cast<unsigned char>(c == 3 ? 0x5a : 0);
  return out;
}

struct Pair {
  const char* from;
  Size from_size;
  const char* to;
  Size to_size;
  double yaw, pitch, roll;
};

// Fused pairs with seams, poles, face edges and pixels without a source among their tiles.
const Pair kPairs[] = {
    {"equirect", {512, 256}, "cubemap:layout=cross", {4 * 96, 3 * 96}, 10, 5, 0},
    {"equirect", {512, 256}, "pinhole:hfov=100", {300, 200}, 170, 75, 10},  // the seam and a pole
    {"equirect", {512, 256}, "fisheye:fov=200", {257, 257}, 40, -20, 0},    // a circle: pixels without a source
    {"cubemap:layout=cross", {4 * 96, 3 * 96}, "equirect", {400, 200}, 0, 0, 0},
    {"pinhole:hfov=80", {320, 240}, "equirect", {360, 180}, 20, 10, 0},  // a partial source
    {"equirect", {512, 256}, "pinhole:hfov=150", {256, 192}, 0, 0, 0},  // auto: the footprint kernel at the centre only
};

TEST(PlannedTaps, ReplayedRunsGiveTheBytesOfPlannedOnesOnEveryTarget) {
  std::vector<std::array<std::array<Image, 3>, 3>> frames;  // [pair][seed - 1][channels 1, 3, 4]
  for (const Pair& p : kPairs) {
    frames.emplace_back();
    for (uint32_t seed : {1u, 2u, 3u})
      for (int k = 0; k < 3; ++k) frames.back()[seed - 1][static_cast<size_t>(k)] = frame(make(p.from, p.from_size), seed, k == 0 ? 1 : k == 1 ? 3 : 4);
  }
  const auto targets = hwy::SupportedAndGeneratedTargets();
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    for (size_t pi = 0; pi < std::size(kPairs); ++pi)
      for (int nc : {1, 3, 4})
        for (bool aa : {false, true}) {
          const Pair& p = kPairs[pi];
          SCOPED_TRACE(std::string(p.from) + " -> " + p.to + ", " + std::to_string(nc) + " ch" + (aa ? ", auto" : ""));
          const Projection src = make(p.from, p.from_size), dst = make(p.to, p.to_size);
          const Eigen::Matrix3d r = rotation_from_ypr(p.yaw, p.pitch, p.roll);
          const Antialias a = aa ? parse_antialias("auto") : Antialias{};
          const Converter kept =
              test::converter(src, dst, r, Interp::Bilinear, Engine::Simd, 2, Keep::MapsAndTaps, a);
          const Converter lean =
              test::converter(src, dst, r, Interp::Bilinear, Engine::Simd, 2, Keep::Nothing, a);
          int64_t misses = 0;
          for (uint32_t seed : {1u, 2u, 3u}) {  // the first run plans, the others replay
            const Image& im = frames[pi][seed - 1][nc == 1 ? 0 : nc == 3 ? 1 : 2];
            EngineStats st;
            const Image got = kept.run(im, &st);
            EXPECT_TRUE(got == lean.run(im)) << "frame " << seed;
            EXPECT_GT(st.fused_tiles, 0);
            if (seed == 1) EXPECT_EQ(st.replayed_tiles, 0);
            else EXPECT_EQ(st.replayed_tiles, st.fused_tiles) << "every fused tile replays";
            if (seed == 1) misses = st.simd_misses;
            else EXPECT_EQ(st.simd_misses, misses) << "the kept misses, resolved again";
          }
        }
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(PlannedTaps, OnlyTheFirstSourcesLayoutReplays) {
  const Projection src = make("equirect", {512, 256}), dst = make("pinhole:hfov=60", {200, 150});
  const Eigen::Matrix3d r = rotation_from_ypr(30, 20, 0);
  const Converter kept =
      test::converter(src, dst, r, Interp::Bilinear, Engine::Simd, 2, Keep::MapsAndTaps);
  const Converter lean =
      test::converter(src, dst, r, Interp::Bilinear, Engine::Simd, 2, Keep::Nothing);
  EngineStats st;
  const Image whole = frame(src, 1);
  EXPECT_TRUE(kept.run(whole, &st) == lean.run(whole));
  // A window of the frame (as a file's region read gives): other offsets from its first pixel.
  const PixelRect g = kept.source_footprint();
  ASSERT_GT(g.x0, 0);
  Image window({g.x1 - g.x0, g.y1 - g.y0}, 3, PixelType::U8);
  const Image other = frame(src, 2);
  for (int64_t y = g.y0; y < g.y1; ++y)
    std::memcpy(window.row(y - g.y0), other.pixel(g.x0, y), window.row_bytes());
  window.set_window(g.x0, g.y0, size_of(src));
  EXPECT_TRUE(kept.run(window, &st) == lean.run(window));
  EXPECT_EQ(st.replayed_tiles, 0);
  const Image gray = frame(src, 3, 1), rgbx = frame(src, 3, 4);
  EXPECT_TRUE(kept.run(gray, &st) == lean.run(gray));
  EXPECT_EQ(st.replayed_tiles, 0);
  EXPECT_TRUE(kept.run(rgbx, &st) == lean.run(rgbx));
  EXPECT_EQ(st.replayed_tiles, 0);
  // The first layout still replays.
  EXPECT_TRUE(kept.run(other, &st) == lean.run(other));
  EXPECT_EQ(st.replayed_tiles, st.tiles);
}

TEST(PlannedTaps, EveryKernelTypeAndAlphaReplaysOnEveryTarget) {
  const Projection src = make("equirect", {256, 128}), dst = make("pinhole:hfov=90", {128, 128});
  const Eigen::Matrix3d r = rotation_from_ypr(10, 10, 0);
  const Image rgb = frame(src, 1);
  const Image rgba = test::render(src, test::band_limited_scene(0.15, 512, 1), PixelType::U8, true);
  const Image wide = test::render(src, test::band_limited_scene(0.15, 512, 1), PixelType::U16);
  struct Case {
    Interp k;
    const Image* im;
  };
  Image half(rgba.size(), 4, PixelType::F16, 3), single(rgba.size(), 2, PixelType::F32, 1);
  for (int64_t y = 0; y < rgba.height(); ++y)
    for (int64_t x = 0; x < rgba.width(); ++x) {
      for (int c = 0; c < 4; ++c) test::set(half, x, y, c, test::get(rgba, x, y, c) / 255.0);
      for (int c = 0; c < 2; ++c) test::set(single, x, y, c, test::get(rgba, x, y, 2 * c + 1) / 255.0);
    }
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    for (const Case& c : {Case{Interp::Bicubic, &rgb}, Case{Interp::Nearest, &rgb}, Case{Interp::Lanczos3, &rgb},
                          Case{Interp::BicubicDering, &rgb}, Case{Interp::Bilinear, &rgba}, Case{Interp::Bicubic, &rgba},
                          Case{Interp::Bilinear, &wide}, Case{Interp::Lanczos3, &half}, Case{Interp::Bicubic, &single}}) {
      SCOPED_TRACE(std::string(name_of(c.k)) + ", " + name_of(c.im->type()) + " x " + std::to_string(c.im->channels()));
      const Converter kept = test::converter(src, dst, r, c.k, Engine::Simd, 2, Keep::MapsAndTaps);
      const Image want = test::converter(src, dst, r, c.k, Engine::Simd, 2).run(*c.im);
      for (int run = 0; run < 2; ++run) {
        EngineStats st;
        EXPECT_TRUE(kept.run(*c.im, &st) == want);
        EXPECT_EQ(st.replayed_tiles, run == 0 ? 0 : st.fused_tiles);
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(PlannedTaps, TilesWithManyMissesAreNotKept) {
  // An 8x4 source seen whole: most taps cross the seam or a pole (the reference's tap rules).
  const Projection src = make("equirect", {8, 4}), dst = make("equirect", {128, 64});
  const Converter kept = test::converter(src, dst, Eigen::Matrix3d::Identity(), Interp::Bilinear,
                                         Engine::Simd, 1, Keep::MapsAndTaps);
  const Converter lean = test::converter(src, dst, Eigen::Matrix3d::Identity(), Interp::Bilinear,
                                         Engine::Simd, 1, Keep::Nothing);
  EngineStats st;
  for (uint32_t seed : {1u, 2u}) {
    const Image im = frame(src, seed);
    EXPECT_TRUE(kept.run(im, &st) == lean.run(im));
    EXPECT_GT(st.simd_misses * 8, st.tiles * kTile * kTile) << "the case should miss over 1/8 of its samples";
  }
  EXPECT_LT(st.replayed_tiles, st.fused_tiles);
}

TEST(PlannedTaps, ConcurrentFirstRunsShareOnePlan) {
  const Projection src = make("equirect", {512, 256}), dst = make("cubemap:layout=cross", {4 * 64, 3 * 64});
  const Eigen::Matrix3d r = rotation_from_ypr(5, 15, 0);
  const Converter kept =
      test::converter(src, dst, r, Interp::Bilinear, Engine::Simd, 2, Keep::MapsAndTaps);
  const Converter lean =
      test::converter(src, dst, r, Interp::Bilinear, Engine::Simd, 2, Keep::Nothing);
  std::vector<Image> in, out(4);
  for (uint32_t seed = 1; seed <= 4; ++seed) in.push_back(frame(src, seed));
  std::vector<std::thread> runs;
  for (size_t i = 0; i < in.size(); ++i) runs.emplace_back([&, i] { out[i] = kept.run(in[i]); });
  for (auto& t : runs) t.join();
  for (size_t i = 0; i < in.size(); ++i) EXPECT_TRUE(out[i] == lean.run(in[i])) << "frame " << i;
  EngineStats st;
  EXPECT_TRUE(kept.run(in[0], &st) == lean.run(in[0]));
  EXPECT_EQ(st.replayed_tiles, st.fused_tiles) << "every tile was planned once by one of the runs";
}

}  // namespace
}  // namespace panoproj
