// Rig files of lenses (jobs/stitch/lens_rig.hpp) and the list of mappings they are written in
// (base/mapping_list.hpp): YAML block and flow styles and JSON give the same lenses; quoted commas
// stay in their value; bad rigs are refused naming the line.
#include <gtest/gtest.h>

#include "jobs/stitch/lens_rig.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

void expect_two_lenses(const LensRig& rig) {
  ASSERT_EQ(rig.lenses.size(), 2u);
  const RigLens& a = rig.lenses[0];
  const RigLens& b = rig.lenses[1];
  EXPECT_EQ(a.name, "front");
  EXPECT_EQ(a.spec, "fisheye:fov=200,model=equisolid");
  EXPECT_EQ(a.input, "frame.jpg");
  ASSERT_TRUE(a.rect.has_value());
  EXPECT_EQ(*a.rect, (PixelRect{0, 0, 1920, 1920}));
  EXPECT_EQ(b.name, "lens 2");
  EXPECT_EQ(*b.rect, (PixelRect{1920, 0, 3840, 1920}));
  EXPECT_EQ(*b.crop, (PixelRect{10, 20, 1910, 1920}));
  EXPECT_DOUBLE_EQ(b.yaw, 180);
  EXPECT_DOUBLE_EQ(b.pitch, -1.5);
  EXPECT_DOUBLE_EQ(b.roll, 0.25);
}

TEST(LensRig, YamlBlockFlowAndJsonGiveTheSameLenses) {
  expect_two_lenses(parse_lens_rig(
      "# a dual fisheye\nlenses:\n  - name: front\n    spec: fisheye:fov=200,model=equisolid\n"
      "    input: frame.jpg   # shared\n    rect: 1920x1920+0+0\n  - spec: "
      "'fisheye:fov=200,model=equisolid'\n    input: frame.jpg\n    rect: 1920x1920+1920+0\n"
      "    crop: 1900x1900+10+20\n    yaw: 180\n    pitch: -1.5\n    roll: 0.25\n",
      "a.yaml"));
  expect_two_lenses(parse_lens_rig(
      "- {name: front, spec: 'fisheye:fov=200,model=equisolid', input: frame.jpg, rect: "
      "1920x1920+0+0}\n- {spec: \"fisheye:fov=200,model=equisolid\", input: frame.jpg, rect: "
      "1920x1920+1920+0, crop: 1900x1900+10+20, yaw: 180, pitch: -1.5, roll: 0.25}\n",
      "b.yaml"));
  expect_two_lenses(parse_lens_rig(
      "{\"lenses\": [\n {\"name\": \"front\", \"spec\": \"fisheye:fov=200,model=equisolid\", "
      "\"input\": \"frame.jpg\", \"rect\": \"1920x1920+0+0\"},\n {\"spec\": "
      "\"fisheye:fov=200,model=equisolid\", \"input\": \"frame.jpg\", \"rect\": "
      "\"1920x1920+1920+0\", \"crop\": \"1900x1900+10+20\", \"yaw\": 180, \"pitch\": -1.5, "
      "\"roll\": 0.25}]}",
      "c.json"));
}

TEST(LensRig, BadRigsAreRefusedNamingTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"lenses:\n", "no lenses"},
      {"- {spec: equirect}\n", "line 1: lens 1 has no input"},
      {"- {input: a.jpg}\n- {spec: equirect}\n", "line 1: lens 1 has no spec"},
      {"- spec: equirect\n  input: a.jpg\n  pose: 3\n", "line 3: unknown key 'pose'"},
      {"- spec: equirect\n  input: a.jpg\n  yaw: 400\n", "line 3: yaw '400'"},
      {"- {spec: equirect, input: a.jpg, rect: 10x10+-1+0}\n", "rect '10x10+-1+0'"},
      {"- {spec: equirect, input: a.jpg, crop: 10x10+0+0x}\n", "crop '10x10+0+0x'"},
      {"[{\"spec\": \"equirect\", \"input\": \"a.jpg\"} {}]", "no ']'"},
      {"{\"views\": []}", "'views' (expected the key \"lenses\")"},
      {"[{\"spec\": \"equirect\", \"input\": \"a.jpg\"}] x", "text after the list"},
      {"spec: equirect\n", "expected a list of lenses"},
  };
  for (const auto& [text, needle] : cases) {
    try {
      parse_lens_rig(text, "r.yaml");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("r.yaml"), std::string::npos) << e.what();
    }
  }
  std::string many = "lenses:\n";
  for (size_t k = 0; k <= kMaxRigLenses; ++k) many += "- {spec: equirect, input: a.jpg}\n";
  EXPECT_THROW(parse_lens_rig(many, "r.yaml"), Error);
}

TEST(LensRig, RigFilesAreKnownByTheirExtension) {
  EXPECT_TRUE(is_rig_path("a/rig.yaml"));
  EXPECT_TRUE(is_rig_path("RIG.YML"));
  EXPECT_TRUE(is_rig_path("r.json"));
  EXPECT_FALSE(is_rig_path("p.pto"));
  EXPECT_FALSE(is_rig_path("yaml"));
}

}  // namespace
}  // namespace panoproj
