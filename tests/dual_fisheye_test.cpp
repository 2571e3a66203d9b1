// Dual fisheye (dual_fisheye.hpp, dual_blend.hpp):
//  - both layouts, turned lenses: pixel -> ray -> pixel round trips, each ray to the lens with the
//    larger margin;
//  - the blend's weights (node margins interpolated) within 1e-3 of the exact ones, and the tiles
//    given to one lens alone need no other;
//  - the blend equals w0 A + (1 - w0) B on flat lenses (float, exact weights per pixel);
//  - a lens's taps never read the other half;
//  - the simd engine against the scalar one; feather=0 against the reference engine's hard cut;
//  - Jordan Pond -> two 200-degree lenses side by side -> equirect: PSNR overall and in the
//    overlap band; the blended band within 1 dB of the band rebuilt from either lens alone;
//  - bad specs and frames: one-line errors.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstring>

#include "sampling/dual_blend.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

const Eigen::Matrix3d kIdentity = Eigen::Matrix3d::Identity();

DualFisheye dual(const std::string& spec, Size size) {
  return std::get<DualFisheye>(make_projection(parse_spec(spec), size));
}

TEST(DualFisheye, RoundTripsThroughTheLensWithTheLargerMargin) {
  for (const char* spec : {"dual-fisheye:fov=200", "dual-fisheye:fov=190,fov2=210,layout=top-bottom,model=equisolid",
                           "dual-fisheye:fov=200,yaw=10,pitch=-5,roll=30,yaw2=185,pitch2=4,roll2=-90,radius=400,cx2=1540"}) {
    const Size size = parse_spec(spec).choice("layout") == "top-bottom" ? Size{1000, 2000} : Size{2000, 1000};
    const DualFisheye d = dual(spec, size);
    double worst = 0;
    int64_t rays = 0;
    for (int64_t y = 0; y < size.height; y += 7)
      for (int64_t x = 0; x < size.width; x += 7) {
        Ray r;
        if (!d.to_ray(x + 0.5, y + 0.5, r)) continue;
        ++rays;
        const int k = d.lens_at(x + 0.5, y + 0.5);
        double bx, by;
        // The lens alone always takes its own ray back; both lenses take it back through the one
        // that sees it better.
        ASSERT_TRUE(d.lens(k).to_pixel(d.rotation(k).transpose() * r, bx, by)) << spec << " at " << x << "," << y;
        worst = std::max(worst, std::hypot(bx - (x + 0.5), by - (y + 0.5)));
        ASSERT_TRUE(d.to_pixel(r, bx, by));
        const int seen = d.margin(0, r) >= d.margin(1, r) ? 0 : 1;
        EXPECT_EQ(d.lens_at(bx, by), seen);
      }
    std::printf("[dual] %s: %lld rays, round trip <= %.2e px\n", spec, static_cast<long long>(rays), worst);
    EXPECT_GT(rays, 20000);
    EXPECT_LT(worst, 1e-9);
  }
}

TEST(DualFisheye, InterpolatedWeightsMatchTheExactOnes) {
  const DualFisheye d = dual("dual-fisheye:fov=200,yaw2=178,pitch2=3", {2048, 1024});
  for (const char* target : {"equirect", "pinhole:hfov=120", "fisheye:fov=250"}) {
    const Projection t = make_projection(parse_spec(target), {1024, 512});
    const Eigen::Matrix3d rot = rotation_from_ypr(80, 20, 10);
    double worst = 0;
    int64_t blended = 0, alone = 0;
    std::vector<float> w;
    for (int64_t y0 = 0; y0 < 512; y0 += kTile)
      for (int64_t x0 = 0; x0 < 1024; x0 += kTile) {
        const PixelRect rect{x0, y0, std::min<int64_t>(x0 + kTile, 1024),
                             std::min<int64_t>(y0 + kTile, 512)};
        const int side = dual_weights(d, t, rot, rect, w);
        (side < 0 ? blended : alone) += 1;
        for (int64_t j = 0; j < rect.height(); ++j)
          for (int64_t i = 0; i < rect.width(); ++i) {
            Ray r;
            if (!to_ray(t, x0 + i + 0.5, y0 + j + 0.5, r)) continue;
            r = rot * r;
            const double exact = d.weight0(d.margin(0, r), d.margin(1, r));
            const double got = side < 0    ? w[static_cast<size_t>(j * rect.width() + i)]
                               : side == 0 ? 1.0
                                           : 0.0;
            worst = std::max(worst, std::fabs(got - exact));
          }
      }
    std::printf("[dual] weights over %s: %lld tiles blended, %lld from one lens; worst weight error %.2e\n", target,
                static_cast<long long>(blended), static_cast<long long>(alone), worst);
    EXPECT_GT(blended, 0);
    EXPECT_GT(alone, 0);
    EXPECT_LT(worst, 1e-3);
  }
}

// Lens 0's half 0.25 and lens 1's 0.75 (float, one channel): any output pixel both see is
// w0 0.25 + (1 - w0) 0.75, with w0 from the exact margins.
TEST(DualFisheye, BlendIsTheWeightedMeanOfTheLenses) {
  for (const char* spec : {"dual-fisheye:fov=200", "dual-fisheye:fov=220,feather=8", "dual-fisheye:fov=200,feather=0"}) {
    const DualFisheye d = dual(spec, {1024, 512});
    Image src({1024, 512}, 1, PixelType::F32);
    for (int64_t y = 0; y < 512; ++y)
      for (int64_t x = 0; x < 1024; ++x) *reinterpret_cast<float*>(src.pixel(x, y)) = x < 512 ? 0.25f : 0.75f;
    const Projection t = make_projection(parse_spec("equirect"), {720, 360});
    for (Engine e : {Engine::Simd, Engine::Scalar}) {
      const Image out = test::converter(d, t, kIdentity, Interp::Bilinear, e, 2).run(src);
      double worst = 0;
      for (int64_t y = 0; y < 360; ++y)
        for (int64_t x = 0; x < 720; ++x) {
          Ray r;
          ASSERT_TRUE(to_ray(t, x + 0.5, y + 0.5, r));
          const double m0 = d.margin(0, r), m1 = d.margin(1, r);
          // (Within half a degree of a rim bilinear taps reach the black outside it... here not:
          // the halves are flat to their edges.)
          const double w0 = d.weight0(m0, m1);
          worst = std::max(worst, std::fabs(*reinterpret_cast<const float*>(out.pixel(x, y)) - (0.25 * w0 + 0.75 * (1 - w0))));
        }
      std::printf("[dual] %s, %s engine: blend error <= %.2e\n", spec, name_of(e), worst);
      EXPECT_LT(worst, d.feather() > 0 ? 2e-3 : 1e-6) << spec;
    }
  }
}

// 180-degree lenses meet at their rims, where bicubic taps reach past the middle column: they
// must clamp to the lens's own half (0) and never read the other's (255).
TEST(DualFisheye, TapsStayInTheirLensHalf) {
  const DualFisheye d = dual("dual-fisheye:fov=180", {512, 256});
  Image src({512, 256}, 3, PixelType::U8);
  for (int64_t y = 0; y < 256; ++y)
    for (int64_t x = 256; x < 512; ++x) std::memset(src.pixel(x, y), 255, 3);
  const Projection t = make_projection(parse_spec("equirect"), {1440, 720});
  for (Engine e : {Engine::Simd, Engine::Scalar, Engine::Reference}) {
    const Image out = test::converter(d, t, kIdentity, Interp::Bicubic, e, 2).run(src);
    int64_t wrong = 0, lens0 = 0;
    for (int64_t y = 0; y < 720; ++y)
      for (int64_t x = 0; x < 1440; ++x) {
        Ray r;
        double sx, sy;
        if (!to_ray(t, x + 0.5, y + 0.5, r) || !d.to_pixel(r, sx, sy)) continue;
        const bool from0 = d.lens_at(sx, sy) == 0;
        lens0 += from0;
        wrong += out.pixel(x, y)[0] != (from0 ? 0 : 255);
      }
    EXPECT_GT(lens0, 1440 * 720 / 3);
    EXPECT_EQ(wrong, 0) << name_of(e);
  }
}

TEST(DualFisheye, SimdMatchesScalarBothWays) {
  const Image pano = test::render(make_projection(parse_spec("equirect"), {1024, 512}), test::smooth_scene(), PixelType::U8);
  const Projection e = make_projection(parse_spec("equirect"), {1024, 512});
  const DualFisheye d = dual("dual-fisheye:fov=200,roll2=90,pitch=3", {1026, 514});
  const Eigen::Matrix3d rot = rotation_from_ypr(30, -10, 5);
  for (Interp k : {Interp::Bilinear, Interp::Bicubic}) {
    const Image fish = test::converter(e, d, rot, k, Engine::Simd, 2).run(pano);
    const Image fish_scalar = test::converter(e, d, rot, k, Engine::Scalar, 2).run(pano);
    const Image back = test::converter(d, e, rot.transpose(), k, Engine::Simd, 2).run(fish);
    const Image back_scalar =
        test::converter(d, e, rot.transpose(), k, Engine::Scalar, 2).run(fish);
    for (const auto& [a, b] : {std::pair{&fish, &fish_scalar}, std::pair{&back, &back_scalar}}) {
      int worst = 0;
      for (size_t i = 0; i < a->byte_size(); ++i) worst = std::max(worst, std::abs(a->data()[i] - b->data()[i]));
      EXPECT_LE(worst, 1) << name_of(k);
    }
    EXPECT_GT(test::psnr(back, pano), 40.0) << name_of(k);
  }
}

TEST(DualFisheye, HardCutMatchesTheReferenceEngine) {
  const Image pano = test::render(make_projection(parse_spec("equirect"), {1024, 512}), test::smooth_scene(), PixelType::U8);
  const Projection e = make_projection(parse_spec("equirect"), {1024, 512});
  const Projection d = make_projection(parse_spec("dual-fisheye:fov=200,feather=0"), {1024, 512});
  const Image fish =
      test::converter(e, d, kIdentity, Interp::Bilinear, Engine::Reference, 2).run(pano);
  const Image ours = test::converter(d, e, kIdentity, Interp::Bilinear, Engine::Simd, 2).run(fish);
  const Image ref =
      test::converter(d, e, kIdentity, Interp::Bilinear, Engine::Reference, 2).run(fish);
  int64_t differ = 0;
  for (size_t i = 0; i < ours.byte_size(); ++i) differ += std::abs(ours.data()[i] - ref.data()[i]) > 1;
  EXPECT_EQ(differ, 0);
}

// Jordan Pond -> dual fisheye (two 200-degree lenses, 2048x2048 each, side
// by side) -> equirect 4096x2048, bicubic; PSNR against the photo overall and in the overlap band
// (80 to 100 degrees from lens 0's axis), and the band rebuilt from each lens alone.
TEST(DualFisheye, JordanPondThroughTwoLensesAndBack) {
  const Image photo = read_image(test::samples_dir() + "/jordan_pond_4096x2048.jpg");
  const Projection e = make_projection(parse_spec("equirect"), {4096, 2048});
  const DualFisheye d = dual("dual-fisheye:fov=200", {4096, 2048});
  const Image fish = test::converter(e, d, kIdentity, Interp::Bicubic, Engine::Simd, 2).run(photo);
  auto in_band = [&](int64_t x, int64_t y) {
    Ray r;
    to_ray(e, x + 0.5, y + 0.5, r);
    return d.margin(0, r) >= 0 && d.margin(1, r) >= 0;
  };
  const auto t0 = std::chrono::steady_clock::now();
  const Image back = test::converter(d, e, kIdentity, Interp::Bicubic, Engine::Simd, 2).run(fish);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  // Each lens alone: a fisheye on the whole frame, turned by R_k^T.
  auto alone = [&](int k) {
    return test::converter(d.lens(k), e, d.rotation(k).transpose(), Interp::Bicubic, Engine::Simd,
                           2)
        .run(fish);
  };
  const Image lens0 = alone(0), lens1 = alone(1);
  const double all = test::psnr(back, photo), band = test::psnr(back, photo, in_band);
  const double band0 = test::psnr(lens0, photo, in_band), band1 = test::psnr(lens1, photo, in_band);
  std::printf("[dual] Jordan Pond -> 2 x 200-deg lenses 2048^2 -> equirect 4096x2048, bicubic: %.2f dB overall, overlap "
              "band %.2f dB blended, %.2f dB lens 0 alone, %.2f dB lens 1 alone (back conversion %.0f ms)\n",
              all, band, band0, band1, ms);
  EXPECT_GT(all, 29.0);
  EXPECT_GE(band, std::min(band0, band1) - 1.0);
  EXPECT_LE(std::fabs(band - band0), 1.0);
  EXPECT_LE(std::fabs(band - band1), 1.0);
}

TEST(DualFisheye, BadSpecsAndFramesAreOneLineErrors) {
  auto message = [](const std::string& spec, Size size) {
    try {
      make_projection(parse_spec(spec), size);
    } catch (const Error& err) {
      return std::string(err.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("dual-fisheye", {1001, 500}).find("even width"), std::string::npos);
  EXPECT_NE(message("dual-fisheye:layout=top-bottom", {500, 1001}).find("even height"), std::string::npos);
  EXPECT_NE(message("dual-fisheye:radius=300", {1000, 500}).find("crosses the middle x=500"), std::string::npos);
  EXPECT_NE(message("dual-fisheye:cx2=700", {1000, 500}).find("lens 1's image circle (cx2=700"), std::string::npos);
  EXPECT_NE(message("dual-fisheye:fov=200,feather=30", {1000, 500}).find("wider than the lenses' overlap of 20"),
            std::string::npos);
  EXPECT_NE(message("dual-fisheye:fov=170,feather=1", {1000, 500}).find("or wider lenses"), std::string::npos);
  EXPECT_NE(message("dual-fisheye:model=orthographic,fov=180,fov2=200", {1000, 500}).find("fov2=200 is too wide"), std::string::npos);
  const Projection e = make_projection(parse_spec("equirect"), {64, 32});
  const Projection d = make_projection(parse_spec("dual-fisheye:fov=200"), {64, 32});
  EXPECT_THROW(test::converter(d, e, kIdentity, Interp::Bilinear, Engine::Reference, 1), Error);
  EXPECT_THROW(test::converter(d, e, kIdentity, Interp::Bilinear, Engine::Simd, 1, Keep::Nothing,
                               parse_antialias("mip")),
               Error);
}

}  // namespace
}  // namespace panoproj

namespace panoproj {
namespace {

TEST(DualFisheye, KeptLensMapsAndTapsGiveTheSameBytes) {
  // Each lens keeps its maps (sited chroma planes: no fused tiles) or its planned taps, and each
  // tile its blend of the lenses; later runs replay them, as the frames of a video do, to the
  // bytes of a converter that keeps nothing.
  // (Tiles inside one lens and tiles across both.)
  const Projection d = make_projection(parse_spec("dual-fisheye:fov=200"), {512, 256});
  const Projection e = make_projection(parse_spec("equirect"), {640, 320});
  const Image rgb = test::render(d, test::band_limited_scene(0.1, 512), PixelType::U8);
  for (const Siting siting : {Siting{}, Siting{-0.25, 0, -0.25, 0}})
    for (const Antialias aa : {Antialias{}, parse_antialias("auto")}) {
      SCOPED_TRACE(std::to_string(siting.source_x) + " " + name_of(aa));
      ConvertOptions o;
      o.interp = Interp::Bicubic, o.antialias = aa;
      const ConversionGeometry g{d, e, rotation_from_ypr(10, 5, 0), {}, siting};
      const Converter kept(g, o, Keep::MapsAndTaps), lean(g, o, Keep::Nothing);
      const Image want = lean.run(rgb);
      for (int run = 0; run < 3; ++run) {
        EngineStats st;
        EXPECT_TRUE(kept.run(rgb, &st) == want) << "run " << run;
        if (run > 0 && !siting.any()) {
          EXPECT_GT(st.replayed_tiles, 0);
        }
      }
    }
}

}  // namespace
}  // namespace panoproj

namespace panoproj {
namespace {

TEST(DualFisheye, OneChannelBlendsAsEachChannelOfThree) {
  // The one-channel integer blend (a video's planes) has a loop of its own: each sample is
  // w a + (1 - w) b rounded, as each channel of a three-channel blend is, the lenses' own
  // samples where w is 0 or 1.
  const PixelRect rect{0, 0, 37, 5};
  const int64_t n = rect.width() * rect.height();
  std::vector<float> w(static_cast<size_t>(n));
  std::vector<uint16_t> a(static_cast<size_t>(n)), b(static_cast<size_t>(n));
  uint32_t seed = 7;
  auto next = [&] { return seed = seed * 1664525u + 1013904223u, seed >> 8; };
  for (int64_t i = 0; i < n; ++i) {
    const uint32_t k = next() % 8;
    w[static_cast<size_t>(i)] = k == 0   ? 0.0f
                                : k == 1 ? 1.0f
                                         : static_cast<float>(next() % 65536) / 65536.0f;
    a[static_cast<size_t>(i)] = static_cast<uint16_t>(next() % 65536);
    b[static_cast<size_t>(i)] = static_cast<uint16_t>(next() % 65536);
  }
  for (const PixelType type : {PixelType::U8, PixelType::U16}) {
    SCOPED_TRACE(name_of(type));
    const int bytes = type == PixelType::U8 ? 1 : 2;
    auto fill = [&](const std::vector<uint16_t>& v, int nc) {
      std::vector<unsigned char> im(static_cast<size_t>(n * nc * bytes));
      for (int64_t i = 0; i < n; ++i)
        for (int c = 0; c < nc; ++c) {
          const uint16_t s = bytes == 1 ? static_cast<uint16_t>(v[static_cast<size_t>(i)] >> 8)
                                        : v[static_cast<size_t>(i)];
          std::memcpy(im.data() + (i * nc + c) * bytes, &s, static_cast<size_t>(bytes));
        }
      return im;
    };
    std::vector<unsigned char> a1 = fill(a, 1), b1 = fill(b, 1), a3 = fill(a, 3), b3 = fill(b, 3);
    blend_lenses(w.data(), rect, type, 1, -1, a1.data(), rect.width() * bytes, b1.data(),
                 rect.width() * bytes);
    blend_lenses(w.data(), rect, type, 3, -1, a3.data(), 3 * rect.width() * bytes, b3.data(),
                 3 * rect.width() * bytes);
    const std::vector<unsigned char> b0 = fill(b, 1), a0 = fill(a, 1);
    for (int64_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        uint16_t one = 0, three = 0;
        std::memcpy(&one, a1.data() + i * bytes, static_cast<size_t>(bytes));
        std::memcpy(&three, a3.data() + (i * 3 + c) * bytes, static_cast<size_t>(bytes));
        ASSERT_EQ(one, three) << "sample " << i << " channel " << c << " w "
                              << w[static_cast<size_t>(i)];
        const float wi = w[static_cast<size_t>(i)];
        if (wi == 0.0f || wi == 1.0f) {
          ASSERT_EQ(0, std::memcmp(a1.data() + i * bytes, (wi == 0.0f ? b0 : a0).data() + i * bytes,
                                   static_cast<size_t>(bytes)));
        }
      }
  }
}

}  // namespace
}  // namespace panoproj
