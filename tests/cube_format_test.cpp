// Cube formats (EAC, face order, turns, padding, FFmpeg's EAC frame) against the exact geometry
// and the reference engine; stereo frames against their mono conversions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/rotation.hpp"
#include "panoproj/spec.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

Projection make(const std::string& spec, Size size) { return make_projection(parse_spec(spec), size); }

int64_t differing(const Image& a, const Image& b) {
  int64_t n = 0;
  const size_t pb = a.pixel_bytes();
  for (size_t i = 0; i < a.byte_size(); i += pb) n += std::memcmp(a.data() + i, b.data() + i, pb) != 0;
  return n;
}

bool same_bytes(const Image& a, const Image& b) {
  return a.size() == b.size() && a.channels() == b.channels() && a.byte_size() == b.byte_size() &&
         std::memcmp(a.data(), b.data(), a.byte_size()) == 0;
}

const char* const kFormats[] = {"cubemap:layout=3x2,order=rludfb,rot=123012", "cubemap:layout=6x1,order=udfblr,rot=302103,pad=0.1",
                                "cubemap:layout=cross,pad_px=3", "cubemap:layout=eac", "cubemap:layout=eac,pad=0.05",
                                "cubemap:layout=eac,border=ffmpeg", "cubemap:layout=1x6,rot=222222"};

// The layout's frame for faces of f pixels.
Size frame_of(const std::string& spec, int64_t f) {
  const std::string l = parse_spec(spec).choice("layout");
  const auto g = Cubemap::grid(l == "3x2" ? CubeLayout::Grid3x2 : l == "eac" ? CubeLayout::Eac : l == "cross" ? CubeLayout::Cross4x3
                               : l == "1x6" ? CubeLayout::Column1x6 : CubeLayout::Row6x1);
  return {g[0] * f, g[1] * f};
}

// Nearest: the SIMD engine picks the reference engine's pixel everywhere, both directions.
TEST(CubeFormats, NearestIsBitForBitTheReferenceEngine) {
  const Projection e = make("equirect", {384, 192});
  const Image pano = test::render(e, test::band_limited_scene(0.3, 384), PixelType::U8);
  const Eigen::Matrix3d turn = rotation_from_ypr(17, -23, 8);
  for (const char* spec : kFormats) {
    const Projection cube = make(spec, frame_of(spec, 96));
    const Image a = test::fast_remap(pano, e, cube, turn, Interp::Nearest, Engine::Simd, 2);
    const Image b = test::fast_remap(pano, e, cube, turn, Interp::Nearest, Engine::Reference, 2);
    EXPECT_TRUE(same_bytes(a, b)) << "equirect -> " << spec << ": " << differing(a, b) << " of " << a.width() * a.height();
    const Image faces = test::render(cube, test::band_limited_scene(0.3, 384), PixelType::U8);
    const Projection back = make("equirect", {512, 256});
    const Image c = test::fast_remap(faces, cube, back, turn, Interp::Nearest, Engine::Simd, 2);
    const Image d = test::fast_remap(faces, cube, back, turn, Interp::Nearest, Engine::Reference, 2);
    EXPECT_TRUE(same_bytes(c, d)) << spec << " -> equirect: " << differing(c, d) << " of " << c.width() * c.height();
  }
}

// rot=1 shows the face turned a quarter clockwise in its slot; order= puts face order[k] in slot k.
TEST(CubeFormats, OrderAndTurnsMoveWholeFaces) {
  const int64_t f = 32;
  const auto scene = test::band_limited_scene(0.2, 256);
  const Image plain = test::render(make("cubemap", {6 * f, f}), scene, PixelType::F32);
  const std::string order = "udfblr";
  for (int q = 0; q < 4; ++q) {
    const std::string spec = "cubemap:order=" + order + ",rot=" + std::string(6, static_cast<char>('0' + q));
    const Image turned = test::render(make(spec, {6 * f, f}), scene, PixelType::F32);
    double worst = 0;
    for (int k = 0; k < 6; ++k) {
      const int64_t face = static_cast<int64_t>(std::string("frblud").find(order[static_cast<size_t>(k)]));
      for (int64_t y = 0; y < f; ++y)
        for (int64_t x = 0; x < f; ++x) {
          // Turned q times clockwise: cell (x, y) shows the face's pixel turned back q times.
          int64_t u = x, v = y;
          for (int i = 0; i < q; ++i) std::tie(u, v) = std::pair<int64_t, int64_t>(v, f - 1 - u);
          for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::fabs(test::get(turned, k * f + x, y, c) - test::get(plain, face * f + u, v, c)));
        }
    }
    EXPECT_LT(worst, 1e-6) << spec;
  }
}

// pad: a cell's edge is atan(1 / (1 - pad)) off its face's axis; EAC: equal angles per pixel.
TEST(CubeFormats, PadAndEacSpacingAreExact) {
  for (double pad : {0.0, 0.05, 0.25, 0.4}) {
    const Projection p = make("cubemap:pad=" + std::to_string(pad), {6 * 100, 100});
    Ray d;
    ASSERT_TRUE(to_ray(p, 0.0, 50.0, d));
    EXPECT_NEAR(std::atan2(std::fabs(d.x()), d.z()), std::atan(1 / (1 - pad)), 1e-12) << pad;
  }
  for (const char* spec : {"cubemap:layout=eac", "cubemap:layout=eac,rot=321012", "cubemap:layout=3x2"}) {
    const Projection p = make(spec, {3 * 64, 2 * 64});
    double lo = 1e9, hi = 0;
    for (int64_t cell = 0; cell < 6; ++cell)
      for (int64_t x = 0; x + 1 < 64; ++x) {
        const double cx = static_cast<double>(cell % 3 * 64), cy = static_cast<double>(cell / 3 * 64) + 32;
        Ray a, b;
        ASSERT_TRUE(to_ray(p, cx + x + 0.5, cy, a) && to_ray(p, cx + x + 1.5, cy, b));
        lo = std::min(lo, test::angle(a, b)), hi = std::max(hi, test::angle(a, b));
      }
    const bool eac = std::string(spec).find("eac") != std::string::npos;
    if (eac) EXPECT_NEAR(hi / lo, 1.0, 1e-9) << spec;  // along the centre line: (pi/2) / 64 each
    else EXPECT_GT(hi / lo, 1.9) << spec;               // tangents: twice the angle at the centre
  }
}

// A smooth scene read from every format across its face edges: no seam (a wrong neighbour or
// turn there errs by a large part of the scene's range).
TEST(CubeFormats, TapsAcrossFaceEdgesAreSeamFree) {
  const auto scene = test::smooth_scene();
  const Projection e = make("equirect", {512, 256});
  const Image truth = test::render(e, scene, PixelType::F32);
  for (const char* spec : kFormats) {
    const Projection cube = make(spec, frame_of(spec, 64));
    const Image faces = test::render(cube, scene, PixelType::F32);
    for (Interp k : {Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3}) {
      const Image out = test::fast_remap(faces, cube, e, Eigen::Matrix3d::Identity(), k, Engine::Simd, 2);
      double worst = 0;
      for (int64_t y = 0; y < 256; ++y)
        for (int64_t x = 0; x < 512; ++x)
          for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(test::get(out, x, y, c) - test::get(truth, x, y, c)));
      // The scene is linear in the ray: what is left is its curvature over a tap's reach.
      EXPECT_LT(worst, 2e-3) << spec << " " << name_of(k);
    }
  }
}

// e -> cube -> e at equal pixel counts: EAC's even sampling keeps more of a detailed scene.
TEST(CubeFormats, EacRoundTripIsAtLeastThePlainCubes) {
  const Projection e = make("equirect", {1024, 512});
  const Image pano = test::render(e, test::band_limited_scene(0.3, 1024), PixelType::F32);
  double psnr[2];
  int i = 0;
  for (const char* spec : {"cubemap:layout=3x2", "cubemap:layout=eac"}) {
    const Projection cube = make(spec, {3 * 256, 2 * 256});
    const Image faces = test::fast_remap(pano, e, cube, Eigen::Matrix3d::Identity(), Interp::Bicubic, Engine::Simd, 2);
    const Image back = test::fast_remap(faces, cube, e, Eigen::Matrix3d::Identity(), Interp::Bicubic, Engine::Simd, 2);
    psnr[i++] = test::psnr(back, pano);
  }
  std::printf("[cube_format] e 1024x512 -> 3x2 faces of 256 -> e, bicubic: plain cube %.2f dB, eac %.2f dB\n", psnr[0],
              psnr[1]);
  EXPECT_GE(psnr[1], psnr[0]);
}

// Stereo: an image of two eyes, each eye a frame of its own content.
Image stereo_frame_of(const Image& left, const Image& right, StereoLayout l) {
  const Size e = left.size();
  Image both(stereo_frame(e, l), left.channels(), left.type(), left.alpha_channel());
  for (int k = 0; k < 2; ++k) {
    const Image& eye = k == 0 ? left : right;
    const auto o = stereo_origin(e, l, k);
    for (int64_t y = 0; y < e.height; ++y) std::memcpy(both.pixel(o[0], o[1] + y), eye.row(y), eye.row_bytes());
  }
  return both;
}

Image eye_part(const Image& both, Size e, StereoLayout l, int k) {
  Image eye(e, both.channels(), both.type(), both.alpha_channel());
  const auto o = stereo_origin(e, l, k);
  for (int64_t y = 0; y < e.height; ++y) std::memcpy(eye.row(y), both.pixel(o[0], o[1] + y), eye.row_bytes());
  return eye;
}

Image convert_with(const Image& src, const std::string& from, const std::string& to, Interp k, Antialias aa,
                   std::optional<Size> size = std::nullopt) {
  ConvertOptions o;
  o.interp = k;
  o.antialias = aa;
  o.threads = 2;
  o.size = size;
  o.yaw = 30, o.pitch = -10;
  return convert(src, parse_spec(from), parse_spec(to), o);
}

const Interp kKernels[] = {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3};
Antialias aa_for(Interp k) { return k == Interp::Nearest ? Antialias{} : Antialias{Antialias::Mode::Auto, 1}; }

TEST(Stereo, EachEyeIsItsMonoConversionBitForBit) {
  const Projection e = make("equirect", {512, 256});
  const Image left = test::render(e, test::band_limited_scene(0.3, 512, 1), PixelType::U8);
  const Image right = test::render(e, test::band_limited_scene(0.3, 512, 2), PixelType::U8);
  for (StereoLayout from : {StereoLayout::TopBottom, StereoLayout::SideBySide})
    for (StereoLayout to : {StereoLayout::TopBottom, StereoLayout::SideBySide}) {
      const std::string fs = from == StereoLayout::TopBottom ? "tb" : "sbs", ts = to == StereoLayout::TopBottom ? "tb" : "sbs";
      const Image both = stereo_frame_of(left, right, from);
      for (Interp k : kKernels) {
        const Image out = convert_with(both, "equirect:stereo=" + fs, "cubemap:layout=eac,stereo=" + ts, k, aa_for(k));
        const Image l = convert_with(left, "equirect", "cubemap:layout=eac", k, aa_for(k));
        const Image r = convert_with(right, "equirect", "cubemap:layout=eac", k, aa_for(k));
        EXPECT_TRUE(same_bytes(out, stereo_frame_of(l, r, to))) << fs << " -> " << ts << " " << name_of(k);
        // One eye to a mono target; a mono source to both eyes.
        const Image r_only = convert_with(both, "equirect:stereo=" + fs + ",eye=right", "cubemap:layout=eac", k, aa_for(k));
        EXPECT_TRUE(same_bytes(r_only, r)) << fs << " right eye " << name_of(k);
        const Image twice = convert_with(left, "equirect", "cubemap:layout=eac,stereo=" + ts, k, aa_for(k));
        EXPECT_TRUE(same_bytes(twice, stereo_frame_of(l, l, to))) << "mono -> " << ts << " " << name_of(k);
      }
    }
}

// Two constant eyes: no output pixel takes anything from the other eye, whatever the kernel and
// antialiasing (auto, supersampling, mip all reach beyond the sample).
TEST(Stereo, ConstantEyesNeverMix) {
  const Size eye{256, 128};
  Image left(eye, 3, PixelType::U8), right(eye, 3, PixelType::U8);
  std::memset(left.data(), 30, left.byte_size());
  std::memset(right.data(), 220, right.byte_size());
  for (StereoLayout l : {StereoLayout::TopBottom, StereoLayout::SideBySide}) {
    const std::string s = l == StereoLayout::TopBottom ? "tb" : "sbs";
    const Image both = stereo_frame_of(left, right, l);
    for (Interp k : kKernels)
      for (Antialias aa : {Antialias{}, Antialias{Antialias::Mode::Auto, 1}, Antialias{Antialias::Mode::Supersample, 3},
                           Antialias{Antialias::Mode::Mip, 1}}) {
        if (k == Interp::Nearest && aa.mode != Antialias::Mode::Off) continue;
        // A 16x shrink: every footprint reaches far past the sample.
        const Image out = convert_with(both, "equirect:stereo=" + s, "pinhole:hfov=150,stereo=" + s, k, aa,
                                       stereo_frame({24, 16}, l));
        for (int e = 0; e < 2; ++e) {
          const Image part = eye_part(out, {24, 16}, l, e);
          for (size_t i = 0; i < part.byte_size(); ++i)
            ASSERT_EQ(part.data()[i], e == 0 ? 30 : 220) << s << " eye " << e << " " << name_of(k) << " " << name_of(aa);
        }
      }
  }
}

TEST(Stereo, FramesThatDoNotSplitAreRefused) {
  const Image odd({512, 257}, 3, PixelType::U8);
  try {
    convert_with(odd, "equirect:stereo=tb", "equirect", Interp::Bilinear, {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("512x257 does not split into two eyes top and bottom"), std::string::npos) << e.what();
  }
  EXPECT_THROW(convert_with(odd, "equirect", "equirect:stereo=sbs", Interp::Bilinear, {}, Size{511, 256}), Error);
  EXPECT_THROW(convert_with(odd, "equirect:eye=right", "equirect", Interp::Bilinear, {}), Error);
}

}  // namespace
}  // namespace panoproj
