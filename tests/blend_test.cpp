// The blended panorama's parts (jobs/stitch/): the pyramid's REDUCE and EXPAND against their
// kernels on linear ramps (which the binomial kernel keeps), a Laplacian pyramid collapsing to its
// image, and the margins' grid against their exact values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "jobs/stitch/blend_margins.hpp"
#include "jobs/stitch/pano_spec.hpp"
#include "jobs/stitch/pto_project.hpp"
#include "jobs/stitch/pyramid.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"

namespace panoproj {
namespace {

Plane ramp(int64_t w, int64_t h, double ax, double ay) {
  Plane p(w, h, 1);
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x) p.row(y)[x] = static_cast<float>(ax * x + ay * y);
  return p;
}

TEST(Pyramid, ReduceKeepsARampAtEverySecondSample) {
  const Plane coarse = reduce(ramp(37, 22, 0.5, -0.25), 2);
  ASSERT_EQ(coarse.width, 19);
  ASSERT_EQ(coarse.height, 11);
  // Away from the edges (2 samples), sample j is the ramp at 2j.
  for (int64_t y = 1; y < coarse.height - 1; ++y)
    for (int64_t x = 1; x < coarse.width - 1; ++x)
      EXPECT_NEAR(coarse.row(y)[x], 0.5 * (2 * x) - 0.25 * (2 * y), 1e-5) << x << "," << y;
}

TEST(Pyramid, ExpandPutsARampBackAtEverySample) {
  // Coarse sample j at fine position 2j.
  Plane coarse(20, 12, 1);
  for (int64_t y = 0; y < 12; ++y)
    for (int64_t x = 0; x < 20; ++x)
      coarse.row(y)[x] = static_cast<float>(0.3 * 2 * x + 0.7 * 2 * y);
  Plane fine(39, 23, 1), scratch;
  expand_add(coarse, fine, scratch, 2);
  for (int64_t y = 1; y < fine.height - 2; ++y)
    for (int64_t x = 1; x < fine.width - 2; ++x)
      EXPECT_NEAR(fine.row(y)[x], 0.3 * x + 0.7 * y, 1e-4) << x << "," << y;
}

TEST(Pyramid, ALaplacianPyramidCollapsesToItsImage) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  Plane g0(53, 31, 3);
  for (float& v : g0.v) v = u(rng);
  std::vector<Plane> g{g0};
  for (int l = 0; l < 4; ++l) g.push_back(reduce(g.back(), 2));
  std::vector<Plane> lap = g;
  Plane scratch, up;
  for (size_t l = 0; l + 1 < g.size(); ++l) {
    up.reshape(g[l].width, g[l].height, 3);
    expand_into(g[l + 1], up, scratch, 2);
    for (size_t i = 0; i < up.v.size(); ++i) lap[l].v[i] -= up.v[i];
  }
  Plane out = lap.back();
  for (size_t l = g.size() - 1; l-- > 0;) {
    Plane level = lap[l];
    expand_add(out, level, scratch, 2);
    out = std::move(level);
  }
  for (size_t i = 0; i < g0.v.size(); ++i) EXPECT_NEAR(out.v[i], g0.v[i], 2e-6);
}

TEST(BlendMargins, TheGridIsTheExactMarginWithinItsBound) {
  const PtoProject p = parse_pto(
      "p f2 w720 h360 v360\ni w400 h300 f0 v80 r5 p10 y20 S20,380,10,290 n\"a.png\"\n"
      "i w300 h300 f2 v180 r0 p-30 y150 S10,290,10,290 n\"b.png\"\n",
      "t.pto");
  const Projection pano = make_projection(parse_spec("equirect"), {720, 360});
  StitchPlan plan;
  plan.project = p;
  for (int index = 0; index < 2; ++index) {
    StitchLayer layer;
    layer.index = index;
    layer.lens = parse_spec(image_spec(p, p.images[static_cast<size_t>(index)]));
    layer.rotation = image_rotation(p.images[static_cast<size_t>(index)]);
    const LayerMargin m(plan, layer);
    const PixelRect rect{3, 5, 717, 355};
    std::vector<float> grid(static_cast<size_t>(rect.width() * rect.height()));
    m.over(pano, rect, grid.data(), 2);
    double worst = 0, inside = 0;
    for (int64_t y = rect.y0; y < rect.y1; ++y)
      for (int64_t x = rect.x0; x < rect.x1; ++x) {
        Ray d;
        ASSERT_TRUE(to_ray(pano, x + 0.5, y + 0.5, d));
        const double exact = m.at(d);
        const float g = grid[static_cast<size_t>((y - rect.y0) * rect.width() + x - rect.x0)];
        if (exact > 0) ++inside;
        // Only margins inside count (outside, the weights are 0 whatever the value). Bilinear over
        // 8 px cells of a margin that bends where two edges are equally near (the min of two
        // distances): within half a cell's angle (4 px at 0.5 deg a pixel here).
        worst = std::max(worst, std::fabs(std::max(g, 0.0f) - std::max(exact, 0.0)));
      }
    EXPECT_GT(inside, 1000);
    EXPECT_LT(worst, 4 * 0.5 * kPi / 180) << index;
    std::printf("image %d: grid within %.2g rad of the exact margin\n", index, worst);
    // A rectangle's values are the canvas grid's, whatever the rectangle.
    std::vector<float> part(100 * 50);
    m.over(pano, {101, 77, 201, 127}, part.data(), 1);
    for (int64_t y = 0; y < 50; ++y)
      for (int64_t x = 0; x < 100; ++x)
        ASSERT_EQ(part[static_cast<size_t>(y * 100 + x)],
                  grid[static_cast<size_t>((77 + y - rect.y0) * rect.width() + 101 + x - rect.x0)]);
  }
}

}  // namespace
}  // namespace panoproj
