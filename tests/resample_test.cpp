// Whole-image behaviour of the reference remap, against analytic truth rendered directly in the
// target projection.
#include "sampling/resample.hpp"

#include <gtest/gtest.h>

#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

using test::get;
using test::Scene;

Projection make(const char* spec, Size size) { return make_projection(parse_spec(spec), size); }

TEST(Remap, IdentityWithNearestIsExact) {
  const Scene scene = test::band_limited_scene(0.2, 512);
  for (auto [spec, size] : {std::pair{"equirect", Size{512, 256}},
                            {"fisheye:fov=200", {300, 300}},
                            {"cubemap:layout=cross", {4 * 96, 3 * 96}},
                            {"pinhole:hfov=100", {320, 200}},
                            {"cylindrical", {512, 240}},
                            {"aitoff", {512, 256}},
                            {"bonne:phi1=30", {400, 380}}}) {
    const Projection p = make(spec, size);
    for (PixelType t : {PixelType::U8, PixelType::F32}) {
      const Image src = test::render(p, scene, t, true);
      const Image out = remap(src, p, p, Eigen::Matrix3d::Identity(), {Interp::Nearest, 2});
      EXPECT_TRUE(out == src) << spec << " " << name_of(t);
    }
  }
}

TEST(Remap, Yaw90IsAnExactColumnShift) {
  const Projection p = make("equirect", {512, 256});
  const Image src = test::render(p, test::band_limited_scene(0.2, 512), PixelType::U8);
  const Image out = remap(src, p, p, rotation_from_ypr(90, 0, 0), {Interp::Nearest, 2});
  // Positive yaw looks right: output column x shows source column x + W/4.
  for (int64_t y = 0; y < 256; ++y)
    for (int64_t x = 0; x < 512; ++x)
      ASSERT_EQ(0, std::memcmp(out.pixel(x, y), src.pixel((x + 128) % 512, y), 3)) << x << "," << y;
}

TEST(Remap, EquirectCubeEquirectBicubicOnBandLimitedScene) {
  // A panorama defined on the sphere, band-limited to 0.1 cycles per equirect pixel at the
  // equator; face = W/4; uint8; bicubic both ways.
  const int64_t W = 2048;
  const Projection e = make("equirect", {W, W / 2});
  const Projection c = make("cubemap", {6 * (W / 4), W / 4});
  const Image src = test::render(e, test::band_limited_scene(0.1, W), PixelType::U8);
  const Image cube = remap(src, e, c, Eigen::Matrix3d::Identity(), {Interp::Bicubic, 0});
  const Image back = remap(cube, c, e, Eigen::Matrix3d::Identity(), {Interp::Bicubic, 0});
  const double db = test::psnr(back, src);
  std::printf("[e2c2e] synthetic 0.1 cyc/px, %lldx%lld, face %lld, bicubic: PSNR %.2f dB\n",
              static_cast<long long>(W), static_cast<long long>(W / 2),
              static_cast<long long>(W / 4), db);
  EXPECT_GE(db, 45.0);
}

TEST(Remap, ThreadCountDoesNotChangeOneBit) {
  const Projection e = make("equirect", {1024, 512});
  const Projection f = make("fisheye:fov=220,model=equisolid", {611, 611});
  const Image src = test::render(e, test::band_limited_scene(0.15, 1024), PixelType::U16, true);
  const Eigen::Matrix3d r = rotation_from_ypr(30, -20, 10);
  for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3}) {
    const Image one = remap(src, e, f, r, {k, 1});
    EXPECT_TRUE(remap(src, e, f, r, {k, 2}) == one) << name_of(k);
    EXPECT_TRUE(remap(src, e, f, r, {k, 7}) == one) << name_of(k);
  }
}

// Sampling across the equirect seam and poles and across cube edges and corners has no seam:
// the error against the truth near the identity is no worse than elsewhere.
TEST(Remap, NoSeamAtEquirectSeamPolesAndCubeCorners) {
  const Scene scene = test::band_limited_scene(0.05, 1024);
  const Projection e = make("equirect", {1024, 512});
  const Projection c = make("cubemap", {6 * 512, 512});
  const Projection cyl = make("cylindrical:vfov=100", {1024, 390});
  const Projection view = make("pinhole:hfov=60", {301, 301});
  struct Look {
    const Projection* src;
    double yaw, pitch;
    const char* what;
    double bound;
  };
  // Bounds ~2-5x the errors measured with the edge rules; with clamped taps instead of the rules,
  // the same looks err by 4e-3 .. 0.1. At a cube corner three faces meet and the neighbour's
  // bilinear read is itself clamped at its edge: 1.1e-3 (0.3 LSB at 8 bits) vs 3e-5 on edges.
  for (const Look& look : {Look{&e, 180, 0, "equirect seam", 1e-4}, Look{&e, 0, 90, "north pole", 1e-4},
                           Look{&e, 77, -90, "south pole", 1e-4}, Look{&c, 45, 35.26, "cube corner", 2e-3},
                           Look{&c, 135, -35.26, "cube corner below", 2e-3},
                           Look{&c, 90, 45, "cube edge", 1e-4}, Look{&c, 0, 0, "cube face centre", 2e-5},
                           Look{&cyl, 180, 0, "cylindrical seam", 1e-4}}) {
    const Image src = test::render(*look.src, scene, PixelType::F32);
    const Eigen::Matrix3d r = rotation_from_ypr(look.yaw, look.pitch, 0);
    const Image out = remap(src, *look.src, view, r, {Interp::Bicubic, 0});
    // Truth: the scene rendered directly in the view, through the same rotation.
    double worst = 0;
    double rgb[3];
    for (int64_t y = 0; y < 301; ++y)
      for (int64_t x = 0; x < 301; ++x) {
        Ray d;
        ASSERT_TRUE(to_ray(view, x + 0.5, y + 0.5, d));
        scene(r * d, rgb);
        for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::fabs(get(out, x, y, ch) - rgb[ch]));
      }
    std::printf("[seams] %-18s worst abs error %.2e\n", look.what, worst);
    EXPECT_LT(worst, look.bound) << look.what;
  }
}

TEST(Remap, OutsideTheSourceFieldIsTransparentNotSmeared) {
  // A narrow pinhole source, white and opaque, into a full equirect.
  const Projection pin = make("pinhole:hfov=40", {64, 48});
  Image src({64, 48}, 4, PixelType::U8, 3);
  std::memset(src.data(), 255, src.byte_size());
  const Projection e = make("equirect", {360, 180});
  for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Lanczos3}) {
    const Image out = remap(src, pin, e, Eigen::Matrix3d::Identity(), {k, 0});
    int64_t opaque = 0;
    for (int64_t y = 0; y < 180; ++y)
      for (int64_t x = 0; x < 360; ++x) {
        const double lon = rad2deg(std::fabs((x + 0.5) / 360 * kTwoPi - kPi));
        const double lat = rad2deg(std::fabs(kHalfPi - (y + 0.5) / 180 * kPi));
        const double a = get(out, x, y, 3);
        if (lon > 21 || lat > 16) {
          ASSERT_EQ(a, 0) << "smeared at " << x << "," << y;
          ASSERT_EQ(get(out, x, y, 0), 0);
        } else if (lon < 19 && lat < 13) {
          ASSERT_EQ(a, 255);
          ++opaque;
        }
      }
    EXPECT_GT(opaque, 400);
  }
}

TEST(Remap, AlphaIsInterpolatedPremultiplied) {
  // Opaque grey columns alternate with transparent bright red ones: no red may bleed in.
  const Projection e = make("equirect", {256, 128});
  Image src({256, 128}, 4, PixelType::U8, 3);
  for (int64_t y = 0; y < 128; ++y)
    for (int64_t x = 0; x < 256; ++x) {
      unsigned char* p = src.pixel(x, y);
      const bool opaque = (x / 4) % 2 == 0;
      p[0] = opaque ? 100 : 255;
      p[1] = opaque ? 100 : 0;
      p[2] = opaque ? 100 : 0;
      p[3] = opaque ? 255 : 0;
    }
  for (Interp k : {Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3}) {
    const Image out = remap(src, e, e, rotation_from_ypr(0.37, 0.21, 0), {k, 0});
    for (int64_t y = 10; y < 118; ++y)
      for (int64_t x = 0; x < 256; ++x) {
        if (get(out, x, y, 3) < 8) continue;  // colour of a nearly transparent pixel is moot
        for (int ch = 0; ch < 3; ++ch)
          ASSERT_NEAR(get(out, x, y, ch), 100, 2) << name_of(k) << " at " << x << "," << y;
      }
  }
}

TEST(Remap, PixelTypesAgreeAndFloatKeepsHdrAndNegatives) {
  const Projection e = make("equirect", {512, 256});
  const Projection f = make("fisheye:fov=180", {200, 200});
  const Scene scene = test::band_limited_scene(0.1, 512);
  const Image ref = remap(test::render(e, scene, PixelType::F32), e, f, Eigen::Matrix3d::Identity(),
                          {Interp::Bicubic, 0});
  for (auto [t, tol] : {std::pair{PixelType::U8, 1.5 / 255}, {PixelType::U16, 2.0 / 65535},
                        {PixelType::F16, 2e-3}}) {
    const Image out = remap(test::render(e, scene, t), e, f, Eigen::Matrix3d::Identity(),
                            {Interp::Bicubic, 0});
    double worst = 0;
    for (int64_t y = 0; y < 200; ++y)
      for (int64_t x = 0; x < 200; ++x)
        for (int ch = 0; ch < 3; ++ch)
          worst = std::max(worst, std::fabs(get(out, x, y, ch) / unit_of(t) - get(ref, x, y, ch)));
    EXPECT_LT(worst, tol + 2e-3) << name_of(t);  // quantization of input and output
  }
  // HDR: values far above 1 and negative ones pass through float untouched by clamping.
  Image hdr({64, 32}, 1, PixelType::F32);
  for (int64_t y = 0; y < 32; ++y)
    for (int64_t x = 0; x < 64; ++x) test::set(hdr, x, y, 0, x < 32 ? 5e4 : -3.0);
  const Projection small = make("equirect", {64, 32});
  const Image out = remap(hdr, small, small, Eigen::Matrix3d::Identity(), {Interp::Bilinear, 0});
  EXPECT_FLOAT_EQ(get(out, 10, 16, 0), 5e4);
  EXPECT_FLOAT_EQ(get(out, 50, 16, 0), -3.0);
}

TEST(Remap, OneToFourChannels) {
  const Projection e = make("equirect", {128, 64});
  for (int nc = 1; nc <= 4; ++nc) {
    Image src({128, 64}, nc, PixelType::U8, nc == 2 || nc == 4 ? nc - 1 : -1);
    for (size_t i = 0; i < src.byte_size(); ++i) src.data()[i] = static_cast<unsigned char>(i * 7);
    if (src.alpha_channel() >= 0)
      for (int64_t y = 0; y < 64; ++y)
        for (int64_t x = 0; x < 128; ++x) src.pixel(x, y)[nc - 1] = 255;
    const Image out = remap(src, e, e, Eigen::Matrix3d::Identity(), {Interp::Bicubic, 0});
    ASSERT_EQ(out.channels(), nc);
    // Bicubic at the pixel centres reproduces the input (Keys weights are 0, 1, 0, 0 there).
    EXPECT_TRUE(out == src) << nc;
  }
}

}  // namespace
}  // namespace panoproj
