// Spec strings: parsing, defaults from the one table, and one clear error per kind of mistake.
#include "panoproj/spec.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "panoproj/error.hpp"
#include "test_support.hpp"

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

// The error of binding a spec to a frame (the module's checks).
std::string make_error_of(const char* text, Size size) {
  try {
    make_projection(parse_spec(text), size);
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
  // Every catalogue name, in catalogue order (a new projection's module adds its own).
  std::string names;
  for (const auto& d : projection_catalog()) names += (names.empty() ? "" : ", ") + std::string(d.name);
  const std::string listed = "expected one of the " + std::to_string(projection_catalog().size()) +
                             " that panoproj info lists: " + names + ")";
  EXPECT_EQ(error_of("fishey"), "unknown projection 'fishey' (did you mean fisheye? " + listed);
  EXPECT_EQ(error_of("perspective"),
            "unknown projection 'perspective' (did you mean pinhole? " + listed);
  EXPECT_EQ(error_of("zzz"), "unknown projection 'zzz' (" + listed);
  EXPECT_EQ(
      names.rfind(
          "pinhole, fisheye, dual-fisheye, brown-conrady, kannala-brandt, double-sphere, unified, ",
          0),
      0u);
  EXPECT_EQ(error_of("fisheye:fov=nan"), "fisheye: fov=nan is not finite (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=inf"), "fisheye: fov=inf is not finite (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=-10"), "fisheye: fov=-10 is out of range (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=361"), "fisheye: fov=361 is out of range (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=0"), "fisheye: fov=0 is out of range (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("fisheye:fov=12x"), "fisheye: fov=12x is not a number (expected 0 < fov <= 360)");
  EXPECT_EQ(error_of("pinhole:hfov=180"), "pinhole: hfov=180 is out of range (expected 0 < hfov < 180)");
  EXPECT_EQ(error_of("fisheye:model=fish"),
            "fisheye: model=fish is not a valid value (expected one of "
            "equidistant|equisolid|orthographic|stereographic|thoby)");
  EXPECT_EQ(error_of("fisheye:fov"), "fisheye: 'fov' is not key=value");
  EXPECT_EQ(error_of("fisheye:zoom=2"),
            "fisheye: unknown key 'zoom' (expected one of: fov, model, k2, clip, aspect, radius, "
            "cx, cy, stereo, eye, response, ev, wb, "
            "vignetting, vignetting_centre)");
  EXPECT_EQ(error_of("fisheye:fov=100,fov=120"), "fisheye: fov given twice");
  EXPECT_EQ(error_of("cubemap:face=10.5"),
            "cubemap: face=10.5 is not a whole number (expected 1 <= face <= 1.07374e+09)");
  EXPECT_EQ(error_of("aitoff:w=1"),
            "aitoff: unknown key 'w' (expected one of: lon0, aspect, hfov, stereo, eye, response, "
            "ev, wb, vignetting, "
            "vignetting_centre)");
  EXPECT_EQ(error_of("bonne:phi1=91"), "bonne: phi1=91 is out of range (expected -90 <= phi1 <= 90)");
  EXPECT_EQ(make_error_of("cubemap:order=frblu", {6, 1}),
            "cubemap: order=frblu is not six distinct letters of f r b l u d (front right back left up down), e.g. rludfb");
  EXPECT_EQ(make_error_of("cubemap:order=ffblud", {6, 1}),
            "cubemap: order=ffblud is not six distinct letters of f r b l u d (front right back left up down), e.g. rludfb");
  EXPECT_EQ(make_error_of("cubemap:rot=000004", {6, 1}), "cubemap: rot=000004 is not six digits 0-3 (quarter turns clockwise per slot), e.g. 000313");
  EXPECT_EQ(error_of("cubemap:pad=0.5"), "cubemap: pad=0.5 is out of range (expected 0 <= pad <= 0.4)");
  EXPECT_EQ(make_error_of("cubemap:pad=0.1,pad_px=3", {6, 1}), "cubemap: pad and pad_px both given (give one: pad_px = pad x cell size)");
  EXPECT_EQ(make_error_of("cubemap:border=ffmpeg", {6, 1}), "cubemap: border=ffmpeg needs layout=eac");
  EXPECT_EQ(error_of("equirect:stereo=lr"), "equirect: stereo=lr is not a valid value (expected one of mono|tb|sbs)");
}

}  // namespace
class SpecFile : public test::TempDirTest {
 protected:
  // "@" and the path of a new file holding text. (Appended, not "@" + path: gcc 12 warns
  // falsely on that, its bug 105329.)
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(path(name), std::ios::binary) << text;
    std::string at = "@";
    at += path(name);
    return at;
  }
};

TEST_F(SpecFile, JsonAndYamlGiveTheSpecTheirKeysSpell) {
  const std::string inline_text = "kannala-brandt:fov=200,fx=620.5,cx=959.2,k1=0.0361,k2=-0.0112";
  const std::string json = write("lens.json", R"({ "projection": "kannala-brandt", "fov": 200, "fx": 620.5,
      "cx": 959.2, "k1": 0.0361, "k2": -0.0112 })");
  const std::string yaml = write("lens.yaml", "---\n# calibrated 2026-11-01\nprojection: kannala-brandt\nfov: 200\n"
                                              "fx: 620.5   # px\ncx: \"959.2\"\nk1: 0.0361\nk2: -0.0112\n");
  const std::string want = parse_spec(inline_text).str();
  EXPECT_EQ(parse_spec(json).str(), want);
  EXPECT_EQ(parse_spec(" " + yaml).str(), want);
  // A name carrying keys of its own.
  EXPECT_EQ(parse_spec(write("f.json", R"({"projection": "fisheye:fov=200", "model": "equisolid"})")).str(),
            "fisheye:fov=200,model=equisolid");
}

TEST_F(SpecFile, BadFilesNameTheFileAndTheFix) {
  auto error_of = [](const std::string& text) {
    try {
      parse_spec(text);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string none = "@";
  none += path("none.json");
  const std::string missing = error_of(none);
  EXPECT_NE(missing.find("the spec file " + path("none.json") + " does not exist"), std::string::npos) << missing;
  EXPECT_NE(error_of(write("a.json", R"({"fx": 1})")).find("no \"projection\" key"), std::string::npos);
  EXPECT_NE(error_of(write("b.json", R"({"projection": "unified", "xi": {"a": 1}})")).find("not a string or number"),
            std::string::npos);
  EXPECT_NE(error_of(write("c.json", R"({"projection": "unified" "xi": 1})")).find("no ',' or '}'"), std::string::npos);
  EXPECT_NE(error_of(write("d.yaml", "projection: unified\nxi\n")).find("line 2 is not 'key: value'"), std::string::npos);
  EXPECT_NE(error_of(write("e.yaml", "projection: unified\nlens:\n  xi: 1\n")).find("line 2 has no value"),
            std::string::npos);
  // Keys are checked as in spec text.
  EXPECT_NE(error_of(write("f.yaml", "projection: unified\nzeta: 1\n")).find("unknown key 'zeta'"), std::string::npos);
  EXPECT_NE(error_of(write("g.yaml", "projection: \"@x\"\n")).find("cannot name another"), std::string::npos);
}

// A key the code asks for but the catalogue does not declare is a bug, not the user's input: an
// InternalError, which a handler of Error (the user's mistakes) does not catch.
TEST(Spec, AKeyMissingFromTheCatalogueIsAnInternalError) {
  const ProjectionSpec s = parse_spec("fisheye:fov=200");
  EXPECT_THROW(s.number("hfov"), InternalError);
  EXPECT_THROW(s.choice("layout"), InternalError);
  bool caught_as_user_error = false;
  try {
    s.number("hfov");
  } catch (const Error&) {
    caught_as_user_error = true;
  } catch (const InternalError& e) {
    EXPECT_EQ(std::string(e.what()), "internal error: fisheye has no key hfov");
  }
  EXPECT_FALSE(caught_as_user_error);
}

}  // namespace panoproj
