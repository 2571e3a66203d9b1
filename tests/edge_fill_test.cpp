// Alpha, masks and fill (EdgeFill, the converter's alpha handling):
//  - soft edges: on a fisheye target's rim, alpha follows the circle's exact area coverage of each
//    pixel; inside, the pixels are the plain conversion's bytes; outside, alpha 0;
//  - a fill colour is the alpha output composited over that colour (within 1 LSB), exactly the
//    colour far outside, and the same in every engine;
//  - masks: on the real Mars panorama (sky alpha 0) nothing of the transparent pixels' colour
//    reaches the output, for every kernel and engine;
//  - fill colours parse, bad ones are one-line errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "panoproj/convert.hpp"
#include "panoproj/options.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

const Eigen::Matrix3d kIdentity = Eigen::Matrix3d::Identity();

Image smooth_rgba(const Projection& e) { return test::render(e, test::smooth_scene(), PixelType::U8, true); }

// The exact share of pixel (x, y) inside the fisheye's image circle (centre c, radius r), by 64 x 64
// point sampling.
double circle_coverage(int64_t x, int64_t y, double c, double r) {
  int in = 0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) in += std::hypot(x + (i + 0.5) / 64 - c, y + (j + 0.5) / 64 - c) <= r;
  return in / 4096.0;
}

TEST(EdgeFill, SoftAlphaFollowsTheCirclesCoverage) {
  const Projection e = make_projection(parse_spec("equirect"), {512, 256});
  const Projection f = make_projection(parse_spec("fisheye:fov=180"), {201, 201});
  const Image src = smooth_rgba(e);
  EdgeFill soft;
  soft.soft = true;
  std::vector<double> coverage(201 * 201);
  for (int64_t y = 0; y < 201; ++y)
    for (int64_t x = 0; x < 201; ++x) coverage[static_cast<size_t>(y * 201 + x)] = circle_coverage(x, y, 100.5, 100.5);
  for (Engine eng : {Engine::Simd, Engine::Scalar, Engine::Reference}) {
    const Image plain = test::converter(e, f, kIdentity, Interp::Bicubic, eng, 2).run(src);
    const Image out =
        test::converter(e, f, kIdentity, Interp::Bicubic, eng, 2, Keep::Nothing, {}, soft).run(src);
    double worst = 0, sum = 0;
    int64_t rim = 0, changed_inside = 0;
    for (int64_t y = 0; y < 201; ++y)
      for (int64_t x = 0; x < 201; ++x) {
        const double cov = coverage[static_cast<size_t>(y * 201 + x)];
        const double a = out.pixel(x, y)[3] / 255.0;
        if (cov > 0 && cov < 1) {
          ++rim;
          worst = std::max(worst, std::fabs(a - cov));
          sum += std::fabs(a - cov);
        } else if (cov == 0) {
          EXPECT_EQ(out.pixel(x, y)[3], 0);
        } else {
          // Well inside: untouched (a pixel whose neighbour reaches the rim is resampled).
          const double r = std::hypot(x + 0.5 - 100.5, y + 0.5 - 100.5);
          if (r < 98) changed_inside += std::memcmp(out.pixel(x, y), plain.pixel(x, y), 4) != 0;
        }
      }
    std::printf("[edges] %s: %lld rim pixels, alpha vs exact coverage: mean %.3f, worst %.3f\n", name_of(eng),
                static_cast<long long>(rim), sum / static_cast<double>(rim), worst);
    EXPECT_GT(rim, 500);
    EXPECT_LT(sum / static_cast<double>(rim), 0.03) << name_of(eng);
    EXPECT_LT(worst, 0.16) << name_of(eng);  // 4x4 sub-positions: steps of 1/16, a curved edge
    EXPECT_EQ(changed_inside, 0) << name_of(eng);
  }
}

TEST(EdgeFill, FillIsTheAlphaOutputOverTheColour) {
  const Projection e = make_projection(parse_spec("equirect"), {512, 256});
  const Projection f = make_projection(parse_spec("fisheye:fov=200"), {160, 120});
  const Image rgba = smooth_rgba(e);
  Image rgb({512, 256}, 3, PixelType::U8);
  for (int64_t y = 0; y < 256; ++y)
    for (int64_t x = 0; x < 512; ++x) std::memcpy(rgb.pixel(x, y), rgba.pixel(x, y), 3);
  const std::array<double, 4> colour = parse_fill_colour("0.25,0.5,0.75");
  for (Engine eng : {Engine::Simd, Engine::Reference}) {
    const Image alpha = test::converter(e, f, kIdentity, Interp::Bilinear, eng, 2, Keep::Nothing,
                                        {}, {true, std::nullopt})
                            .run(rgba);
    const Image filled = test::converter(e, f, kIdentity, Interp::Bilinear, eng, 2, Keep::Nothing,
                                         {}, {true, colour})
                             .run(rgb);
    int worst = 0;
    for (int64_t y = 0; y < 120; ++y)
      for (int64_t x = 0; x < 160; ++x) {
        const double a = alpha.pixel(x, y)[3] / 255.0;
        for (int c = 0; c < 3; ++c) {
          const double over = a * alpha.pixel(x, y)[c] + (1 - a) * colour[c] * 255;
          worst = std::max(worst, static_cast<int>(std::lround(std::fabs(over - filled.pixel(x, y)[c]))));
        }
      }
    EXPECT_LE(worst, 1) << name_of(eng);
    // A corner, far outside the circle: the colour itself.
    EXPECT_EQ(filled.pixel(0, 0)[0], 64);
    EXPECT_EQ(filled.pixel(0, 0)[1], 128);
    EXPECT_EQ(filled.pixel(0, 0)[2], 191);
  }
}

// The sky of the real Mars panorama is transparent; painting its colour magenta must change no
// output pixel that has any alpha (premultiplied interpolation: its taps weigh nothing).
TEST(EdgeFill, TransparentPixelsNeverBleed) {
  const Image mars = read_image(test::samples_dir() + "/mars_spirit_1024x512_rgba.png");
  ASSERT_EQ(mars.alpha_channel(), 3);
  Image painted = mars;
  int64_t sky = 0;
  for (int64_t y = 0; y < mars.height(); ++y)
    for (int64_t x = 0; x < mars.width(); ++x) {
      unsigned char* p = painted.pixel(x, y);
      if (p[3] == 0) p[0] = 255, p[1] = 0, p[2] = 255, ++sky;
    }
  ASSERT_GT(sky, mars.width() * mars.height() / 4);
  const Projection e = make_projection(parse_spec("equirect"), {1024, 512});
  const Projection view = make_projection(parse_spec("pinhole:hfov=90"), {320, 240});
  const Eigen::Matrix3d r = rotation_from_ypr(40, 8, 0);  // the horizon across the view
  for (Engine eng : {Engine::Simd, Engine::Scalar, Engine::Reference})
    for (Interp k : {Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3, Interp::Lanczos3Dering}) {
      const Image a = test::converter(e, view, r, k, eng, 2).run(mars);
      const Image b = test::converter(e, view, r, k, eng, 2).run(painted);
      int worst = 0;
      int64_t partial = 0;
      for (int64_t y = 0; y < 240; ++y)
        for (int64_t x = 0; x < 320; ++x) {
          const unsigned char* p = a.pixel(x, y);
          if (p[3] == 0) continue;
          partial += p[3] < 255;
          for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(p[c] - b.pixel(x, y)[c]));
        }
      EXPECT_GT(partial, 100) << "the view should cross the sky's edge";
      EXPECT_LE(worst, 1) << name_of(eng) << " " << name_of(k);
    }
}

TEST(EdgeFill, ColoursParseAndBadOnesAreErrors) {
  EXPECT_EQ(parse_fill_colour("1,1,1"), (std::array<double, 4>{1, 1, 1, 1}));
  EXPECT_EQ(parse_fill_colour("0.5,0,2.5,0"), (std::array<double, 4>{0.5, 0, 2.5, 0}));
  EXPECT_EQ(parse_fill_colour("#ff8000"), (std::array<double, 4>{1, 128 / 255.0, 0, 1}));
  EXPECT_EQ(parse_fill_colour("#00000080"), (std::array<double, 4>{0, 0, 0, 128 / 255.0}));
  for (const char* bad : {"", "1,1", "1,1,1,1,1", "red", "#fff", "#gg0000", "1,nan,1", "1,,1", "1,1,1,"}) {
    try {
      parse_fill_colour(bad);
      ADD_FAILURE() << bad;
    } catch (const Error& err) {
      EXPECT_NE(std::string(err.what()).find("fill colour '" + std::string(bad) + "'"), std::string::npos) << err.what();
    }
  }
}

}  // namespace
}  // namespace panoproj
