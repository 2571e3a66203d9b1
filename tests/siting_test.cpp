// Sited planes (a video's chroma, projection.hpp's Siting): each target sample comes from the
// source position of its sited place, read at that position less the source's offset, as the
// reference sampler reads the exact map there; a plane taken as centred instead is off. Sited
// tiles take the fused geometry where centred ones do, on every SIMD target.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "geometry/source_taps.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/rotation.hpp"
#include "sampling/reference_sampler.hpp"
#include "sampling/simd_sampler.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

Projection make(const char* spec, Size size) {
  return make_projection(parse_spec(spec), size);
}

// The reference: the exact map at the sited positions, sampled by the reference sampler.
Image reference(const Image& src, const ConversionGeometry& g, Interp interp) {
  const Size ts = size_of(g.target);
  Image out(ts, 1, src.type());
  const SourceTaps taps(g.source);
  for (int64_t y = 0; y < ts.height; ++y)
    for (int64_t x = 0; x < ts.width; ++x) {
      double sx = 0, sy = 0;
      const uint8_t ok = source_pixel(g.source, g.target, g.rotation,
                                      static_cast<double>(x) + 0.5 + g.siting.target_x,
                                      static_cast<double>(y) + 0.5 + g.siting.target_y, sx, sy);
      sx -= g.siting.source_x, sy -= g.siting.source_y;
      sample_reference(src, taps, interp, &sx, &sy, &ok, 1, out.pixel(x, y));
    }
  return out;
}

// The scene's first channel as a one-channel plane (16-bit, or 8-bit as a video's).
Image plane(const Projection& p, double cycles_per_px, PixelType type = PixelType::U16) {
  const Image rgb =
      test::render(p, test::band_limited_scene(cycles_per_px, size_of(p).width), type);
  Image out(rgb.size(), 1, type);
  for (int64_t y = 0; y < rgb.height(); ++y)
    for (int64_t x = 0; x < rgb.width(); ++x)
      std::memcpy(out.pixel(x, y), rgb.pixel(x, y), rgb.pixel_bytes() / 3);
  return out;
}

double most_difference(const Image& a, const Image& b) {
  double most = 0;
  for (int64_t y = 0; y < a.height(); ++y)
    for (int64_t x = 0; x < a.width(); ++x)
      most = std::max(most, std::fabs(test::get(a, x, y, 0) - test::get(b, x, y, 0)));
  return most;
}

struct SitingCase {
  const char *from, *to;
  Size source, target;
  Siting siting;
  Engine engine;
};

class SitedPlanes : public ::testing::TestWithParam<SitingCase> {};

TEST_P(SitedPlanes, MatchTheReferenceMapAtTheSitedPositions) {
  const SitingCase& c = GetParam();
  const Projection sp = make(c.from, c.source);
  const Image src = plane(sp, 0.15);
  ConversionGeometry g{sp, make(c.to, c.target), rotation_from_ypr(20, -10, 5), {}, c.siting};
  ConvertOptions o;
  o.interp = Interp::Bicubic, o.engine = c.engine, o.antialias = Antialias{};
  const Image out = Converter(g, o, Keep::Maps).run(src);
  const Image truth = reference(src, g, Interp::Bicubic);
  // 1/1024 px map tolerance on a 16-bit band-limited scene: a few LSB.
  EXPECT_LE(most_difference(out, truth), 24.0);
  // The deliberate mistake: the planes taken as centred.
  ConversionGeometry centred = g;
  centred.siting = {};
  EXPECT_GT(most_difference(out, reference(src, centred, Interp::Bicubic)), 200.0);
}

INSTANTIATE_TEST_SUITE_P(Cases, SitedPlanes,
                         ::testing::Values(
                             // H.264's 4:2:0 (left): a quarter chroma pixel left on both sides.
                             SitingCase{"equirect",
                                        "cubemap:layout=3x2",
                                        {256, 128},
                                        {192, 128},
                                        {-0.25, 0, -0.25, 0},
                                        Engine::Simd},
                             SitingCase{"equirect",
                                        "fisheye:fov=200",
                                        {256, 128},
                                        {96, 96},
                                        {-0.25, 0, -0.25, 0},
                                        Engine::Scalar},
                             // Top-left siting, and a source and target sited apart.
                             SitingCase{"equirect",
                                        "pinhole:hfov=90",
                                        {256, 128},
                                        {80, 60},
                                        {-0.25, -0.25, 0, 0.25},
                                        Engine::Simd},
                             SitingCase{"cubemap:layout=3x2",
                                        "equirect",
                                        {192, 128},
                                        {256, 128},
                                        {-0.25, 0, -0.25, 0},
                                        Engine::Simd}));

class SitedSubPixels : public ::testing::TestWithParam<double> {};
TEST_P(SitedSubPixels, SitAsTheirPixel) {
  // Supersampling's sub-pixels sit around the sited position: their mean matches a 4x4 box of
  // reference samples there. (Not in the first column: sub-pixels a sited offset puts outside the
  // target's frame have no source, where the reference's equirect ray wraps.)
  const Projection sp = make("equirect", {512, 256});
  const Image src = plane(sp, 0.1);
  const Siting siting{GetParam(), 0, GetParam(), 0};
  ConversionGeometry g{sp, make("equirect", {128, 64}), rotation_from_ypr(10, 0, 0), {}, siting};
  ConvertOptions o;
  o.interp = Interp::Bilinear, o.engine = Engine::Simd, o.antialias = parse_antialias("4");
  const Image out = Converter(g, o).run(src);
  ConversionGeometry fine = g;
  fine.target = make("equirect", {512, 256});
  fine.siting = siting.on_sub_target(4);
  const Image samples = reference(src, fine, Interp::Bilinear);
  double most = 0;
  for (int64_t y = 0; y < 64; ++y)
    for (int64_t x = 1; x < 128; ++x) {
      double sum = 0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) sum += test::get(samples, 4 * x + i, 4 * y + j, 0);
      most = std::max(most, std::fabs(sum / 16 - test::get(out, x, y, 0)));
    }
  EXPECT_LE(most, 24.0) << "siting " << siting.target_x;
}

INSTANTIATE_TEST_SUITE_P(Offsets, SitedSubPixels, ::testing::Values(0.0, -0.25));

// Video's chroma: 8-bit planes, their taps kept (planned on the first frame, replayed after),
// fetched by loads and by gathers.
TEST(SitedPlanes, TakeTheFusedGeometryAndMatchTheReferenceOnEveryTarget) {
  struct Case {
    const char *from, *to;
    Size source, target;
    Siting siting;
  };
  const Case cases[] = {
      {"equirect", "cubemap:layout=3x2", {256, 128}, {192, 128}, {-0.25, 0, -0.25, 0}},
      {"equirect", "cubemap:layout=eac", {256, 128}, {192, 128}, {-0.25, 0, -0.25, 0}},
      {"equirect", "pinhole:hfov=90", {256, 128}, {96, 54}, {-0.25, -0.25, 0, 0.25}},
      {"dual-fisheye:fov=200", "equirect", {256, 128}, {256, 128}, {-0.25, 0, -0.25, 0}},
      {"equirect", "fisheye:fov=200", {256, 128}, {96, 96}, {-0.25, 0, -0.25, 0}},
  };
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    for (const Case& c : cases) {
      SCOPED_TRACE(std::string(c.from) + " -> " + c.to);
      const Projection sp = make(c.from, c.source);
      const Image src = plane(sp, 0.15, PixelType::U8);
      const ConversionGeometry g{
          sp, make(c.to, c.target), rotation_from_ypr(20, -10, 5), {}, c.siting};
      ConvertOptions o;
      o.interp = Interp::Bicubic, o.engine = Engine::Simd, o.antialias = Antialias{};
      const Converter kept(g, o, Keep::MapsAndTaps);
      EngineStats planned, replayed;
      set_simd_gray_fetch(0);  // taps by loads, then (the replay) by gathers: the same bytes
      const Image first = kept.run(src, &planned);
      set_simd_gray_fetch(1);
      const Image again = kept.run(src, &replayed);
      set_simd_gray_fetch(-1);
      EXPECT_GT(planned.fused_tiles, planned.tiles / 2) << "sited tiles fused";
      EXPECT_EQ(replayed.replayed_tiles, replayed.fused_tiles);
      EXPECT_TRUE(first == again) << "the replay gives the planned bytes";
      // The fused float positions within kFloatTolerance of the exact map's: 1 LSB from the
      // scalar engine's (the exact maps; a dual fisheye's lenses blended alike).
      ConvertOptions scalar = o;
      scalar.engine = Engine::Scalar;
      EXPECT_LE(most_difference(first, Converter(g, scalar).run(src)), 1.0);
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(SitedPlanes, NeedTheSimdOrScalarEngineWithoutEdgeFill) {
  const Projection p = make("equirect", {64, 32});
  ConversionGeometry g{p, p, Eigen::Matrix3d::Identity(), {}, {-0.25, 0, -0.25, 0}};
  ConvertOptions o;
  o.engine = Engine::Reference, o.antialias = Antialias{};
  EXPECT_THROW(Converter(g, o), Error);
  o.engine = Engine::Simd, o.edges.soft = true;
  EXPECT_THROW(Converter(g, o), Error);
}

}  // namespace
}  // namespace panoproj
