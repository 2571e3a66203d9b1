// Spec strings: parsing, defaults from the one table, and one clear error per kind of mistake.
#include "panoproj/spec.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

std::string error_of(const char* text) {
  try {
    parse_spec(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Spec, ParsesNamesKeysAndDefaults) {
  const ProjectionSpec s = parse_spec("fisheye:fov=210, model=equisolid");
  EXPECT_EQ(s.kind(), Kind::Fisheye);
  EXPECT_EQ(*s.number("fov"), 210.0);
  EXPECT_EQ(s.choice("model"), "equisolid");
  EXPECT_EQ(s.choice("clip"), "circle");  // table default
  EXPECT_FALSE(s.number("radius").has_value());  // derived default
  EXPECT_EQ(s.str(), "fisheye:fov=210,model=equisolid");
  EXPECT_EQ(*parse_spec("eckert-greifendorff").number("w"), 0.25);
  EXPECT_EQ(parse_spec("eckert-greifendorff").kind(), Kind::Hammer);
  EXPECT_EQ(*parse_spec("hammer").number("w"), 0.5);
  EXPECT_EQ(*parse_spec("equirect").number("hfov"), 360.0);
  EXPECT_EQ(parse_spec("cubemap:layout=cross").choice("layout"), "cross");
}

TEST(Spec, EveryCatalogEntryParsesWithItsDefaults) {
  for (const auto& d : projection_catalog()) {
    const ProjectionSpec s = parse_spec(d.name);
    EXPECT_EQ(s.name(), d.name);
    for (const auto& p : d.params) {
      if (*p.default_text && p.type != ParamType::Choice) {
        EXPECT_TRUE(std::isfinite(*s.number(p.key))) << d.name << " " << p.key;
      }
    }
  }
}

TEST(Spec, ErrorsNameTheValueAndWhatWasExpected) {
  EXPECT_EQ(error_of("fishey"),
            "unknown projection 'fishey' (expected one of: pinhole, brown-conrady, fisheye, kannala-brandt, "
            "double-sphere, unified, extended-unified, ptlens, equirect, cylindrical, cubemap, aitoff, "
            "hammer, eckert-greifendorff, bonne)");
  EXPECT_EQ(error_of("fisheye:fov=nan"), "fisheye: fov=nan is not finite (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=inf"), "fisheye: fov=inf is not finite (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=-10"), "fisheye: fov=-10 is out of range (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=361"), "fisheye: fov=361 is out of range (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=0"), "fisheye: fov=0 is out of range (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=12x"), "fisheye: fov=12x is not a number (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("pinhole:hfov=180"), "pinhole: hfov=180 is out of range (expected 0 < hfov < 180)");
  EXPECT_EQ(error_of("fisheye:model=fish"),
            "fisheye: model=fish is not a valid value (expected one of "
            "equidistant|equisolid|orthographic|stereographic)");
  EXPECT_EQ(error_of("fisheye:fov"), "fisheye: 'fov' is not key=value");
  EXPECT_EQ(error_of("fisheye:zoom=2"),
            "fisheye: unknown key 'zoom' (expected one of: fov, model, clip, aspect, radius, cx, cy)");
  EXPECT_EQ(error_of("fisheye:fov=100,fov=120"), "fisheye: fov given twice");
  EXPECT_EQ(error_of("cubemap:face=10.5"),
            "cubemap: face=10.5 is not a whole number (expected 1 <= face <= 1.07374e+09)");
  EXPECT_EQ(error_of("aitoff:w=1"), "aitoff: unknown key 'w' (expected one of: lon0)");
  EXPECT_EQ(error_of("bonne:phi1=91"), "bonne: phi1=91 is out of range (expected -90 <= phi1 <= 90)");
}

}  // namespace
}  // namespace panoproj
