// The cube face convention (cubemap.hpp), proven on a real pair: Pannellum's Jordan Pond cubemap
// and the equirect it was made from (samples/images, see samples/images/SOURCES.md).
//  - cubemap -> equirect 2048x1024 matches the photo: both area-downsampled to 1024x512,
//    PSNR >= 36 dB;
//  - each of the 7 wrong orientations (rotations/mirrors) of the up face and of the down face
//    scores at least 3 dB lower;
//  - equirect -> cubemap (face W/4) -> equirect on the real photo, bicubic: reported.
#include <gtest/gtest.h>

#include "panoproj/convert.hpp"
#include "panoproj/io.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

// The 8 symmetries of a square: d = 0 is the identity.
Image dihedral(const Image& strip, int face, int d) {
  Image out = strip;
  const int64_t f = strip.height(), ox = face * f;
  for (int64_t y = 0; y < f; ++y)
    for (int64_t x = 0; x < f; ++x) {
      int64_t sx = x, sy = y;
      if (d & 1) std::swap(sx, sy);       // transpose
      if (d & 2) sx = f - 1 - sx;         // mirror x
      if (d & 4) sy = f - 1 - sy;         // mirror y
      std::memcpy(out.pixel(ox + x, y), strip.pixel(ox + sx, sy), strip.pixel_bytes());
    }
  return out;
}

class RealCubemap : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    photo_ = new Image(read_image(test::samples_dir() + "/jordan_pond_4096x2048.jpg"));
    faces_ = new Image(
        read_cube_faces(test::samples_dir() + "/cubemap_jordan_pond/face{index}_{face}.jpg"));
    photo_small_ = new Image(test::area_downsample(*photo_, 4));
  }
  static void TearDownTestSuite() {
    delete photo_;
    delete faces_;
    delete photo_small_;
  }
  static double score(const Image& faces, Interp interp) {
    ConvertOptions o;
    o.interp = interp;
    o.size = Size{2048, 1024};
    const Image e = convert(faces, parse_spec("cubemap:layout=files"), parse_spec("equirect"), o);
    return test::psnr(test::area_downsample(e, 2), *photo_small_);
  }
  static Image* photo_;
  static Image* faces_;
  static Image* photo_small_;
};
Image* RealCubemap::photo_ = nullptr;
Image* RealCubemap::faces_ = nullptr;
Image* RealCubemap::photo_small_ = nullptr;

TEST_F(RealCubemap, MatchesTheEquirectAndOnlyInTheDocumentedOrientation) {
  const double right = score(*faces_, Interp::Bilinear);
  std::printf("[cubemap-real] cubemap -> equirect 2048x1024 vs photo at 1024x512: %.2f dB\n", right);
  EXPECT_GE(right, 36.0);
  for (int face : {4, 5}) {
    for (int d = 1; d < 8; ++d) {
      const double wrong = score(dihedral(*faces_, face, d), Interp::Bilinear);
      std::printf("[cubemap-real] %s face, symmetry %d: %.2f dB (%.2f lower)\n", kFaceNames[face],
                  d, wrong, right - wrong);
      EXPECT_LE(wrong, right - 3.0) << kFaceNames[face] << " symmetry " << d;
    }
  }
}

// Face W/4 has 512 px/rad at its centre against the photo's 652 px/rad: a sharp photo loses
// detail there, so this is a reported figure with a regression floor, not a quality claim. The
// default face size (density-matched, 1304 px) is reported beside it; what remains is two
// Catmull-Rom resamplings of near-Nyquist JPEG detail at arbitrary sub-pixel offsets. Without
// antialiasing: it removes, by design, the detail the cube's polar faces cannot hold (the way
// back then differs more from the photo: 29.7 instead of 30.3 dB at face 1304).
TEST_F(RealCubemap, PhotoRoundTripThroughCubemap) {
  for (int64_t face : {int64_t{1024}, int64_t{0}}) {
    ConvertOptions o;
    o.interp = Interp::Bicubic;
    o.antialias = Antialias{};
    if (face > 0) o.size = Size{6 * face, face};
    const Image cube = convert(*photo_, parse_spec("equirect"), parse_spec("cubemap"), o);
    o.size = Size{4096, 2048};
    const Image back = convert(cube, parse_spec("cubemap"), parse_spec("equirect"), o);
    const double db = test::psnr(back, *photo_);
    std::printf("[e2c2e] Jordan Pond 4096x2048 -> cubemap face %lld -> equirect, bicubic: %.2f dB\n",
                static_cast<long long>(cube.height()), db);
    EXPECT_GE(db, face > 0 ? 27.0 : 30.0);
  }
}

}  // namespace
}  // namespace panoproj
