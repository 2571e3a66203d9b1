// Camera responses and the photometric correction (photometry/): the inverse against a plain
// search of the table, round trips, Hugin's clamps and monotonic flattening, and the correction
// against its formula at known source positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "panoproj/error.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"
#include "photometry/photometric.hpp"
#include "photometry/response.hpp"
#include "photometry/source_correction.hpp"

namespace panoproj {
namespace {

// The inverse as Hugin's InvLUTFunctor writes it: std::lower_bound over the table of `r`, read
// back through code() at the sample irradiances.
double searched_inverse(const Response& r, double v) {
  std::vector<double> t(kResponseSamples);
  for (int i = 0; i < kResponseSamples; ++i)
    t[i] = r.code(static_cast<double>(i) / (kResponseSamples - 1));
  if (v >= t.back()) return t.back();
  if (v < t[0]) return 0;
  const auto p = std::lower_bound(t.begin(), t.end(), v);
  const auto x = static_cast<size_t>(p - t.begin());
  if (x == 0) return 0;
  if (v == *p) return static_cast<double>(x) / (kResponseSamples - 1);
  return (static_cast<double>(x - 1) + (v - t[x - 1]) / (t[x] - t[x - 1])) / (kResponseSamples - 1);
}

TEST(Response, TheInverseIsTheTablesSearchedInverseAndRoundTrips) {
  std::mt19937 rng(51);
  std::uniform_real_distribution<double> coefficient(-1.5, 1.5), unit(0, 1);
  int curves = 0;
  for (int k = 0; k < 200 && curves < 40; ++k) {
    const std::array<double, 5> p{coefficient(rng), coefficient(rng) / 2, coefficient(rng) / 3,
                                  coefficient(rng) / 4, coefficient(rng) / 5};
    Response r;
    try {
      r = Response::emor(p, "curve");
    } catch (const Error&) {
      continue;  // not monotonic: refused (below)
    }
    ++curves;
    EXPECT_EQ(r.code(0), 0);
    EXPECT_NEAR(r.code(1), 1, 1e-12);
    for (int s = 0; s < 2000; ++s) {
      const double v = unit(rng);
      EXPECT_DOUBLE_EQ(r.irradiance(v), searched_inverse(r, v)) << v;
      EXPECT_NEAR(r.code(r.irradiance(v)), v, 1e-12) << v;
    }
  }
  EXPECT_GE(curves, 20);
}

TEST(Response, ClampsAsHuginsTables) {
  const Response f0 = Response::emor({}, "f0");
  EXPECT_EQ(f0.code(-0.5), 0);
  EXPECT_EQ(f0.code(3), f0.code(1));
  EXPECT_EQ(f0.irradiance(-0.1), 0);
  EXPECT_EQ(f0.irradiance(1.7), f0.code(1));
  // f0 bends codes up (a camera's gamma): mid grey's code well above its irradiance.
  EXPECT_GT(f0.code(0.18), 0.4);
  const Response linear;
  EXPECT_TRUE(linear.linear());
  EXPECT_EQ(linear.irradiance(1.25), 1.25);  // no table: no clamp (Hugin's Rt1)
}

TEST(Response, RefusesCurvesThatAreNotResponses) {
  EXPECT_THROW(Response::emor({NAN, 0, 0, 0, 0}, "a"), Error);
  EXPECT_THROW(Response::emor({1e300, 0, 0, 0, 0}, "a"), Error);
  try {
    Response::emor({-9, 0, 0, 0, 0}, "i line 7");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("i line 7: response Ra-9"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not monotonic"), std::string::npos);
  }
}

TEST(Response, SmallDipsAreFlattenedAsHugin) {
  // The largest p along h5 whose curve still passes: its table non-decreasing after flattening.
  for (double p5 = 0.5; p5 < 8; p5 += 0.5) {
    Response r;
    try {
      r = Response::emor({0, 0, 0, 0, p5}, "h5");
    } catch (const Error&) {
      break;
    }
    double last = -1;
    for (int i = 0; i < kResponseSamples; ++i) {
      const double v = r.code(static_cast<double>(i) / (kResponseSamples - 1));
      EXPECT_GE(v, last);
      last = v;
    }
  }
}

// A 2 x 1 float RGBA part whose pixel x has the source position (Hugin's pixels) at[x].
struct Part {
  Image pixels{Size{2, 1}, 4, PixelType::F32, 3};
  std::array<std::array<double, 2>, 2> at{};
  float* px(int x) { return reinterpret_cast<float*>(pixels.pixel(x, 0)); }
  PhotometricStep::SourcePosition position() const {
    return [this](double x, double, double& sx, double& sy) {
      const auto& p = at[static_cast<size_t>(x)];
      sx = p[0], sy = p[1];
      return true;
    };
  }
};

TEST(Photometry, LinearLayersFollowTheFormula) {
  Photometry ph;  // linear response
  ph.exposure = 1.5;
  ph.red = 1.25, ph.blue = 0.8;
  ph.vignetting.coefficients = {1, -0.3, 0.05, -0.01};
  ph.vignetting.shift_x = 7, ph.vignetting.shift_y = -3;
  PhotometricOutput out;
  out.hdr = true, out.exposure = 0.5;
  out.response = Response();
  const Size size{400, 300};
  const PhotometricStep step(ph, out, size, "t");
  EXPECT_FALSE(step.identity());
  EXPECT_TRUE(step.needs_positions());
  Part part;
  for (int x = 0; x < 2; ++x) std::fill(part.px(x), part.px(x) + 4, 0.25f);
  part.px(1)[3] = 0;  // not kept: left as it is
  part.at = {{{350, 40}, {10, 10}}};
  Image weights;
  step.apply(part.pixels, part.position(), &weights, 1);
  const double dx = 350 - (199.5 + 7), dy = 40 - (149.5 - 3);
  const double s = (dx * dx + dy * dy) / (200.0 * 200 + 150.0 * 150);
  const double v = 1 + s * (-0.3 + s * (0.05 - 0.01 * s));
  const double g = std::exp2(1.5 - 0.5) / v;
  EXPECT_NEAR(part.px(0)[0], 0.25 * g / 1.25, 1e-6);
  EXPECT_NEAR(part.px(0)[1], 0.25 * g, 1e-6);
  EXPECT_NEAR(part.px(0)[2], 0.25 * g / 0.8, 1e-6);
  EXPECT_EQ(part.px(1)[0], 0.25f);
  EXPECT_EQ(weights.row(0)[0], 64);  // round(0.25 * 255)
  EXPECT_EQ(weights.row(0)[1], 0);
}

TEST(Photometry, TheGridsPositionsGiveEachPixelsOwnVignetting) {
  // A 100-degree rectilinear image (900 x 600, strongly vignetted, centre shifted) seen from an
  // equirect canvas at about its scale: a part over its corner, where the map bends most, and
  // past its edge (no source there).
  const Projection image = make_projection(parse_spec("pinhole:hfov=100"), {900, 600});
  const Projection canvas = make_projection(parse_spec("equirect"), {3000, 1500});
  Photometry ph;
  ph.response = Response();
  ph.vignetting.coefficients = {1, -0.6, 0.2, -0.05};
  ph.vignetting.shift_x = 30;
  PhotometricOutput out;
  out.hdr = true, out.response = Response();
  const PhotometricStep step(ph, out, {900, 600}, "t");
  const Size size{203, 151};
  const double x0 = 1500 + 260, y0 = 750 - 330;
  const PhotometricStep::SourcePosition map = [&](double x, double y, double& sx, double& sy) {
    Ray d;
    return to_ray(canvas, x0 + x, y0 + y, d) && to_pixel(image, d, sx, sy) &&
           (sx -= 0.5, sy -= 0.5, true);
  };
  Image part(size, 4, PixelType::F32, 3);
  for (int64_t y = 0; y < size.height; ++y)
    for (int64_t x = 0; x < size.width; ++x)
      std::fill_n(reinterpret_cast<float*>(part.pixel(x, y)), 4, 0.5f);
  step.apply(part, map, nullptr, 2);
  double worst = 0;
  int64_t inside = 0, outside = 0;
  for (int64_t y = 0; y < size.height; ++y)
    for (int64_t x = 0; x < size.width; ++x) {
      double sx, sy;
      const float got = reinterpret_cast<float*>(part.pixel(x, y))[1];
      if (!map(static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, sx, sy)) {
        EXPECT_EQ(got, 0.5f);
        ++outside;
        continue;
      }
      ++inside;
      worst = std::max(worst, std::fabs(got * step.vignetting(sx, sy) / 0.5 - 1));
    }
  EXPECT_GT(inside, 5000);
  EXPECT_GT(outside, 1000);
  EXPECT_LT(worst, 2e-5);
}

TEST(Photometry, TheIdentityClampsOnly) {
  Photometry ph;
  PhotometricOutput out;
  const PhotometricStep step(ph, out, {10, 10}, "t");
  EXPECT_TRUE(step.identity());
  EXPECT_FALSE(step.needs_positions());
  Part part;
  part.px(0)[0] = 1.5f, part.px(0)[1] = -0.25f, part.px(0)[2] = 0.5f, part.px(0)[3] = 1;
  step.apply(part.pixels, nullptr, nullptr, 1);
  EXPECT_EQ(part.px(0)[0], 1.0f);
  EXPECT_EQ(part.px(0)[1], 0.0f);
  EXPECT_EQ(part.px(0)[2], 0.5f);
}

TEST(Photometry, AFlatFieldDividesByItsNearestPixelOverItsLargest) {
  auto flat = std::make_shared<Image>(Size{4, 2}, 1, PixelType::F32);
  for (int64_t y = 0; y < 2; ++y)
    for (int64_t x = 0; x < 4; ++x)
      reinterpret_cast<float*>(flat->row(y))[x] = static_cast<float>(1 + x + 4 * y);
  Photometry ph;
  ph.response = Response();
  ph.vignetting.flat_field = flat;
  PhotometricOutput out;
  out.hdr = true;
  const PhotometricStep step(ph, out, {4, 2}, "t");
  Part part;
  std::fill(part.px(0), part.px(0) + 4, 0.5f);
  std::fill(part.px(1), part.px(1) + 4, 0.5f);
  part.at = {{{1.9, 1.4}, {-0.3, -0.3}}};  // pixel (2, 1), 7 of 8; clamped to (0, 0), 1 of 8
  step.apply(part.pixels, part.position(), nullptr, 1);
  EXPECT_NEAR(part.px(0)[1], 0.5 * 8 / 7, 1e-6);
  EXPECT_NEAR(part.px(1)[1], 0.5 * 8 / 1, 1e-6);
}

TEST(Photometry, AFlatFieldIsTakenAtEveryPixelNotInterpolated) {
  // A field that steps every pixel (dust, a sensor's pattern): no grid may smooth it over.
  const Size size{40, 24};
  auto flat = std::make_shared<Image>(size, 1, PixelType::F32);
  for (int64_t y = 0; y < size.height; ++y)
    for (int64_t x = 0; x < size.width; ++x)
      reinterpret_cast<float*>(flat->row(y))[x] = (x + y) % 2 ? 1.0f : 0.5f;
  Photometry ph;
  ph.response = Response();
  ph.vignetting.flat_field = flat;
  PhotometricOutput out;
  out.hdr = true;
  const PhotometricStep step(ph, out, size, "t");
  Image part(size, 4, PixelType::F32, 3);
  for (int64_t y = 0; y < size.height; ++y)
    for (int64_t x = 0; x < size.width; ++x)
      std::fill_n(reinterpret_cast<float*>(part.pixel(x, y)), 4, 0.25f);
  step.apply(
      part,
      [](double x, double y, double& sx, double& sy) { return sx = x - 0.5, sy = y - 0.5, true; },
      nullptr, 1);
  for (int64_t y = 0; y < size.height; ++y)
    for (int64_t x = 0; x < size.width; ++x)
      ASSERT_NEAR(reinterpret_cast<float*>(part.pixel(x, y))[1], (x + y) % 2 ? 0.25 : 0.5, 1e-6)
          << x << "," << y;
}

TEST(Photometry, RefusesModelsNothingCanBeDividedBy) {
  const PhotometricOutput out;
  const auto refused = [&](const Photometry& ph, Size size, const char* needle) {
    try {
      PhotometricStep(ph, out, size, "img 3");
      ADD_FAILURE() << needle;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  Photometry ph;
  ph.vignetting.coefficients = {1, -1.2, 0, 0};  // 0 at r = 0.91: inside a 4:3 image's corners
  refused(ph, {400, 300}, "inside the image");
  ph.vignetting.coefficients = {1, -0.9, 0, 0};  // 0.1 at the corners: kept
  EXPECT_NO_THROW(PhotometricStep(ph, out, {400, 300}, "img 3"));
  ph.vignetting.shift_x = 300;  // the centre moved out: the far corner at r = 1.65
  refused(ph, {400, 300}, "falls to");
  ph = Photometry();
  ph.red = 0;
  refused(ph, {4, 4}, "white balance Er0");
  ph = Photometry();
  ph.exposure = INFINITY;
  refused(ph, {4, 4}, "exposure values");
  ph = Photometry();
  ph.vignetting.flat_field = std::make_shared<Image>(Size{3, 3}, 1, PixelType::F32);
  refused(ph, {4, 4}, "a flat field of 3x3");
  auto zero = std::make_shared<Image>(Size{4, 4}, 1, PixelType::F32);
  ph.vignetting.flat_field = zero;
  refused(ph, {4, 4}, "the flat field's values run from 0");
}

// A source's correction from its spec's keys (source_correction.hpp).
Image uniform(Size size, int channels, PixelType type, double value) {
  Image im(size, channels, type);
  for (int64_t y = 0; y < size.height; ++y)
    for (int64_t x = 0; x < size.width; ++x)
      for (int c = 0; c < channels; ++c) {
        if (type == PixelType::F32)
          reinterpret_cast<float*>(im.row(y))[x * channels + c] = static_cast<float>(value);
        else
          im.row(y)[x * channels + c] = static_cast<unsigned char>(std::lround(value * 255));
      }
  return im;
}

float at(const Image& im, int64_t x, int64_t y, int c = 0) {
  return reinterpret_cast<const float*>(im.row(y))[x * im.channels() + c];
}

TEST(SourceCorrection, EachPixelTakesItsOwnLensModel) {
  // Linear light 0.25; lens 1 a stop down (ev2 = 1): 0.5 where the projection's lens_at says 1.
  const auto check = [](const std::string& spec, Size size) {
    const ProjectionSpec from = parse_spec(spec + ",response=linear,ev2=1");
    const Projection p = make_projection(from, size);
    const auto c = SourceCorrection::make(from, parse_spec("equirect:ev=0"), p, StereoLayout::Mono);
    ASSERT_TRUE(c && !c->identity(PixelType::F32)) << spec;
    Image out;
    c->apply(uniform(size, 3, PixelType::F32, 0.25), out, 2);
    int64_t ones = 0;
    for (int64_t y = 0; y < size.height; ++y)
      for (int64_t x = 0; x < size.width; ++x) {
        const int lens = std::visit(
            [&](const auto& q) {
              if constexpr (requires { q.lens_at(0.0, 0.0); })
                return q.lens_at(static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5);
              else
                return 0;
            },
            p);
        ones += lens;
        ASSERT_NEAR(at(out, x, y, 1), lens ? 0.5 : 0.25, 1e-7) << spec << " at " << x << "," << y;
      }
    EXPECT_GT(ones, size.width * size.height / 4) << spec;
  };
  check("dual-fisheye:fov=200", {64, 32});
  check("dual-fisheye:fov=200,layout=top-bottom", {32, 64});
  check("gopro-max:face=64,outer=96,band=8", {256, 128});
}

TEST(SourceCorrection, WindowsScalesAndEyesTakeTheFramesPositions) {
  // V = 1 - 0.5 r^2 about the eye's centre shifted (6, -4), r over its half diagonal: a window
  // of the frame at 1/2 scale, each eye of a top-bottom stereo frame alike.
  const Size eye{80, 40};
  const ProjectionSpec from =
      parse_spec("equirect:stereo=tb,response=linear,vignetting=1/-0.5,vignetting_centre=6/-4");
  const auto c = SourceCorrection::make(from, parse_spec("equirect:stereo=tb"),
                                        make_projection(from, eye), StereoLayout::TopBottom);
  ASSERT_TRUE(c);
  Image window = uniform({30, 50}, 1, PixelType::F32, 1.0);
  window.set_window(7, 3, {40, 40});  // (the 80x80 frame at 1/2)
  Image out;
  c->apply(window, out, 2);
  EXPECT_EQ(out.origin_x(), 7);
  EXPECT_EQ(out.frame_size(), (Size{40, 40}));
  const double half_diagonal = std::sqrt(80.0 * 80 / 4 + 40.0 * 40 / 4);
  double worst = 0;
  for (int64_t y = 0; y < 37; ++y)
    for (int64_t x = 0; x < 30; ++x) {
      const double fx = (static_cast<double>(7 + x) + 0.5) * 2 - 0.5;
      double fy = (static_cast<double>(3 + y) + 0.5) * 2 - 0.5;
      if (fy >= 40) fy -= 40;  // the right eye's rows
      const double dx = fx - (79 / 2.0 + 6), dy = fy - (39 / 2.0 - 4);
      const double v = 1 - 0.5 * (dx * dx + dy * dy) / (half_diagonal * half_diagonal);
      worst = std::max(worst, std::fabs(at(out, x, y) - 1 / v));
    }
  EXPECT_LT(worst, 1e-6);
}

TEST(SourceCorrection, IntegerSamplesAreTheFloatCorrectionRounded) {
  const ProjectionSpec from = parse_spec("fisheye:fov=180,ev=0.7,wb=1.1/0.9,vignetting=1/-0.3");
  const ProjectionSpec to = parse_spec("equirect");
  const Size size{48, 48};
  const auto c = SourceCorrection::make(from, to, make_projection(from, size), StereoLayout::Mono);
  Image u8(size, 3, PixelType::U8), f(size, 3, PixelType::F32);
  for (int64_t y = 0; y < size.height; ++y)
    for (int64_t x = 0; x < size.width; ++x)
      for (int k = 0; k < 3; ++k) {
        const auto v = static_cast<unsigned char>((x * 5 + y * 3 + k * 70) % 256);
        u8.row(y)[x * 3 + k] = v;
        reinterpret_cast<float*>(f.row(y))[x * 3 + k] = static_cast<float>(v / 255.0);
      }
  // (Float samples default to a linear response: the integer one's EMoR given for both.)
  const ProjectionSpec from_f = parse_spec(from.str() + ",response=emor");
  const auto cf =
      SourceCorrection::make(from_f, to, make_projection(from_f, size), StereoLayout::Mono);
  Image a, b;
  c->apply(u8, a, 2);
  cf->apply(f, b, 2);
  int64_t moved = 0;
  for (int64_t y = 0; y < size.height; ++y)
    for (int64_t x = 0; x < size.width; ++x)
      for (int k = 0; k < 3; ++k) {
        const double want = std::clamp(std::nearbyint(at(b, x, y, k) * 255.0), 0.0, 255.0);
        ASSERT_EQ(a.row(y)[x * 3 + k], want) << x << "," << y << "," << k;
        moved += a.row(y)[x * 3 + k] != u8.row(y)[x * 3 + k];
      }
  EXPECT_GT(moved, size.width * size.height);  // (the correction does something)
}

TEST(SourceCorrection, RefusesWhatNoSourceCanMean) {
  const auto make = [](const std::string& from, const std::string& to, Size size) {
    const ProjectionSpec f = parse_spec(from);
    return SourceCorrection::make(f, parse_spec(to), make_projection(f, size), StereoLayout::Mono);
  };
  EXPECT_EQ(make("equirect", "fisheye", {64, 32}), nullptr);
  EXPECT_THROW(make("equirect", "fisheye:wb=1/1", {64, 32}), Error);
  EXPECT_THROW(make("gopro-max:face=64,outer=96,band=8,vignetting=1/-0.1", "equirect", {256, 128}),
               Error);
  EXPECT_THROW(make("equirect:vignetting=1/-1.5", "fisheye", {64, 32}), Error);
  EXPECT_NO_THROW(make("equirect:vignetting=1/-0.5", "fisheye", {64, 32}));
}

}  // namespace
}  // namespace panoproj
