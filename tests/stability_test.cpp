// The stability report's cases as assertions (stability.hpp), and conversions of extreme
// sources: float samples from 1e-30 to 1e30 (and 16-bit ones at both ends of their range)
// through every kernel and engine, and images of 1x1 and 1x40000 pixels: no NaN or inf out.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "panoproj/convert.hpp"
#include "panoproj/rotation.hpp"
#include "panoproj/diagnostics/stability.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

TEST(Stability, EveryCaseWithinItsBound) {
  std::vector<StabilityResult> results;
  for (const StabilityCase& c : stability_cases()) {
    const StabilityResult r = run_stability_case(c);
    EXPECT_TRUE(r.pass()) << c.spec << " " << c.size.width << "x" << c.size.height << ": " << r.max_px << " px, "
                          << r.non_finite << " non-finite, " << r.lost << " lost";
    EXPECT_GT(r.points, 0) << c.spec;
    if (c.spec == "aitoff" && c.size.width > 1) {
      EXPECT_GT(r.max_newton, 0) << "the Newton inverse ran";
    }
    results.push_back(r);
  }
  EXPECT_GE(results.size(), 100u);
  std::printf("%s", stability_table(results).c_str());
}

Projection make(const char* spec, Size size) { return make_projection(parse_spec(spec), size); }

int64_t non_finite(const Image& im) {
  int64_t n = 0;
  for (int64_t y = 0; y < im.height(); ++y)
    for (int64_t x = 0; x < im.width(); ++x)
      for (int c = 0; c < im.channels(); ++c) n += !std::isfinite(test::get(im, x, y, c));
  return n;
}

TEST(Stability, HugeDynamicRangeStaysFinite) {
  // Float and half sources alternating 1e-30 .. 1e30 (half: its range, 6e-8 .. 65504), 16-bit
  // ones 0 and 65535: every kernel (Lanczos-3 and bicubic ring), both engines, antialiasing.
  const Projection s = make("equirect", {256, 128}), d = make("fisheye:fov=200", {96, 96});
  for (PixelType t : {PixelType::F32, PixelType::F16, PixelType::U16}) {
    Image im({256, 128}, 3, t);
    for (int64_t y = 0; y < 128; ++y)
      for (int64_t x = 0; x < 256; ++x)
        for (int c = 0; c < 3; ++c) {
          const bool high = (x + y + c) % 2;  // set() takes integers in units of their range
          const double v = t == PixelType::F32 ? std::pow(10.0, -30 + 60 * ((x * 7 + y * 13 + c) % 11) / 10.0)
                           : t == PixelType::F16 ? (high ? 65504.0 : 6e-8)
                                                 : (high ? 1.0 : 0.0);
          test::set(im, x, y, c, v);
        }
    for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3})
      for (Engine e : {Engine::Simd, Engine::Scalar, Engine::Reference}) {
        // (nearest never averages: antialiasing is refused with it, as in every front end)
        const Antialias aa = e == Engine::Reference || k == Interp::Nearest
                                 ? Antialias{}
                                 : Antialias{Antialias::Mode::Auto, 1};
        const Image out =
            test::converter(s, d, rotation_from_ypr(10, 80, 0), k, e, 2, Keep::Nothing, aa).run(im);
        EXPECT_EQ(non_finite(out), 0) << name_of(t) << " " << name_of(k) << " " << name_of(e);
      }
  }
}

TEST(Stability, TinyAndLongImagesConvert) {
  // 1x1 and 2x1 sources and targets, and a 40000x2 strip (over 32767 px) both ways.
  const std::pair<const char*, Size> forms[] = {{"equirect", {1, 1}},          {"equirect", {2, 1}},
                                                {"fisheye:fov=180", {1, 1}},   {"pinhole:hfov=90", {1, 1}},
                                                {"cubemap", {6, 1}},           {"equirect", {40000, 2}},
                                                {"cylindrical", {40000, 3}},   {"aitoff", {2, 1}}};
  for (const auto& [fs, fsize] : forms)
    for (const auto& [ts, tsize] : forms) {
      const Projection s = make(fs, fsize), d = make(ts, tsize);
      Image im(fsize, 3, PixelType::F32);
      for (size_t i = 0; i < im.byte_size() / 4; ++i) reinterpret_cast<float*>(im.data())[i] = 0.25f + 0.5f * (i % 2);
      for (Interp k : {Interp::Nearest, Interp::Lanczos3}) {
        const Antialias aa =
            k == Interp::Nearest ? Antialias{} : Antialias{Antialias::Mode::Auto, 1};
        const Image out = test::converter(s, d, rotation_from_ypr(30, 20, 10), k, Engine::Simd, 2,
                                          Keep::Nothing, aa)
                              .run(im);
        ASSERT_EQ(out.size(), tsize);
        EXPECT_EQ(non_finite(out), 0) << fs << " -> " << ts;
        // Values stay within the source's range (0.25 .. 0.75) up to the kernels' ringing.
        for (int64_t y = 0; y < out.height(); ++y)
          for (int64_t x = 0; x < out.width(); ++x) EXPECT_LE(std::fabs(test::get(out, x, y, 0)), 1.0) << fs << " -> " << ts;
      }
    }
}

}  // namespace
}  // namespace panoproj
