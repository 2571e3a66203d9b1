// The fast engine: SIMD vs scalar sampling on every Highway target that runs here, for every
// kernel, pixel type and channel count, odd widths (unaligned rows); thread-count independence;
// agreement with the exact reference; an image wider than 32767 px.
#include "panoproj/convert.hpp"

#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>

#include "panoproj/error.hpp"
#include "sampling/resample.hpp"
#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

Projection make(const char* spec, Size size) { return make_projection(parse_spec(spec), size); }

// Largest difference over all samples, in units of the type (LSB for integers).
double max_diff(const Image& a, const Image& b) {
  double worst = 0;
  for (int64_t y = 0; y < a.height(); ++y)
    for (int64_t x = 0; x < a.width(); ++x)
      for (int c = 0; c < a.channels(); ++c)
        worst = std::max(worst, std::fabs(test::get(a, x, y, c) - test::get(b, x, y, c)));
  return worst;
}

// Pixels whose bytes differ.
int64_t differing_pixels(const Image& a, const Image& b) {
  int64_t n = 0;
  for (int64_t y = 0; y < a.height(); ++y)
    for (int64_t x = 0; x < a.width(); ++x) n += std::memcmp(a.pixel(x, y), b.pixel(x, y), a.pixel_bytes()) != 0;
  return n;
}

Image scene_image(const Projection& p, PixelType t, int channels) {
  const Image rgba = test::render(p, test::band_limited_scene(0.2, 512), t, true);
  if (channels == 4) return rgba;
  Image out(rgba.size(), channels, t, channels == 2 ? 1 : -1);
  for (int64_t y = 0; y < out.height(); ++y)
    for (int64_t x = 0; x < out.width(); ++x)
      for (int c = 0; c < channels; ++c)
        test::set(out, x, y, c, (c == 1 && channels == 2 ? test::get(rgba, x, y, 3) : test::get(rgba, x, y, c)) / unit_of(t));
  return out;
}

// Stated bounds, SIMD (float, or 16-bit fixed point for uint8 without alpha) vs scalar (double):
// nearest exact; integers within 1 LSB; float within 2e-6
// relative to the unit-range scene (Lanczos-3 weights from vector sin: 5e-6); half within one
// half ulp at 1.0 (2^-11 ~ 4.9e-4).
double bound(PixelType t, Interp k) {
  if (k == Interp::Nearest) return 0.0;  // the same pixel, copied
  switch (t) {
    case PixelType::U8:
    case PixelType::U16: return 1.0;
    case PixelType::F16: return 4.9e-4;
    case PixelType::F32: return kernel_of(k) == Interp::Lanczos3 ? 5e-6 : 2e-6;
  }
  return 0;
}

TEST(Engine, SimdMatchesScalarOnEveryTarget) {
  // An Aitoff target: the SIMD geometry does not take it, so both engines map with the tile
  // mapper and only the sampling differs.
  const Projection src = make("equirect", {517, 259});  // odd: rows start unaligned
  const Projection dst = make("aitoff", {203, 103});
  const Eigen::Matrix3d r = rotation_from_ypr(20, -10, 5);
  const auto targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    ASSERT_STREQ(simd_target(), hwy::TargetName(target)) << "dispatch did not switch target";
    for (PixelType t : {PixelType::U8, PixelType::U16, PixelType::F16, PixelType::F32})
      for (int nc : {1, 2, 3, 4}) {
        const Image im = scene_image(src, t, nc);
        for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3, Interp::BicubicDering,
                         Interp::Lanczos3Dering}) {
          EngineStats st;
          const Image a = test::fast_remap(im, src, dst, r, k, Engine::Simd, 2, &st);
          const Image b = test::fast_remap(im, src, dst, r, k, Engine::Scalar, 2);
          EXPECT_EQ(st.fused_tiles, 0) << "the tile mapper's positions, not the fused geometry";
          EXPECT_LT(st.simd_misses * 50, 203 * 203) << "the SIMD kernels should take almost every sample";
          const double d = max_diff(a, b);
          EXPECT_LE(d, bound(t, k)) << name_of(t) << " " << nc << "ch " << name_of(k);
        }
      }
  }
  hwy::SetSupportedTargetsForTest(0);
  std::printf("[engine] SIMD checked on %zu targets; dispatch picks %s here\n", targets.size(), simd_target());
}

TEST(Engine, FusedGeometryMatchesTheReferenceOnEveryTarget) {
  // The fused path (float or double geometry in registers, then the same kernels) against the
  // exact reference: positions within SimdGeometry::kFloatTolerance move a sample of this scene
  // (at most ~160 LSB per px) by < 0.2 LSB, so integers stay within 1 LSB, floats within 1e-3;
  // nearest picks the same pixels (float vectors near a pixel edge recomputed in double).
  struct Pair {
    const char* src;
    Size ss;
    const char* dst;
    Size ds;
  };
  const Pair pairs[] = {{"equirect", {517, 259}, "cubemap", {6 * 128, 128}},
                        {"equirect", {517, 259}, "fisheye:fov=190,model=equisolid", {203, 203}},
                        {"cubemap", {6 * 61, 61}, "pinhole:hfov=100", {151, 101}},
                        {"cubemap", {6 * 61, 61}, "equirect", {301, 151}},
                        {"equirect", {517, 259}, "cubemap:layout=eac", {3 * 128, 2 * 128}},
                        {"cubemap:layout=eac", {3 * 61, 2 * 61}, "fisheye:fov=200", {203, 203}},
                        {"aitoff", {517, 259}, "pinhole:hfov=120", {151, 101}},
                        {"equirect", {517, 259}, "bonne:phi1=30", {203, 151}}};
  const Eigen::Matrix3d r = rotation_from_ypr(20, -10, 5);
  const auto targets = hwy::SupportedAndGeneratedTargets();
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    for (const Pair& c : pairs) {
      const Projection src = make(c.src, c.ss), dst = make(c.dst, c.ds);
      // (One channel of uint8 and uint16: a video's planes, the gray kernels.)
      for (auto [t, nc] : {std::pair{PixelType::U8, 3},
                           {PixelType::U8, 4},
                           {PixelType::U16, 2},
                           {PixelType::F32, 1},
                           {PixelType::U8, 1},
                           {PixelType::U16, 1}}) {
        const Image im = scene_image(src, t, nc);
        for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3}) {
          EngineStats st;
          const Image a = test::fast_remap(im, src, dst, r, k, Engine::Simd, 2, &st);
          const Image b = remap(im, src, dst, r, {k, 2});
          EXPECT_EQ(st.fused_tiles, st.tiles) << c.src << " -> " << c.dst;
          if (k == Interp::Nearest) {
            EXPECT_EQ(differing_pixels(a, b), 0) << c.src << " -> " << c.dst << " " << name_of(t);
          } else {
            EXPECT_LE(max_diff(a, b), t == PixelType::F32 ? 1e-3 : 1.0)
                << c.src << " -> " << c.dst << " " << name_of(t) << " " << nc << "ch " << name_of(k);
          }
        }
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Pixels in memory whose last byte is followed by an unreadable page: a read past the end faults.
class GuardedPixels {
 public:
  explicit GuardedPixels(size_t bytes) {
    const auto page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    size_ = (bytes + page - 1) / page * page + page;
    map_ = mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    EXPECT_NE(map_, MAP_FAILED);
    EXPECT_EQ(mprotect(static_cast<char*>(map_) + size_ - page, page, PROT_NONE), 0);
    data_ = static_cast<unsigned char*>(map_) + (size_ - page - bytes);
  }
  ~GuardedPixels() { munmap(map_, size_); }
  unsigned char* data() const { return data_; }

 private:
  void* map_;
  size_t size_;
  unsigned char* data_;
};

TEST(Engine, ViewsOfExactBuffersAreNeverReadPastTheirEnd) {
  // Identity and a part-pixel turn of an equirect: pixels of the last row's right end are taps
  // inside the frame, which the gathers (8 bytes from a tap) would read past. On a view whose
  // buffer ends at an unreadable page, every kernel, type and channel count must still give the
  // bytes of the owning image.
  const Projection src = make("equirect", {61, 30});
  for (double yaw : {0.0, 0.3 * 360.0 / 61}) {
    const Eigen::Matrix3d r = rotation_from_ypr(yaw, 0, 0);
    for (PixelType t : {PixelType::U8, PixelType::U16, PixelType::F16, PixelType::F32})
      for (int nc : {1, 2, 3, 4}) {
        const Image im = scene_image(src, t, nc);
        GuardedPixels guarded(im.byte_size());
        std::memcpy(guarded.data(), im.data(), im.byte_size());
        const Image view = Image::view(guarded.data(), im.size(), nc, t, im.alpha_channel());
        ASSERT_TRUE(view.is_view());
        for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3}) {
          SCOPED_TRACE(std::string(name_of(t)) + " x" + std::to_string(nc) + " " + name_of(k));
          const Image a = test::fast_remap(view, src, src, r, k, Engine::Simd, 1);
          EXPECT_TRUE(a == test::fast_remap(im, src, src, r, k, Engine::Simd, 1));
        }
      }
  }
}

TEST(Engine, ThreadCountDoesNotChangeOneBit) {
  const Projection src = make("cubemap", {6 * 128, 128});
  const Projection dst = make("equirect", {700, 350});
  const Image im = scene_image(src, PixelType::U8, 3);
  for (Engine e : {Engine::Simd, Engine::Scalar}) {
    const Image one = test::fast_remap(im, src, dst, Eigen::Matrix3d::Identity(), Interp::Bicubic, e, 1);
    EXPECT_TRUE(test::fast_remap(im, src, dst, Eigen::Matrix3d::Identity(), Interp::Bicubic, e, 2) == one);
    EXPECT_TRUE(test::fast_remap(im, src, dst, Eigen::Matrix3d::Identity(), Interp::Bicubic, e, 5) == one);
  }
}

TEST(Engine, CachedMapGivesTheSameBytesAndChecksSizes) {
  const Projection src = make("equirect", {600, 300});
  const Projection dst = make("cubemap:layout=cross", {4 * 100, 3 * 100});
  const Eigen::Matrix3d r = rotation_from_ypr(10, 5, 0);
  const Converter cached =
      test::converter(src, dst, r, Interp::Bicubic, Engine::Simd, 2, Keep::Maps);
  for (uint32_t seed : {1u, 2u}) {  // two frames through one cached map
    const Image im = test::render(src, test::band_limited_scene(0.1, 600, seed), PixelType::U8);
    EXPECT_TRUE(cached.run(im) == test::fast_remap(im, src, dst, r, Interp::Bicubic, Engine::Simd, 1));
  }
  EXPECT_THROW(cached.run(Image({601, 300}, 3, PixelType::U8)), Error);
}

TEST(Engine, FootprintIsTheSameWithOrWithoutAKeptMap) {
  // Without a cache the footprint keeps one tile map per thread (large outputs); with one it
  // keeps them all. Both must name the same source rectangle and give the same image.
  const Projection src = make("equirect", {2048, 1024});
  for (auto [spec, pitch] : {std::pair{"pinhole:hfov=70", 20.0}, {"pinhole:hfov=70", 80.0}, {"aitoff", 0.0},
                             {"fisheye:fov=100", -30.0}}) {
    const Projection dst = make(spec, {400, 300});
    const Eigen::Matrix3d r = rotation_from_ypr(40, pitch, 0);
    const Converter kept =
        test::converter(src, dst, r, Interp::Bicubic, Engine::Simd, 2, Keep::Maps);
    const Converter lean =
        test::converter(src, dst, r, Interp::Bicubic, Engine::Simd, 2, Keep::Nothing);
    const auto a = kept.source_footprint(), b = lean.source_footprint();
    EXPECT_EQ(a.x0, b.x0);
    EXPECT_EQ(a.y0, b.y0);
    EXPECT_EQ(a.x1, b.x1);
    EXPECT_EQ(a.y1, b.y1);
    // Fused tiles take their bounds from the vector geometry (float where allowed); the tile
    // mapper's (scalar engine) may differ only by the rounding of a tap index.
    const auto c =
        test::converter(src, dst, r, Interp::Bicubic, Engine::Scalar, 2).source_footprint();
    EXPECT_LE(std::abs(a.x0 - c.x0), 1) << spec;
    EXPECT_LE(std::abs(a.y0 - c.y0), 1) << spec;
    EXPECT_LE(std::abs(a.x1 - c.x1), 1) << spec;
    EXPECT_LE(std::abs(a.y1 - c.y1), 1) << spec;
    const Image im = test::render(src, test::band_limited_scene(0.1, 2048), PixelType::U8);
    EXPECT_TRUE(kept.run(im) == lean.run(im)) << spec;
  }
}

TEST(Engine, TargetsShowingTheWholeSphereNeedTheWholeSource) {
  const Projection pin = make("pinhole:hfov=90", {400, 300}), pano = make("equirect", {2048, 1024});
  const Eigen::Matrix3d r = rotation_from_ypr(30, 10, 0);
  for (const char* spec : {"cubemap", "equirect", "aitoff", "hammer", "bonne"}) {
    const Size size = std::string(spec) == "cubemap" ? Size{600, 100} : Size{600, 300};
    const auto f = test::converter(pin, make(spec, size), r, Interp::Bilinear, Engine::Simd, 2)
                       .source_footprint();
    EXPECT_TRUE(f.x0 == 0 && f.y0 == 0 && f.x1 == 400 && f.y1 == 300) << spec;
  }
  // A partial equirect view shows part of the sphere: only part of the source.
  const auto f = test::converter(pano, make("equirect:hfov=90,vfov=60", {300, 200}), r,
                                 Interp::Bilinear, Engine::Simd, 2)
                     .source_footprint();
  EXPECT_LT((f.x1 - f.x0) * (f.y1 - f.y0), 2048 * 1024 / 4);
}

TEST(Engine, AgreesWithTheReference) {
  // Coordinates within 1/256 px and float sampling: within 1 LSB of the exact double path on a
  // band-limited scene (a steeper image moves more per 1/256 px).
  struct C {
    const char* src;
    Size ss;
    const char* dst;
    Size ds;
  };
  for (const C& c : {C{"equirect", {1024, 512}, "cubemap", {6 * 256, 256}},
                     C{"cubemap", {6 * 256, 256}, "equirect", {1024, 512}},
                     C{"equirect", {1024, 512}, "aitoff", {800, 400}},
                     C{"fisheye:fov=210", {512, 512}, "equirect", {1024, 512}}}) {
    const Projection sp = make(c.src, c.ss), dp = make(c.dst, c.ds);
    const Image im = test::render(sp, test::band_limited_scene(0.1, 1024), PixelType::U8, true);
    for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Bicubic}) {
      const Image ref = remap(im, sp, dp, Eigen::Matrix3d::Identity(), {k, 0});
      const Image fast = test::fast_remap(im, sp, dp, Eigen::Matrix3d::Identity(), k, Engine::Simd, 0);
      if (k == Interp::Nearest) {
        // A 1/256 px shift can move a sample across a pixel boundary: count, don't bound.
        EXPECT_LT(differing_pixels(ref, fast), ref.width() * ref.height() / 100) << c.src << " -> " << c.dst;
      } else {
        EXPECT_LE(max_diff(ref, fast), 1.0) << c.src << " -> " << c.dst << " " << name_of(k);
      }
    }
  }
}

TEST(Engine, WiderThan32767Pixels) {
  // A 40000 x 16 strip of a full-longitude equirect: yaw 90 with nearest is an exact shift of
  // 10000 columns; bilinear agrees with the reference.
  const Projection p = make("equirect:vfov=0.144", {40000, 16});
  Image im({40000, 16}, 3, PixelType::U8);
  for (int64_t y = 0; y < 16; ++y)
    for (int64_t x = 0; x < 40000; ++x)
      for (int c = 0; c < 3; ++c) im.pixel(x, y)[c] = static_cast<unsigned char>((x * 7 + y * 31 + c * 85) % 251);
  const Eigen::Matrix3d yaw = rotation_from_ypr(90, 0, 0);
  const Image shifted = test::fast_remap(im, p, p, yaw, Interp::Nearest, Engine::Simd, 0);
  for (int64_t y = 0; y < 16; ++y)
    for (int64_t x = 0; x < 40000; x += 7)
      ASSERT_EQ(0, std::memcmp(shifted.pixel(x, y), im.pixel((x + 10000) % 40000, y), 3)) << x;
  const Image ref = remap(im, p, p, rotation_from_ypr(33.3, 0, 0), {Interp::Bilinear, 0});
  const Image fast = test::fast_remap(im, p, p, rotation_from_ypr(33.3, 0, 0), Interp::Bilinear, Engine::Simd, 0);
  EXPECT_LE(max_diff(ref, fast), 1.0);
}

}  // namespace
}  // namespace panoproj
