// HDR end to end on a real HDRI (samples/images/blender_city_1024x512.exr: a sun at 3.4e4, tiny
// negative values from its DWAB compression) with two 16x16 patches painted in, one at -0.5 and
// one at 1e6 (past half float's range): equirect -> cubemap -> equirect in float with each kernel
// clamps nothing (the patches' centres come back), and reports the round trip's relative error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "panoproj/convert.hpp"
#include "sampling/interpolator.hpp"
#include "panoproj/io.hpp"
#include "panoproj/rotation.hpp"
#include "panoproj/spec.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

// All samples of a float image, row by row.
std::vector<float> samples_of(const Image& im) {
  std::vector<float> v;
  v.reserve(static_cast<size_t>(im.width() * im.height() * im.channels()));
  for (int64_t y = 0; y < im.height(); ++y) {
    const auto* row = reinterpret_cast<const float*>(im.pixel(0, y));
    v.insert(v.end(), row, row + im.width() * im.channels());
  }
  return v;
}

TEST(Hdr, RealHdriSurvivesEquirectCubeEquirect) {
  Image src = read_image(test::samples_dir() + "/blender_city_1024x512.exr");
  ASSERT_EQ(src.type(), PixelType::F32);
  // The patches, near the equator (where the cube's round trip is nearly 1:1).
  auto patch = [&](int64_t x0, int64_t y0, float v) {
    for (int64_t y = y0; y < y0 + 16; ++y)
      for (int64_t x = x0; x < x0 + 16; ++x)
        for (int c = 0; c < 3; ++c) reinterpret_cast<float*>(src.pixel(x, y))[c] = v;
  };
  patch(300, 250, -0.5f);
  patch(700, 240, 1e6f);
  auto centre = [](const Image& im, int64_t x0, int64_t y0) { return reinterpret_cast<const float*>(im.pixel(x0 + 8, y0 + 8))[1]; };
  const Projection e = make_projection(parse_spec("equirect"), {1024, 512});
  const Projection cube = make_projection(parse_spec("cubemap"), {6 * 512, 512});
  const std::vector<float> in = samples_of(src);
  const auto in_neg = std::count_if(in.begin(), in.end(), [](float v) { return v < 0; });
  for (Interp k : {Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3}) {
    const Image faces =
        test::converter(e, cube, Eigen::Matrix3d::Identity(), k, Engine::Simd, 2).run(src);
    const Image back =
        test::converter(cube, e, Eigen::Matrix3d::Identity(), k, Engine::Simd, 2).run(faces);
    const std::vector<float> out = samples_of(back);
    // Relative error |out - in| / max(|in|, 0.01) (0.01: the darkest values that matter here).
    std::vector<double> rel(out.size());
    bool finite = true;
    for (size_t i = 0; i < out.size(); ++i) {
      finite &= std::isfinite(out[i]);
      rel[i] = std::fabs(out[i] - in[i]) / std::max(std::fabs(in[i]), 0.01f);
    }
    std::sort(rel.begin(), rel.end());
    const double median = rel[rel.size() / 2], p99 = rel[rel.size() * 99 / 100];
    const auto out_neg = std::count_if(out.begin(), out.end(), [](float v) { return v < 0; });
    // The sun: a few pixels of the original (away from the patches).
    float sun_in = 0, sun_out = 0;
    for (size_t i = 0; i < in.size(); ++i)
      if (in[i] < 1e5f && in[i] > sun_in) sun_in = in[i], sun_out = out[i];
    std::printf("[hdr] city 1024x512 -> cube 6x512^2 -> equirect, %s: relative error median %.2e, 99th percentile %.2e; "
                "sun's brightest sample %.4g -> %.4g; patches -0.5 -> %.6g, 1e6 -> %.7g; negative samples %lld -> %lld\n",
                name_of(k), median, p99, sun_in, sun_out, centre(back, 300, 250), centre(back, 700, 240),
                static_cast<long long>(in_neg), static_cast<long long>(out_neg));
    EXPECT_TRUE(finite) << name_of(k);
    EXPECT_LT(median, 0.01) << name_of(k);
    EXPECT_NEAR(centre(back, 300, 250), -0.5f, 1e-5f) << name_of(k);
    EXPECT_NEAR(centre(back, 700, 240), 1e6f, 10.0f) << name_of(k);
    EXPECT_GT(sun_out, 0.3f * sun_in) << name_of(k);  // spread by the kernel, not clipped
  }
}

// The deringing kernels on the real sun (the HDRI as it is: its own tiny negatives kept apart):
// equirect -> Aitoff 1024x512 in float (a target both engines map with the tile mapper, so their
// positions are the same and only the kernels differ), against the plain kernels. Bicubic and
// Lanczos-3 ring around the sun (samples below every tap near them); the deringed ones stay
// within the 2x2 taps around each sample, so they make no sample outside the source's range, and
// the SIMD kernels agree with the scalar ones (float weights against double: within 5e-6 of the
// brightest sample, engine_test's bound scaled to this range). Reported: how many samples the clamp changes (on
// this textured city, also the kernels' sharpening of fine detail).
TEST(Hdr, DeringingKernelsKeepTheSunsRingsOut) {
  const Image src = read_image(test::samples_dir() + "/blender_city_1024x512.exr");
  const std::vector<float> in = samples_of(src);
  const float in_min = *std::min_element(in.begin(), in.end()), in_max = *std::max_element(in.begin(), in.end());
  const Projection e = make_projection(parse_spec("equirect"), {1024, 512});
  const Projection cube = make_projection(parse_spec("aitoff"), {1024, 512});
  const Eigen::Matrix3d r = rotation_from_ypr(10, 5, 0);
  for (auto [plain, dering] : {std::pair{Interp::Bicubic, Interp::BicubicDering}, {Interp::Lanczos3, Interp::Lanczos3Dering}}) {
    const std::vector<float> p =
        samples_of(test::converter(e, cube, r, plain, Engine::Simd, 2).run(src));
    const std::vector<float> d =
        samples_of(test::converter(e, cube, r, dering, Engine::Simd, 2).run(src));
    const std::vector<float> ds =
        samples_of(test::converter(e, cube, r, dering, Engine::Scalar, 2).run(src));
    int64_t below = 0, below_d = 0, changed = 0;
    double worst = 0, ring = 0;
    for (size_t i = 0; i < p.size(); ++i) {
      below += p[i] < in_min;
      below_d += d[i] < in_min || d[i] > in_max;
      changed += d[i] != p[i];
      ring = std::max(ring, static_cast<double>(d[i] - p[i]));
      worst = std::max(worst, std::fabs(static_cast<double>(d[i]) - ds[i]) / in_max);
    }
    std::printf("[hdr] dering, %s -> %s: %lld samples below the source's least (%g) -> %lld outside its range; "
                "%.2f%% of samples changed, by up to %.4g; SIMD vs scalar %.1e of the brightest sample\n",
                name_of(plain), name_of(dering), static_cast<long long>(below), in_min, static_cast<long long>(below_d),
                100.0 * static_cast<double>(changed) / static_cast<double>(p.size()), ring, worst);
    EXPECT_GT(below, 0) << name_of(plain) << " rings (else this scene proves nothing)";
    EXPECT_EQ(below_d, 0) << name_of(dering);
    EXPECT_LT(changed * 4, static_cast<int64_t>(p.size()));
    EXPECT_LT(worst, 5e-6);  // engine_test's float bound, on values up to the sun's
  }
}

// uint8 takes the generic kernel when deringing (the fixed-point one has no clamp): on a sharp
// checkerboard of 40 and 200, within 1 LSB of the scalar engine and every sample between the two
// levels (the plain kernels overshoot both).
TEST(Hdr, DeringingUint8MatchesTheReference) {
  const Projection e = make_projection(parse_spec("equirect"), {512, 256});
  Image src({512, 256}, 3, PixelType::U8);
  for (int64_t y = 0; y < 256; ++y)
    for (int64_t x = 0; x < 512; ++x) std::memset(src.pixel(x, y), ((x / 8 + y / 8) % 2) ? 200 : 40, 3);
  const Projection pin = make_projection(parse_spec("pinhole:hfov=70"), {301, 203});
  const Eigen::Matrix3d r = rotation_from_ypr(33, 12, 7);
  for (Interp k : {Interp::BicubicDering, Interp::Lanczos3Dering}) {
    const Image a = test::converter(e, pin, r, k, Engine::Simd, 2).run(src);
    const Image b = test::converter(e, pin, r, k, Engine::Scalar, 2).run(src);
    const Image plain = test::converter(e, pin, r, kernel_of(k), Engine::Simd, 2).run(src);
    int worst = 0, outside = 0, plain_outside = 0;
    for (size_t i = 0; i < a.byte_size(); ++i) {
      worst = std::max(worst, std::abs(a.data()[i] - b.data()[i]));
      outside += a.data()[i] < 40 || a.data()[i] > 200;
      plain_outside += plain.data()[i] < 40 || plain.data()[i] > 200;
    }
    EXPECT_LE(worst, 1) << name_of(k);
    EXPECT_EQ(outside, 0) << name_of(k);
    EXPECT_GT(plain_outside, 0) << name_of(kernel_of(k));
  }
}

}  // namespace
}  // namespace panoproj
