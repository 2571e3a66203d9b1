// Antialiasing (options.hpp: Antialias): mip levels, their blend, supersampling; against area-averaged
// truth from the analytic scenes (scene.hpp). Also rescaled() projections, which both rely on.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>

#include "panoproj/diagnostics/accuracy.hpp"
#include "panoproj/options.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/rotation.hpp"
#include "panoproj/diagnostics/scene.hpp"
#include "panoproj/spec.hpp"
#include "sampling/pyramid.hpp"
#include "sampling/subpixels.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

using test::get;

Projection make(const char* spec, Size size) { return make_projection(parse_spec(spec), size); }

Image convert(const Image& im, const Projection& s, const Projection& d, Interp k, Antialias aa,
              Engine e = Engine::Simd, const Eigen::Matrix3d& r = Eigen::Matrix3d::Identity()) {
  return test::converter(s, d, r, k, e, 2, Keep::Nothing, aa).run(im);
}

const Antialias kOff{}, kAuto{Antialias::Mode::Auto, 1}, kMip{Antialias::Mode::Mip, 1};

TEST(Antialias, ParsesAndNames) {
  EXPECT_EQ(parse_antialias("off").mode, Antialias::Mode::Off);
  EXPECT_EQ(parse_antialias("auto").mode, Antialias::Mode::Auto);
  EXPECT_EQ(parse_antialias("mip").mode, Antialias::Mode::Mip);
  EXPECT_EQ(parse_antialias("4").n, 4);
  EXPECT_EQ(name_of(parse_antialias("7")), "7");
  for (const char* bad : {"1", "17", "4x", "", "on", "-2"}) {
    try {
      parse_antialias(bad);
      ADD_FAILURE() << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("antialias '" + std::string(bad) + "'"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(test::converter(make("equirect", {64, 32}), make("pinhole", {16, 16}),
                               Eigen::Matrix3d::Identity(), Interp::Bilinear, Engine::Reference, 1,
                               Keep::Nothing, kAuto),
               Error);
}

TEST(Antialias, RescaledProjectionsScalePixelPositions) {
  const char* specs[] = {"pinhole:hfov=100", "fisheye:fov=200,model=equisolid", "equirect", "equirect:hfov=120,vfov=80,lat0=10",
                         "cylindrical:hfov=360,vfov=100", "aitoff", "hammer", "bonne:phi1=40", "cubemap:layout=cross"};
  for (const char* spec : specs) {
    const Projection p = make(spec, std::string(spec).rfind("cubemap", 0) == 0 ? Size{4 * 40, 3 * 40} : Size{160, 100});
    const Size s = size_of(p);
    // Each axis scales on its own (cube faces stay square).
    const bool cube = std::string(spec).rfind("cubemap", 0) == 0;
    for (const auto& [fx, fy] : {std::pair{3, 3}, std::pair{2, 4}}) {
      if (cube && fx != fy) continue;
      const Projection q = rescaled(p, {s.width * fx, s.height * fy});
      int checked = 0;
      for (double y = 3.5; y < s.height; y += 7)
        for (double x = 2.5; x < s.width; x += 7) {
          Ray d;
          double qx, qy;
          if (!to_ray(p, x, y, d)) continue;
          ASSERT_TRUE(to_pixel(q, d, qx, qy)) << spec;
          EXPECT_NEAR(qx, fx * x, 1e-7 * s.width) << spec << " " << fx << "x" << fy;
          EXPECT_NEAR(qy, fy * y, 1e-7 * s.height) << spec << " " << fx << "x" << fy;
          ++checked;
        }
      EXPECT_GT(checked, 50) << spec;
    }
  }
  EXPECT_THROW(rescaled(make("cubemap", {6 * 10, 10}), {65, 10}), Error);
}

TEST(Antialias, AutoLeavesMagnifyingConversionsUntouched) {
  // A 90-degree pinhole of 200 px (127 px per radian) from a 512-px equirect (81): rho < 1.
  const Projection s = make("equirect", {512, 256}), d = make("pinhole:hfov=90", {200, 150});
  const Image im = render_scene(Scene::Waves, s, PixelType::U8, 1, 2);
  for (Interp k : {Interp::Bilinear, Interp::Lanczos3})
    for (Antialias aa : {kAuto, kMip}) EXPECT_TRUE(convert(im, s, d, k, aa) == convert(im, s, d, k, kOff)) << name_of(k);
  // Same-scale views whose tiles cross the seam, the poles or cube faces (their source extent
  // spans the frame, but no pixel's own footprint does).
  const Eigen::Matrix3d r = rotation_from_ypr(37, 0, 0);
  const Projection cube = make("cubemap", {6 * 128, 128});
  const Image cube_im = render_scene(Scene::Waves, cube, PixelType::U8, 1, 2);
  for (Antialias aa : {kAuto, kMip}) {
    EXPECT_TRUE(convert(im, s, s, Interp::Bilinear, aa, Engine::Simd, r) == convert(im, s, s, Interp::Bilinear, kOff, Engine::Simd, r))
        << name_of(aa);
    EXPECT_TRUE(convert(cube_im, cube, cube, Interp::Bilinear, aa) == convert(cube_im, cube, cube, Interp::Bilinear, kOff))
        << name_of(aa);
  }
}

TEST(Antialias, UniformShrinkIsTheAreaAverage) {
  // Equirect 1024x512 -> 256x128: every output pixel spans 4x4 source pixels. Auto takes 2x2
  // sub-pixels, each at the centre of a 2x2 block, where bilinear is that block's mean; mip
  // samples level 1 (2x2 means) halfway between two of its pixels. Both give the 4x4 mean.
  const Projection s = make("equirect", {1024, 512}), d = make("equirect", {256, 128});
  for (PixelType t : {PixelType::F32, PixelType::U8}) {
    const Image im = render_scene(Scene::Chart, s, t, 1, 2);
    for (Antialias aa : {kAuto, kMip}) {
      const Image out = convert(im, s, d, Interp::Bilinear, aa);
      double worst = 0;
      for (int64_t y = 0; y < 128; ++y)
        for (int64_t x = 0; x < 256; ++x) {
          double mean = 0;
          for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) mean += get(im, 4 * x + i, 4 * y + j, 0) / 16;
          worst = std::max(worst, std::fabs(get(out, x, y, 0) - mean));
        }
      // Float: float weights and sums; uint8: the rounding of the sub-pixels (or levels) and of
      // their mean.
      EXPECT_LT(worst, t == PixelType::F32 ? 5e-5 : 1.0) << name_of(aa) << " " << name_of(t);
    }
  }
}

TEST(Antialias, ShrinkingGainsOverAliasing) {
  // The sharp chart, equirect 1024x512 -> fisheye 180 128x128 (4 times smaller, as the bench's
  // 4096 -> 512), truth the area average of each output pixel (8x8 rays).
  const Projection s = make("equirect", {1024, 512}), d = make("fisheye:fov=180", {128, 128});
  const Image im = render_scene(Scene::Chart, s, PixelType::U8, 2, 2);
  const Image truth = render_scene(Scene::Chart, d, PixelType::U8, 8, 2);
  const auto mask = compared_pixels(s, d, Eigen::Matrix3d::Identity());
  for (Interp k : {Interp::Bilinear, Interp::Bicubic}) {
    const double off = compare_images(convert(im, s, d, k, kOff), truth, mask).psnr;
    const double aut = compare_images(convert(im, s, d, k, kAuto), truth, mask).psnr;
    const double mip = compare_images(convert(im, s, d, k, kMip), truth, mask).psnr;
    const double sup = compare_images(convert(im, s, d, k, {Antialias::Mode::Supersample, 4}), truth, mask).psnr;
    std::printf("[antialias] chart %s: off %.2f dB, auto %.2f dB, mip %.2f dB, 4x4 %.2f dB\n", name_of(k), off, aut, mip,
                sup);
    EXPECT_GE(aut, off + 3.0) << name_of(k);
    EXPECT_GE(mip, off + 3.0) << name_of(k);
    EXPECT_GE(sup, off + 3.0) << name_of(k);
  }
}

TEST(Antialias, EnginesAgree) {
  // The same levels and weights under the SIMD kernels and the reference sampler.
  const Projection s = make("equirect", {1024, 512}), d = make("fisheye:fov=190,model=equisolid", {96, 96});
  const Image im = render_scene(Scene::Waves, s, PixelType::U8, 1, 2);
  const Eigen::Matrix3d r = rotation_from_ypr(30, 50, 10);  // the pole in view
  for (Antialias aa : {kAuto, kMip, Antialias{Antialias::Mode::Supersample, 3}}) {
    const Image a = convert(im, s, d, Interp::Bicubic, aa, Engine::Simd, r);
    const Image b = convert(im, s, d, Interp::Bicubic, aa, Engine::Scalar, r);
    double worst = 0;
    for (int64_t y = 0; y < 96; ++y)
      for (int64_t x = 0; x < 96; ++x)
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(get(a, x, y, c) - get(b, x, y, c)));
    EXPECT_LE(worst, 1.0) << name_of(aa);
  }
}

TEST(Antialias, SubpixelsOnEveryTarget) {
  // 5x5 sub-pixels make 320-px rects of the 5-times target, sampled in kTile parts: on every
  // Highway target (the narrowest hold the fewest pixels per chunk of blocks) the SIMD result
  // stays within 1 LSB of the reference sampler's.
  const Projection s = make("equirect", {512, 256}), d = make("pinhole:hfov=120", {70, 50});
  const Image im = render_scene(Scene::Waves, s, PixelType::U8, 1, 2);
  const Antialias five{Antialias::Mode::Supersample, 5};
  const Image want = convert(im, s, d, Interp::Bilinear, five, Engine::Scalar);
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    const Image got = convert(im, s, d, Interp::Bilinear, five);
    double worst = 0;
    for (int64_t y = 0; y < 50; ++y)
      for (int64_t x = 0; x < 70; ++x)
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(get(got, x, y, c) - get(want, x, y, c)));
    EXPECT_LE(worst, 1.0) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(Antialias, IntegerSubpixelMeansRoundTheExactMeans) {
  // The integer path (8/16-bit without alpha; n = 2 compiled apart) against the exact mean of
  // each n x n block, rounded half up, on random samples over odd sizes.
  std::mt19937 rng(7);
  for (PixelType t : {PixelType::U8, PixelType::U16})
    for (int n : {2, 3, 4}) {
      const PixelRect rect{0, 0, 13, 5};
      const int nc = 3;
      Image sub({rect.width() * n, rect.height() * n}, nc, t, -1);
      const uint32_t top = t == PixelType::U8 ? 255 : 65535;
      for (int64_t y = 0; y < sub.height(); ++y)
        for (int64_t x = 0; x < sub.width(); ++x)
          for (int c = 0; c < nc; ++c) {
            const auto v = static_cast<uint16_t>(rng() % (top + 1));
            if (t == PixelType::U8) sub.pixel(x, y)[c] = static_cast<unsigned char>(v);
            else std::memcpy(sub.pixel(x, y) + 2 * c, &v, 2);
          }
      Image out({rect.width(), rect.height()}, nc, t, -1);
      average_subpixels(sub, sub.data(), static_cast<int64_t>(sub.row_bytes()), rect, n, out.data(),
                        static_cast<int64_t>(out.row_bytes()));
      int wrong = 0;
      for (int64_t y = 0; y < rect.height(); ++y)
        for (int64_t x = 0; x < rect.width(); ++x)
          for (int c = 0; c < nc; ++c) {
            double sum = 0;
            for (int b = 0; b < n; ++b)
              for (int a = 0; a < n; ++a) sum += get(sub, x * n + a, y * n + b, c);
            wrong += get(out, x, y, c) != std::floor(sum / (n * n) + 0.5);
          }
      EXPECT_EQ(wrong, 0) << name_of(t) << " n " << n;
    }
}

TEST(Antialias, PyramidLevelsAreBlockMeansEvenOfAWindow) {
  // Level 2 of a float image is the mean of each 4x4 block; a window of the frame (odd origin)
  // gives the same values wherever its blocks are whole.
  const Projection p = make("equirect", {64, 32});
  const Image im = render_scene(Scene::Waves, p, PixelType::F32, 1, 1);
  const Pyramid full(im, p);
  full.build_rows(2, 0, 32);
  ASSERT_EQ(full.levels(), 6);  // 64x32 -> 2x1
  const Image& l2 = full.image(2);
  ASSERT_EQ(l2.size(), (Size{16, 8}));
  for (int64_t y = 0; y < 8; ++y)
    for (int64_t x = 0; x < 16; ++x) {
      double mean = 0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) mean += get(im, 4 * x + i, 4 * y + j, 1) / 16;
      EXPECT_NEAR(get(l2, x, y, 1), mean, 1e-6);
    }
  Image win({41, 23}, 3, PixelType::F32);
  for (int64_t y = 0; y < 23; ++y) std::memcpy(win.row(y), im.pixel(5, 3 + y), win.row_bytes());
  win.set_window(5, 3, {64, 32});
  const Pyramid part(win, p);
  part.build_rows(2, 0, 32);
  const Image& w2 = part.image(2);
  int compared = 0;
  for (int64_t Y = 2; Y < 6; ++Y)  // blocks of frame rows 8..23 and columns 8..43: inside
    for (int64_t X = 2; X < 11; ++X, ++compared)
      EXPECT_FLOAT_EQ(get(w2, X - w2.origin_x(), Y - w2.origin_y(), 0), get(l2, X, Y, 0));
  EXPECT_EQ(compared, 36);
}

TEST(Antialias, IntegerLevelsRoundTheBlockMeans) {
  // uint8, 3 channels, a window starting on odd pixels: every level-1 pixel is (a + b + c + d +
  // 2) / 4 of its block, the pixels outside the window replaced by the nearest held ones.
  const Projection p = make("equirect", {64, 32});
  Image win({41, 23}, 3, PixelType::U8);
  std::mt19937 rng(3);
  for (size_t i = 0; i < win.byte_size(); ++i) win.data()[i] = static_cast<unsigned char>(rng());
  win.set_window(5, 3, {64, 32});
  const Pyramid pyr(win, p);
  pyr.build_rows(1, 0, 32);
  const Image& l1 = pyr.image(1);
  ASSERT_EQ(l1.origin_x(), 2);
  ASSERT_EQ(l1.width(), 21);  // level columns 2 .. 22: frame columns 4 .. 45 hold 5 .. 45
  for (int64_t y = 0; y < l1.height(); ++y)
    for (int64_t x = 0; x < l1.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) {
            const int64_t fx = std::clamp<int64_t>(2 * (x + 2) + i, 5, 45), fy = std::clamp<int64_t>(2 * (y + 1) + j, 3, 25);
            sum += win.at(fx, fy)[c];
          }
        ASSERT_EQ(l1.pixel(x, y)[c], (sum + 2) / 4) << x << "," << y << " channel " << c;
      }
}

TEST(Antialias, TransparentPixelsAddNoColour) {
  // Opaque green columns between transparent red ones: shrunk, no red may show.
  const Projection s = make("equirect", {512, 256}), d = make("equirect", {32, 16});
  Image im({512, 256}, 4, PixelType::U8, 3);
  for (int64_t y = 0; y < 256; ++y)
    for (int64_t x = 0; x < 512; ++x) {
      unsigned char* q = im.pixel(x, y);
      const bool opaque = x % 8 < 3;
      q[0] = opaque ? 0 : 255, q[1] = opaque ? 255 : 0, q[2] = 0, q[3] = opaque ? 255 : 0;
    }
  for (Antialias aa : {kAuto, kMip, Antialias{Antialias::Mode::Supersample, 4}}) {
    const Image out = convert(im, s, d, Interp::Bilinear, aa);
    int max_red = 0, min_alpha = 255;
    for (int64_t y = 0; y < 16; ++y)
      for (int64_t x = 0; x < 32; ++x) max_red = std::max<int>(max_red, out.pixel(x, y)[0]), min_alpha = std::min<int>(min_alpha, out.pixel(x, y)[3]);
    EXPECT_LE(max_red, 1) << name_of(aa);
    EXPECT_GT(min_alpha, 60) << name_of(aa);  // about 3/8 covered
  }
}

TEST(Antialias, FootprintHoldsWhatItReads) {
  // The CLI reads only source_footprint(): a window of just that gives the full image's bytes.
  // 12 source px per output px: mip level 2 and 3 (Lanczos-3 reaching 24 px at level 3).
  const Projection s = make("equirect", {2048, 1024}), d = make("pinhole:hfov=60", {32, 24});
  const Image im = render_scene(Scene::Chart, s, PixelType::U8, 1, 2);
  const Eigen::Matrix3d r = rotation_from_ypr(70, 20, 0);
  for (Antialias aa : {kAuto, kMip, Antialias{Antialias::Mode::Supersample, 3}}) {
    const Converter c =
        test::converter(s, d, r, Interp::Lanczos3, Engine::Simd, 2, Keep::Nothing, aa);
    const PixelRect g = c.source_footprint();
    ASSERT_LT((g.x1 - g.x0) * (g.y1 - g.y0), 2048 * 1024 / 4) << "a small part of the source";
    Image win({g.x1 - g.x0, g.y1 - g.y0}, 3, PixelType::U8);
    for (int64_t y = 0; y < win.height(); ++y) std::memcpy(win.row(y), im.pixel(g.x0, g.y0 + y), win.row_bytes());
    win.set_window(g.x0, g.y0, {2048, 1024});
    EXPECT_TRUE(c.run(win) == c.run(im)) << name_of(aa);
  }
  // Views around the poles at 20-60x shrinks, where a pixel's sub-pixels reach the pole its
  // centres miss (by 18 rows in a 32x shrink: read_while_converting_test).
  struct View {
    const char* to;
    Size size;
    double yaw, pitch, roll;
  };
  for (const View& v : {View{"pinhole:hfov=120", {32, 24}, 0, -80, 0}, View{"pinhole:hfov=120", {24, 16}, 10, 85, 30},
                        View{"pinhole:hfov=90", {16, 16}, 0, -89, 0}, View{"fisheye:fov=180", {24, 24}, 0, -70, 0}})
    for (Antialias aa : {kAuto, kMip, Antialias{Antialias::Mode::Supersample, 8}}) {
      const Converter c =
          test::converter(s, make(v.to, v.size), rotation_from_ypr(v.yaw, v.pitch, v.roll),
                          Interp::Bilinear, Engine::Simd, 2, Keep::Nothing, aa);
      const PixelRect g = c.source_footprint();
      Image win({g.x1 - g.x0, g.y1 - g.y0}, 3, PixelType::U8);
      for (int64_t y = 0; y < win.height(); ++y) std::memcpy(win.row(y), im.pixel(g.x0, g.y0 + y), win.row_bytes());
      win.set_window(g.x0, g.y0, {2048, 1024});
      EXPECT_TRUE(c.run(win) == c.run(im)) << v.to << " pitch " << v.pitch << ", " << name_of(aa);
    }
}

}  // namespace
}  // namespace panoproj
