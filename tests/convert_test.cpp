// Planning a conversion: default sizes keep square pixels at the source's centre density, and
// bad parameters are refused before any work.
#include "panoproj/convert.hpp"

#include <gtest/gtest.h>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

Size planned(const char* from, Size size, const char* to) {
  return size_of(make_geometry(size, parse_spec(from), parse_spec(to), {}).target);
}

TEST(ConversionGeometry, DefaultSizesKeepSquarePixelsAtTheSourceDensity) {
  const Size e{4096, 2048};  // 4096 / 2 pi = 651.9 px/rad
  EXPECT_EQ(planned("equirect", e, "equirect"), e);
  EXPECT_EQ(planned("equirect", e, "equirect:hfov=90,vfov=45"), (Size{1024, 512}));
  // Cylindrical: W/H = hfov / (2 tan(vfov/2)).
  const Size c = planned("equirect", e, "cylindrical:hfov=360,vfov=90");
  EXPECT_EQ(c.width, 4096);
  EXPECT_EQ(c.height, std::llround(4096 / kTwoPi * 2));
  // Fisheye: equidistant radius = density * psi_max; square.
  EXPECT_EQ(planned("equirect", e, "fisheye:fov=180"), (Size{2048, 2048}));
  EXPECT_EQ(planned("equirect", e, "fisheye:fov=360"), (Size{4096, 4096}));
  // Pinhole: focal = density.
  EXPECT_EQ(planned("equirect", e, "pinhole:hfov=90"), (Size{1304, 1304}));
  // Cube faces: face focal F/2 = density.
  EXPECT_EQ(planned("equirect", e, "cubemap"), (Size{6 * 1304, 1304}));
  EXPECT_EQ(planned("equirect", e, "cubemap:face=512,layout=cross"), (Size{4 * 512, 3 * 512}));
  // Maps: unit scale at their centre: Aitoff is 2 pi wide.
  EXPECT_EQ(planned("equirect", e, "aitoff"), e);
  // From a cube of 1584 faces: 792 px/rad.
  EXPECT_EQ(planned("cubemap", {6 * 1584, 1584}, "equirect"), (Size{4976, 2488}));
}

std::string geometry_error(const char* from, Size size, const char* to, ConvertOptions o = {}) {
  try {
    make_geometry(size, parse_spec(from), parse_spec(to), o);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ConversionGeometry, RefusesBadParameters) {
  ConvertOptions o;
  o.yaw = std::nan("");
  EXPECT_EQ(geometry_error("equirect", {64, 32}, "equirect", o), "yaw: nan (expected a finite angle in degrees)");
  o = {};
  o.size = Size{0, 10};
  EXPECT_EQ(geometry_error("equirect", {64, 32}, "equirect", o), "size: 0x10 (expected 1 to 2147483647 pixels a side)");
  EXPECT_EQ(geometry_error("cubemap", {600, 120}, "equirect"),
            "cubemap: layout=6x1 needs a 6F x 1F image with square faces; got 600x120 (check the "
            "size or the layout; a target's --face-size N gives N x N faces)");
  EXPECT_EQ(geometry_error("fisheye:fov=200,model=orthographic", {64, 64}, "equirect"),
            "fisheye: fov=200 is too wide for model=orthographic (expected <= 180)");
  EXPECT_EQ(geometry_error("equirect:lat0=60,vfov=90", {64, 32}, "equirect"),
            "equirect: lat0=60 with vfov=90 spans latitudes 15..105 (expected within [-90, 90])");
  EXPECT_EQ(geometry_error("pinhole:hfov=60,focal=100", {64, 64}, "equirect"),
            "pinhole: give hfov or focal, not both");
  // A tiny-fov source would ask for a gigantic default output.
  EXPECT_NE(geometry_error("fisheye:fov=0.001", {2048, 2048}, "equirect").find("give --size WxH"),
            std::string::npos);
}

}  // namespace
}  // namespace panoproj
