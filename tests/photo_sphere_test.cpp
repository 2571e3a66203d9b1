// Photo Sphere XMP (photo_sphere.hpp): the packet panoproj writes reads back field for field from
// a JPEG, the other XMP forms read, crops become the partial equirect they describe, and what does
// not fit is refused.
#include "panoproj/photo_sphere.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/spec.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

class PhotoSphereTest : public test::TempDirTest {
 protected:
  // An image file (JPEG or PNG, by the name) carrying xmp.
  std::string file(const std::string& name, const std::string& xmp) {
    WriteOptions w;
    w.xmp = xmp;
    write_image(Image({64, 32}, 3, PixelType::U8), path(name), w);
    return path(name);
  }
};

// A packet's fields; the pose and the stereo mode default.
PhotoSphere sphere(const char* type, int64_t full_w, int64_t full_h, int64_t crop_w, int64_t crop_h, int64_t left,
                   int64_t top, double pitch = 0, double roll = 0) {
  PhotoSphere ps;
  ps.projection_type = type;
  ps.full_width = full_w, ps.full_height = full_h, ps.crop_width = crop_w, ps.crop_height = crop_h;
  ps.crop_left = left, ps.crop_top = top, ps.pose_pitch = pitch, ps.pose_roll = roll;
  return ps;
}

bool same(const PhotoSphere& a, const PhotoSphere& b) {
  return a.projection_type == b.projection_type && a.full_width == b.full_width && a.full_height == b.full_height &&
         a.crop_width == b.crop_width && a.crop_height == b.crop_height && a.crop_left == b.crop_left &&
         a.crop_top == b.crop_top;
}

TEST_F(PhotoSphereTest, WrittenFieldsReadBack) {
  const PhotoSphere ps = sphere("equirectangular", 8000, 4000, 3000, 1500, 7000, 1200, -12.5, 3.25);
  const auto back = read_photo_sphere(file("a.jpg", photo_sphere_xmp(ps)));
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(same(*back, ps));
  EXPECT_EQ(back->pose_pitch, -12.5);
  EXPECT_EQ(back->pose_roll, 3.25);
  // The pose's rotation: the camera's axis pitched down 12.5 degrees (+y is down).
  const Ray axis = photo_sphere_pose(*back) * Ray(0, 0, 1);
  EXPECT_NEAR(std::asin(axis.y()), deg2rad(12.5), 1e-12);
  // The same in a PNG (an iTXt chunk), which OpenImageIO still reads as an image.
  const auto png = read_photo_sphere(file("a.png", photo_sphere_xmp(ps)));
  ASSERT_TRUE(png.has_value());
  EXPECT_TRUE(same(*png, ps));
  EXPECT_EQ(png->pose_roll, 3.25);
  EXPECT_EQ(read_image(path("a.png")).width(), 64);
  // Without a packet: none.
  EXPECT_FALSE(read_photo_sphere(file("b.jpg", "")).has_value());
  write_image(Image({8, 4}, 3, PixelType::U8), path("c.png"), {});
  EXPECT_FALSE(read_photo_sphere(path("c.png")).has_value());
}

TEST_F(PhotoSphereTest, PacketsAfterLargeSegmentsAndCutFiles) {
  // The reader takes 64 kB first, and up to 4 MB where the segments or chunks before the packet
  // run past them: 150 kB of APP2 segments (JPEG) or a private chunk (PNG) before it.
  const PhotoSphere ps = sphere("equirectangular", 8000, 4000, 3000, 1500, 7000, 1200, 5, 0);
  auto bytes = [](const std::string& f) {
    std::ifstream in(f, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  auto put = [&](const std::string& name, const std::string& b) {
    std::ofstream(path(name), std::ios::binary) << b;
    return path(name);
  };
  std::string jpeg = bytes(file("big.jpg", photo_sphere_xmp(ps))), app2;
  for (int k = 0; k < 3; ++k) app2 += std::string("\xFF\xE2\xC3\x52", 4) + std::string(50000, 'i');  // 0xC352 = 50002
  const auto from_jpeg = read_photo_sphere(put("big.jpg", jpeg.substr(0, 2) + app2 + jpeg.substr(2)));
  ASSERT_TRUE(from_jpeg.has_value());
  EXPECT_TRUE(same(*from_jpeg, ps));
  const std::string png = bytes(file("big.png", photo_sphere_xmp(ps)));
  const std::string chunk = std::string("\x00\x02\x49\xF0prIv", 8) + std::string(150000, 'p') + "crc!";  // 0x249F0
  const auto from_png = read_photo_sphere(put("big.png", png.substr(0, 33) + chunk + png.substr(33)));  // after IHDR
  ASSERT_TRUE(from_png.has_value());
  EXPECT_TRUE(same(*from_png, ps));
  // Cut inside the segments before the packet: none, no error (the decoder names the damage).
  EXPECT_FALSE(read_photo_sphere(put("cut.jpg", (jpeg.substr(0, 2) + app2).substr(0, 120000))).has_value());
  EXPECT_FALSE(read_photo_sphere(put("cut.png", (png.substr(0, 33) + chunk).substr(0, 90000))).has_value());
}

TEST_F(PhotoSphereTest, ElementFormAndDefaults) {
  // Fields as elements, no crop fields: the crop is the whole panorama.
  const std::string xmp =
      "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\"><rdf:RDF><rdf:Description xmlns:GPano=\"http://ns.google.com/photos/1.0/panorama/\">"
      "<GPano:ProjectionType>equirectangular</GPano:ProjectionType><GPano:FullPanoWidthPixels>4096</GPano:FullPanoWidthPixels>"
      "</rdf:Description></rdf:RDF></x:xmpmeta>";
  const auto ps = read_photo_sphere(file("e.jpg", xmp));
  ASSERT_TRUE(ps.has_value());
  EXPECT_TRUE(same(*ps, sphere("equirectangular", 4096, 2048, 4096, 2048, 0, 0)));
  EXPECT_EQ(parse_spec(photo_sphere_spec(*ps, {4096, 2048})).str(), parse_spec("equirect:hfov=360,vfov=180,lon0=0,lat0=0").str());
}

TEST(PhotoSphere, CropsArePartialEquirects) {
  // A quarter of the longitudes right of the centre, the upper half of the latitudes, stored at
  // half size: hfov 90, vfov 90, centred at lon 45, lat 45.
  const PhotoSphere ps = sphere("equirectangular", 8000, 4000, 2000, 2000, 4000, 0);
  const ProjectionSpec s = parse_spec(photo_sphere_spec(ps, {1000, 1000}));
  EXPECT_DOUBLE_EQ(*s.number("hfov"), 90);
  EXPECT_DOUBLE_EQ(*s.number("vfov"), 90);
  EXPECT_DOUBLE_EQ(*s.number("lon0"), 45);
  EXPECT_DOUBLE_EQ(*s.number("lat0"), 45);
  // Past the seam: the crop 7000..9000 of 8000 is centred at lon 180 - 0 = -180 / 180.
  EXPECT_NEAR(std::fabs(*parse_spec(photo_sphere_spec(sphere("equirectangular", 8000, 4000, 2000, 1000, 7000, 1500), {2000, 1000}))
                             .number("lon0")),
              180.0, 1e-9);
  // What does not fit.
  EXPECT_THROW(photo_sphere_spec(sphere("cylindrical", 8000, 4000, 8000, 2000, 0, 1000), {8000, 2000}), Error);
  EXPECT_THROW(photo_sphere_spec(ps, {1000, 700}), Error);  // not the crop's aspect
  EXPECT_THROW(photo_sphere_spec(sphere("equirectangular", 8000, 4000, 2000, 3000, 0, 2000), {2000, 3000}), Error);
  // An equirect's own fields give its spec back (within half a pixel of the full panorama: the
  // fields are whole pixels).
  const Projection e = make_projection(parse_spec("equirect:hfov=120,vfov=60,lon0=-30,lat0=10"), {1200, 600});
  const ProjectionSpec back = parse_spec(photo_sphere_spec(photo_sphere_of(std::get<Equirect>(e)), {1200, 600}));
  EXPECT_NEAR(*back.number("hfov"), 120, 1e-9);
  EXPECT_NEAR(*back.number("vfov"), 60, 1e-9);
  EXPECT_NEAR(*back.number("lon0"), -30, 360.0 / 3600 / 2);
  EXPECT_NEAR(*back.number("lat0"), 10, 180.0 / 1800 / 2);
}

TEST(PhotoSphere, StereoFramesDescribeOneEye) {
  // GSpherical:StereoMode read back; the GPano fields are one eye's, the spec says the layout.
  PhotoSphere ps = sphere("equirectangular", 4096, 2048, 4096, 2048, 0, 0, 0, 0);
  for (const auto& [mode, size, stereo] : {std::tuple{"top-bottom", Size{4096, 4096}, "stereo=tb"},
                                           std::tuple{"left-right", Size{8192, 2048}, "stereo=sbs"}}) {
    ps.stereo_mode = mode;
    const ProjectionSpec s = parse_spec(photo_sphere_spec(ps, size));
    EXPECT_EQ(s.choice("stereo"), std::string(stereo).substr(7)) << mode;
    EXPECT_DOUBLE_EQ(*s.number("hfov"), 360) << mode;
    // The whole frame's size as one eye's would not fit the fields.
    EXPECT_THROW(photo_sphere_spec(ps, {size.width + 1, size.height + 1}), Error) << mode;
  }
  ps.stereo_mode = "";
  EXPECT_THROW(photo_sphere_spec(ps, {4096, 4096}), Error);  // a tb frame's size without its mode
}

}  // namespace
}  // namespace panoproj
