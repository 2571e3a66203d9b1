// The footprint kernel (footprint_kernel.hpp), auto antialiasing's filter: its weights against
// the exact area overlaps, its widths against the exact per-pixel footprints, the sub-pixel
// count's equirect rule, and the SIMD kernels against the reference on every Highway target.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "sampling/footprint_kernel.hpp"
#include "sampling/map_steps.hpp"
#include "panoproj/options.hpp"
#include "panoproj/conventions.hpp"
#include "panoproj/convert.hpp"
#include "sampling/interpolator.hpp"
#include "panoproj/rotation.hpp"
#include "panoproj/diagnostics/scene.hpp"
#include "panoproj/spec.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

using test::get;

Projection make(const char* spec, Size size) { return make_projection(parse_spec(spec), size); }

const Antialias kAuto{Antialias::Mode::Auto, 1};

TEST(FootprintKernel, WeightsAreTheBoxsOverlapWithEachPixel) {
  // Tap i covers [c_i - 0.5, c_i + 0.5] (c_i its centre); its weight is the share of the box
  // [s - e / 2, s + e / 2] it covers, here integrated numerically.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(10.0, 11.0), width(1.0, kFootprintReach);
  double worst = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double s = pos(rng), e = trial < 5 ? 1.0 + trial : width(rng);
    double w[kFootprintTaps];
    footprint_weights(s, e, w);
    const int64_t first = first_tap(kFootprintGrid, s);
    double sum = 0.0;
    for (int i = 0; i < kFootprintTaps; ++i) {
      const double c = static_cast<double>(first + i) + 0.5;
      constexpr int kSteps = 20000;
      double covered = 0.0;
      for (int q = 0; q < kSteps; ++q) {
        const double x = s - e / 2 + (q + 0.5) * e / kSteps;
        covered += std::fabs(x - c) < 0.5 ? 1.0 / kSteps : 0.0;
      }
      worst = std::max(worst, std::fabs(w[i] - covered));
      sum += w[i];
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
  std::printf("[footprint] weights vs numeric overlap: worst %.2e\n", worst);
  EXPECT_LT(worst, 2e-4);  // the integration's own step
}

TEST(FootprintKernel, UnitWidthIsBilinear) {
  for (double s = 7.0; s < 8.0; s += 0.0625) {
    double w[kFootprintTaps], b[2];
    footprint_weights(s, 1.0, w);
    tap_weights(Interp::Bilinear, s, b);
    const int64_t off = first_tap(Interp::Bilinear, s) - first_tap(kFootprintGrid, s);
    for (int i = 0; i < kFootprintTaps; ++i)
      EXPECT_NEAR(w[i], i == off ? b[0] : i == off + 1 ? b[1] : 0.0, 1e-12) << s << " tap " << i;
  }
}

TEST(FootprintKernel, FieldFollowsTheExactFootprints) {
  // The widths blended from 3 x 3 points per tile against each pixel's own (its exact steps, the
  // map's within 1/1024 px), where neither is clamped; the footprint changes slowly, so the
  // blend stays close. Worst near a fisheye's rim, where points outside the circle take the
  // others' mean. Tiles whose points lie on different cube faces are left out: the faces' axes
  // differ, and the blend mixes them (docs/accuracy.md: cube -> equirect 4x smaller, auto 30.8 dB
  // against 31.2 for 4x4 sub-pixels).
  struct Case {
    const char* from;
    Size from_size;
    const char* to;
    Size to_size;
    Eigen::Matrix3d r;
    double bound;  // relative
  };
  const Case cases[] = {
      {"equirect", {4096, 2048}, "fisheye:fov=180", {512, 512}, Eigen::Matrix3d::Identity(), 0.15},
      {"equirect", {4096, 2048}, "pinhole:hfov=100", {600, 400}, rotation_from_ypr(20, 30, 10), 0.02},
      {"cubemap", {6 * 512, 512}, "equirect", {512, 256}, rotation_from_ypr(10, 5, 0), 0.25},
  };
  for (const Case& c : cases) {
    const Projection s = make(c.from, c.from_size), d = make(c.to, c.to_size);
    const double wrap = std::holds_alternative<Equirect>(s) ? static_cast<double>(c.from_size.width) : 0.0;
    double worst = 0.0;
    int64_t compared = 0;
    for (int64_t y0 = 0; y0 < c.to_size.height; y0 += kTile)
      for (int64_t x0 = 0; x0 < c.to_size.width; x0 += kTile) {
        const PixelRect rect{x0, y0, std::min(x0 + kTile, c.to_size.width),
                             std::min(y0 + kTile, c.to_size.height)};
        FootprintField field;
        if (footprint_field(s, d, c.r, rect, wrap, field).side <= 0.0) continue;
        if (const auto* cube = std::get_if<Cubemap>(&s)) {
          std::set<int> faces;
          for (int q = 0; q < 9; ++q) {
            double x, y;
            if (source_pixel(s, d, c.r,
                             static_cast<double>(x0) + 0.5 +
                                 0.5 * (q % 3) * static_cast<double>(rect.width() - 1),
                             static_cast<double>(y0) + 0.5 +
                                 0.5 * (q / 3) * static_cast<double>(rect.height() - 1),
                             x, y))
              faces.insert(cube->face_at(x, y));
          }
          if (faces.size() > 1) continue;
        }
        TileMap tm;
        map_tile(s, d, c.r, rect, tm);
        for (int64_t j = 0; j < rect.height(); ++j)
          for (int64_t i = 0; i < rect.width(); ++i) {
            float ux, uy, vx, vy, ex, ey;
            if (!pixel_steps(tm, i, j, static_cast<float>(wrap), ux, uy, vx, vy)) continue;
            const double want_x = std::sqrt(ux * ux + vx * vx), want_y = std::sqrt(uy * uy + vy * vy);
            // Unclamped pixels away from face edges (where one side's steps jump).
            if (want_x < 1.05 || want_x > kFootprintReach - 0.05 || want_y < 1.05 || want_y > kFootprintReach - 0.05) continue;
            if (const auto* cube = std::get_if<Cubemap>(&s)) {
              const int64_t k = j * rect.width() + i, face = cube->face_at(tm.xs[k], tm.ys[k]);
              bool edge = false;
              for (const int64_t q : {k - 1, k + 1, k - rect.width(), k + rect.width()})
                edge |= q < 0 || q >= rect.width() * rect.height() || !tm.ok[q] ||
                        cube->face_at(tm.xs[q], tm.ys[q]) != face;
              if (edge) continue;
            }
            field.at(i, j, ex, ey);
            worst = std::max({worst, std::fabs(ex / want_x - 1.0), std::fabs(ey / want_y - 1.0)});
            ++compared;
          }
      }
    std::printf("[footprint] %s -> %s: widths within %.2f%% of each pixel's (%lld pixels)\n", c.from, c.to, 100 * worst,
                static_cast<long long>(compared));
    EXPECT_GT(compared, 1000) << c.to;
    EXPECT_LT(worst, c.bound) << c.from << " -> " << c.to;
  }
}

TEST(FootprintKernel, SubpixelFieldIsTheTilesScaled) {
  // The middle sub-pixel of each output pixel (n odd) sits at the pixel's centre: its width is
  // the pixel's divided by n, while neither is clamped.
  const Projection s = make("equirect", {4096, 2048}), d = make("fisheye:fov=180", {512, 512});
  const PixelRect tile{128, 128, 192, 192};  // footprints of about 4 source pixels
  FootprintField field;
  ASSERT_GT(footprint_field(s, d, Eigen::Matrix3d::Identity(), tile, 4096, field).side, 3.0);
  constexpr int n = 3;
  const PixelRect part{tile.x0 * n + 64, tile.y0 * n + 128, tile.x0 * n + 128,
                       tile.y0 * n + 192};  // one kTile part of the 3-times rect
  const FootprintField sub = field.for_rect(tile, part, n);
  int compared = 0;
  // Output pixel (tile.x0 + x, tile.y0 + y)'s middle sub-pixel: n (tile.x0 + x) + n / 2.
  for (int64_t j = (n / 2 - part.y0 % n + n) % n; j < part.height(); j += n)
    for (int64_t i = (n / 2 - part.x0 % n + n) % n; i < part.width(); i += n) {
      const int64_t x = (part.x0 + i) / n - tile.x0, y = (part.y0 + j) / n - tile.y0;
      float ex, ey, sx, sy;
      field.at(x, y, ex, ey);
      sub.at(i, j, sx, sy);
      ASSERT_TRUE(ex < kFootprintReach && ey < kFootprintReach && ex > n && ey > n);  // neither clamped
      EXPECT_NEAR(sx, ex / n, 1e-4f * ex) << x << "," << y;
      EXPECT_NEAR(sy, ey / n, 1e-4f * ey) << x << "," << y;
      ++compared;
    }
  EXPECT_GT(compared, 400);
}

TEST(FootprintKernel, EquirectRowsNearThePolesDoNotSplit) {
  // Equirect 4096x2048 -> equirect 1024x512: every footprint is 4x4 source pixels (the side);
  // the split side counts x steps at cos(latitude), so it is the side at the equator and less
  // toward the poles.
  const Projection s = make("equirect", {4096, 2048}), d = make("equirect", {1024, 512});
  FootprintField field;
  const FootprintSides equator =
      footprint_field(s, d, Eigen::Matrix3d::Identity(), {512, 224, 576, 288}, 4096, field);
  const FootprintSides polar =
      footprint_field(s, d, Eigen::Matrix3d::Identity(), {512, 0, 576, 64}, 4096, field);
  EXPECT_NEAR(equator.side, 4.0, 1e-3);
  EXPECT_NEAR(polar.side, 4.0, 1e-3);
  // The points' rows lie within 11 degrees of the equator (the split within 1% of the side),
  // and at 67.7, 78.75 and 89.6 degrees of latitude: the median, the middle row's.
  EXPECT_NEAR(equator.split, 4.0, 0.04);
  EXPECT_NEAR(polar.split, 4.0 * std::sqrt(std::cos(78.75 * kPi / 180)), 0.03);
}

TEST(FootprintKernel, SimdMatchesTheReferenceOnEveryTarget) {
  // Auto on shrinking conversions (tiles with one footprint kernel pass and with 2x2 sub-pixels;
  // fused SIMD geometry and tile maps), every pixel type, 1, 3 and 4 channels (alpha
  // premultiplied), on every Highway target: within 1 LSB of the reference for integers, 1e-5 of
  // the range for float.
  struct Case {
    const char* to;
    Size size;
  };
  // Fused (footprints of 4.3 and 10.7 source pixels: 3x3 sub-pixels); a map (5.7: 2x2).
  const Case cases[] = {{"fisheye:fov=180", {60, 60}}, {"fisheye:fov=180", {24, 24}}, {"aitoff", {90, 45}}};
  const Projection s = make("equirect", {512, 256});
  const Eigen::Matrix3d r = rotation_from_ypr(15, 40, 5);  // a pole in view
  for (PixelType t : {PixelType::U8, PixelType::U16, PixelType::F16, PixelType::F32})
    for (int nc : {1, 3, 4}) {
      Image im = render_scene(Scene::Chart, s, t, 1, 2);
      if (nc != 3) {
        Image other(im.size(), nc, t, nc == 4 ? 3 : -1);
        for (int64_t y = 0; y < im.height(); ++y)
          for (int64_t x = 0; x < im.width(); ++x)
            for (int c = 0; c < nc; ++c)
              test::set(other, x, y, c, c == 3 ? 0.25 + 0.75 * ((x / 7 + y / 5) % 2) : get(im, x, y, c % 3) / unit_of(t));
        im = other;
      }
      for (const Case& c : cases) {
        const Projection d = make(c.to, c.size);
        const Image want =
            test::converter(s, d, r, Interp::Bilinear, Engine::Scalar, 2, Keep::Nothing, kAuto)
                .run(im);
        const double bound = t == PixelType::U8 || t == PixelType::U16 ? 1.0 : t == PixelType::F16 ? 2e-3 : 1e-5;
        for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
          hwy::SetSupportedTargetsForTest(target);
          const Image got =
              test::converter(s, d, r, Interp::Bilinear, Engine::Simd, 2, Keep::Nothing, kAuto)
                  .run(im);
          double worst = 0;
          for (int64_t y = 0; y < c.size.height; ++y)
            for (int64_t x = 0; x < c.size.width; ++x)
              for (int ch = 0; ch < nc; ++ch) worst = std::max(worst, std::fabs(get(got, x, y, ch) - get(want, x, y, ch)));
          EXPECT_LE(worst, bound) << c.to << " " << name_of(t) << " " << nc << " channels " << hwy::TargetName(target);
        }
        hwy::SetSupportedTargetsForTest(0);
      }
    }
}

}  // namespace
}  // namespace panoproj
