// GoPro MAX (gopro_max.hpp):
//  - every pixel's ray back to that pixel in its own lens (1e-9 px); outside the band through
//    both lenses too; a band ray's two copies D px apart on one row (the repeat seen on the
//    frames);
//  - the margins: both lenses see a ray exactly where both margins are >= 0;
//  - an analytic scene rendered into the layout from its own inverse and converted to an equirect:
//    PSNR beside a plain EAC cube's of the same faces; the blend against the hard cut;
//  - the simd engine against the scalar one; a frame scaled by 1/2 (JPEG decode scale, 4:2:0
//  chroma)
//    against the parametric form at half size;
//  - bad specs and frames: one-line errors (the presets listed where none matches).
#include <gtest/gtest.h>

#include <cstdio>

#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

GoProMax max_of(const std::string& spec, Size size) {
  return std::get<GoProMax>(make_projection(parse_spec(spec), size));
}

struct Mode {
  const char* spec;
  Size size;
  int64_t band;
};
constexpr Mode kModes[] = {{"gopro-max", {4096, 2688}, 64},
                           {"gopro-max", {2272, 1472}, 32},
                           {"gopro-max", {4032, 2688}, 0},
                           {"gopro-max:preset=max2-10bit", {5952, 3840}, 96}};

TEST(GoProMax, EveryPixelComesBackInItsOwnLensAndBandRaysRepeatBandPixelsApart) {
  for (const Mode& m : kModes) {
    const GoProMax g = max_of(m.spec, m.size);
    double worst = 0, worst_pair = 0;
    int64_t rays = 0, in_band = 0;
    for (int64_t y = 0; y < m.size.height; y += 5)
      for (int64_t x = 0; x < m.size.width; x += 3) {
        const double px = static_cast<double>(x) + 0.5, py = static_cast<double>(y) + 0.5;
        Ray r;
        ASSERT_TRUE(g.to_ray(px, py, r)) << m.spec << " at " << x << "," << y;
        ++rays;
        const int k = g.lens_at(px, py);
        double bx, by;
        ASSERT_TRUE(g.lens(k).to_pixel(r, bx, by)) << m.spec << " at " << x << "," << y;
        worst = std::max(worst, std::hypot(bx - px, by - py));
        const bool both = g.margin(1 - k, r) >= 0;
        ASSERT_TRUE(g.to_pixel(r, bx, by));
        if (!both) {
          worst = std::max(worst, std::hypot(bx - px, by - py));
          continue;
        }
        // The band: the other lens's copy on the same row, D px along it (within the frame's
        // outer face).
        ++in_band;
        double ox, oy;
        ASSERT_TRUE(g.lens(1 - k).to_pixel(r, ox, oy)) << m.spec << " at " << x << "," << y;
        worst_pair =
            std::max(worst_pair, std::fabs(std::fabs(ox - px) - static_cast<double>(m.band)) +
                                     std::fabs(oy - py));
      }
    std::printf(
        "[gopro-max] %s at %lldx%lld: %lld rays (%lld in the band), own lens <= %.2e px, band "
        "copies D apart "
        "within %.2e px\n",
        m.spec, static_cast<long long>(m.size.width), static_cast<long long>(m.size.height),
        static_cast<long long>(rays), static_cast<long long>(in_band), worst, worst_pair);
    EXPECT_LT(worst, 1e-9);
    EXPECT_LT(worst_pair, 1e-9);
    if (m.band > 0) EXPECT_GT(in_band, 0);
  }
}

TEST(GoProMax, BothLensesSeeARayExactlyWhereBothMarginsAreNonNegative) {
  const GoProMax g = max_of("gopro-max", {4096, 2688});
  std::mt19937 rng(5);
  std::normal_distribution<double> n01;
  int both = 0;
  for (int i = 0; i < 200000; ++i) {
    Ray d(n01(rng), n01(rng), 0.05 * n01(rng));  // (near the seam)
    d.normalize();
    double x, y;
    const double m0 = g.margin(0, d), m1 = g.margin(1, d);
    if (std::fabs(m0) < 1e-9 || std::fabs(m1) < 1e-9) continue;  // (on a band's edge)
    EXPECT_EQ(g.lens(0).to_pixel(d, x, y), m0 >= 0) << d.transpose();
    EXPECT_EQ(g.lens(1).to_pixel(d, x, y), m1 >= 0) << d.transpose();
    both += m0 >= 0 && m1 >= 0;
  }
  EXPECT_GT(both, 10000);
}

// An analytic scene in the layout and in a plain EAC cube of the same faces, both to an equirect:
// the 3K's shape (outer faces S - D = C across) and the 5.6K's (squeezed: S - D < C), at 1/2.
TEST(GoProMax, AnAnalyticSceneConvertsBackBesideThePlainCube) {
  const Size eq{1472, 736};
  const Projection target = make_projection(parse_spec("equirect"), eq);
  const test::Scene scene = test::band_limited_scene(0.12, eq.width);
  const Image truth = test::render(target, scene, PixelType::F32);
  auto through = [&](const std::string& spec, Size frame, Engine engine = Engine::Simd) {
    const Projection p = make_projection(parse_spec(spec), frame);
    const Image src = test::render(p, scene, PixelType::F32);
    return test::converter(p, target, Eigen::Matrix3d::Identity(), Interp::Bicubic, engine, 0)
        .run(src);
  };
  // The seam's band in the equirect: longitudes +-90 degrees (x = W/4, 3W/4), 20 px wide.
  auto band = [&](int64_t x, int64_t) {
    return std::abs(x - eq.width / 4) < 10 || std::abs(x - 3 * eq.width / 4) < 10;
  };
  struct Shape {
    const char* name;
    int64_t face, outer, band;
  };
  for (const Shape& s : {Shape{"3K", 368, 384, 16}, Shape{"5.6K", 336, 344, 16}}) {
    const Size frame{2 * s.outer + s.face, 2 * s.face};
    const std::string spec = "gopro-max:face=" + std::to_string(s.face) +
                             ",outer=" + std::to_string(s.outer) +
                             ",band=" + std::to_string(s.band);
    const Image cube = through("cubemap:layout=eac", {3 * s.face, 2 * s.face});
    const Image max = through(spec, frame);
    const Image cut = through(spec + ",feather=0", frame);
    const Image scalar = through(spec, frame, Engine::Scalar);
    const double p_cube = test::psnr(cube, truth), p_max = test::psnr(max, truth),
                 p_cut = test::psnr(cut, truth);
    const double b_cube = test::psnr(cube, truth, band), b_max = test::psnr(max, truth, band);
    std::printf(
        "[gopro-max] %s shape, faces of %lld px: analytic scene -> equirect %lldx%lld: PSNR plain "
        "EAC cube %.2f dB "
        "(seam band %.2f), MAX %.2f (%.2f), hard cut %.2f; simd vs scalar %.2f dB\n",
        s.name, static_cast<long long>(s.face), static_cast<long long>(eq.width),
        static_cast<long long>(eq.height), p_cube, b_cube, p_max, b_max, p_cut,
        test::psnr(max, scalar));
    // (The 5.6K's outer faces hold 2.4% fewer pixels across: a little less detail there.)
    EXPECT_GT(p_max, p_cube - 1.0) << s.name;
    EXPECT_GT(b_max, b_cube - 1.5) << s.name;
    EXPECT_GT(p_cut, p_cube - 1.0) << s.name;
    EXPECT_GT(test::psnr(max, scalar), 90.0) << s.name;
  }
}

TEST(GoProMax, AHalfFrameIsTheParametricFormAtHalfSize) {
  const Projection full = make_projection(parse_spec("gopro-max"), {4096, 2688});
  const Projection half = rescaled(full, {2048, 1344});
  const Projection param =
      make_projection(parse_spec("gopro-max:face=672,outer=688,band=32"), {2048, 1344});
  double worst = 0;
  for (int64_t y = 0; y < 1344; y += 3)
    for (int64_t x = 0; x < 2048; x += 3) {
      Ray a, b;
      ASSERT_TRUE(to_ray(half, x + 0.5, y + 0.5, a));
      ASSERT_TRUE(to_ray(param, x + 0.5, y + 0.5, b));
      worst = std::max(worst, test::angle(a, b));
    }
  EXPECT_LT(worst, 1e-12);
}

TEST(GoProMax, BadSpecsAndFramesAreOneLine) {
  auto error_of = [](const std::string& spec, Size size) {
    try {
      make_projection(parse_spec(spec), size);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string unknown = error_of("gopro-max", {4000, 2688});
  EXPECT_NE(unknown.find("strips of 4000x1344 match no preset"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("max-5.6k 4096x1344"), std::string::npos) << unknown;
  EXPECT_NE(error_of("gopro-max", {4096, 1343}).find("odd height"), std::string::npos);
  EXPECT_NE(error_of("gopro-max:preset=max-3k", {4096, 2688}).find("do not hold faces"),
            std::string::npos);
  EXPECT_NE(error_of("gopro-max:face=1344", {4096, 2688}).find("without band="), std::string::npos);
  EXPECT_NE(error_of("gopro-max:preset=max-3k,band=32", {2272, 1472}).find("both given"),
            std::string::npos);
  EXPECT_NE(error_of("gopro-max:band=1376", {4096, 2688}).find("narrower"), std::string::npos);
  EXPECT_NE(error_of("gopro-max:band=63", {4096, 2688}).find("even band"), std::string::npos);
  EXPECT_NE(error_of("gopro-max:feather=5", {4096, 2688}).find("wider than the band"),
            std::string::npos);
  EXPECT_NE(error_of("gopro-max:feather=nan", {4096, 2688}), "no error");
  for (const auto& e : {unknown, error_of("gopro-max:feather=5", {4096, 2688})})
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

}  // namespace
}  // namespace panoproj
