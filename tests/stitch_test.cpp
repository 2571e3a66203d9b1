// Hugin projects (jobs/stitch): the .pto reader and its refusals, the panorama's and lenses'
// specs against libpano13's scalings, crops and masks, the layers' extent, and the job end to end
// against analytic truth. (Against nona itself: python/tests/test_stitch.py.)
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>

#include "job_support.hpp"
#include "jobs/stitch/layer_masks.hpp"
#include "jobs/stitch/pano_spec.hpp"
#include "jobs/stitch/pto_project.hpp"
#include "jobs/stitch/stitch.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

using test::TempDirTest;

const char* kProject = R"(# hugin project file
#hugin_ptoversion 2
p f2 w3000 h1500 v360  k0 E11.5 R0 S100,2900,50,1450 n"TIFF_m c:LZW r:CROP"
m i5

# image lines
#-hugin  cropFactor=1
i w4000 h3000 f0 v50 Ra0 Rb0 Rc0 Rd0 Re0 Eev11.5 Er1 Eb1 r1.5 p-2 y30 TrX0 TrY0 TrZ0 Tpy0 Tpp0 j0 a0.01 b-0.02 c0.005 d12 e-7 g0 t0 Va1 Vb0 Vc0 Vd0 Vx0 Vy0  Vm5 S10,3990,20,2980 n"a b.jpg"
#-hugin  cropFactor=1 disabled
i w4000 h3000 f0 v=0 Ra=0 Rb=0 Rc=0 Rd=0 Re=0 Eev12 Er=0 Eb=0 r0 p0 y70 TrX0 TrY0 TrZ0 Tpy0 Tpp0 j=0 a=0 b=0 c=0 d=0 e=0 g=0 t=0 Va=0 Vb=0 Vc=0 Vd=0 Vx=0 Vy=0  Vm5 n"c.jpg"
i w1000 h1000 f2 v180 r0 p90 y0 j2 a0 b0 c0 d0 e0 g0 t0 S0,1000,0,1000 n"/abs/fish.png"

# specify variables that should be optimized
v y1
v

# control points
c n0 N1 x10 y20 X30 Y40 t0

k i0 t0 p"10 10 100 10 50 90"
k i2 t4 p"0 0 20 0 20 20 0 20"
)";

TEST(PtoProject, ReadsHuginsLinesLinksAndMasks) {
  const PtoProject p = parse_pto(kProject, "a.pto");
  EXPECT_EQ(p.pano.projection, 2);
  EXPECT_EQ(p.pano.width, 3000);
  EXPECT_EQ(p.pano.height, 1500);
  EXPECT_EQ(p.pano.hfov, 360);
  ASSERT_TRUE(p.pano.crop);
  EXPECT_EQ(p.pano.crop->right, 2900);
  EXPECT_EQ(p.pano.output, "TIFF_m c:LZW r:CROP");
  EXPECT_EQ(p.interpolator, 5);
  ASSERT_EQ(p.images.size(), 3u);
  const PtoImage& a = p.images[0];
  EXPECT_EQ(a.name, "a b.jpg");
  EXPECT_EQ(a.yaw, 30);
  EXPECT_EQ(a.pitch, -2);
  EXPECT_EQ(a.roll, 1.5);
  EXPECT_EQ(a.d, 12);
  EXPECT_FALSE(a.disabled);
  EXPECT_EQ(a.exposure, 11.5);
  EXPECT_EQ(p.pano.exposure, 11.5);
  EXPECT_FALSE(p.pano.hdr);
  EXPECT_EQ(a.vignetting_mode, 5);
  ASSERT_TRUE(a.crop);
  EXPECT_EQ(a.crop->left, 10);
  // Links take image 0's values; the lens and stack are image 0's.
  const PtoImage& b = p.images[1];
  EXPECT_TRUE(b.disabled);
  EXPECT_EQ(b.hfov, 50);
  EXPECT_EQ(b.a, 0.01);
  EXPECT_EQ(b.e, -7);
  EXPECT_EQ(b.yaw, 70);
  EXPECT_EQ(b.lens, 0);
  EXPECT_EQ(b.stack, 0);
  EXPECT_EQ(b.exposure, 12);
  EXPECT_EQ(b.red, 1);  // Er=0: image 0's
  EXPECT_EQ(p.images[2].lens, 2);
  EXPECT_EQ(p.images[2].stack, 2);
  ASSERT_EQ(p.masks.size(), 2u);
  EXPECT_EQ(p.masks[1].type, 4);
  EXPECT_EQ(p.masks[1].xy.size(), 8u);
}

// Each bad input: the message names the file, the line, the token and what was expected.
TEST(PtoProject, RefusesEachBadInputNamingItsLineAndToken) {
  const std::string p = "p f2 w400 h200 v360\n";
  const std::string i = "i w40 h30 f0 v50 r0 p0 y0 n\"x.jpg\"\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {p + "q f0\n", "a.pto:2: line: unknown line 'q f0' (expected p, m, i, k, v or c)"},
      {p + "image w1\n", "a.pto:2: line: unknown line 'image w1'"},
      {p + "i w40 h30 f0 v50 zz3 n\"x\"\n",
       "a.pto:2: i line: unknown token 'zz3' (expected one of"},
      {p + "i w40 h30 f0 vnan n\"x\"\n", "a.pto:2: i line: token vnan: expected a finite number"},
      {p + "i w40 h30 f0 v1e999 n\"x\"\n", "token v1e999: expected a finite number"},
      {p + "i w40 h30 f0 vinf n\"x\"\n", "token vinf: expected a finite number"},
      {p + "i w40 h30 f0 v0 n\"x\"\n",
       "a.pto:2: i line: token v: expected a field of view in (0, 360]"},
      {p + "i w40 h30 f0 v500 n\"x\"\n", "token v: expected a field of view in (0, 360]"},
      {p + "i w0 h30 f0 v50 n\"x\"\n", "token w0: expected a whole number in [1, 2147483647]"},
      {p + "i w40.5 h30 f0 v50 n\"x\"\n", "token w40.5: expected a whole number"},
      {p + "i w40 h30 f0 v50\n", "a.pto:2: i line: an image needs n (its file)"},
      {p + "i h30 f0 v50 n\"x\"\n", "an image needs w and h"},
      {p + "i w40 h30 f0 n\"x\"\n", "an image needs v (its field of view)"},
      {p + "i w40 h30 f0 v50 n\"x\n", "token n: no closing quote"},
      {p + "i w40 h30 f0 v50 v60 n\"x\"\n", "token v given twice"},
      {p + "i w40 h30 f0 v50 S0,50,0,30 n\"x\"\n",
       "token S0,50,0,30: the crop must be a non-empty rectangle inside the 40x30 frame"},
      {p + "i w40 h30 f0 v50 S10,5,0,30 n\"x\"\n", "the crop must be a non-empty rectangle"},
      {p + "i w40 h30 f0 v50 S10,20 n\"x\"\n", "expected left,right,top,bottom"},
      {p + "i w40 h30 f0 v50 TrX0.5 n\"x\"\n",
       "token TrX: translation (mosaic mode) is not supported"},
      {p + "i w40 h30 f0 v50 C0,10,0,10 n\"x\"\n", "token C (a cut frame) is not supported"},
      {p + "i w40 h30 f0 v=3 n\"x\"\n", "a.pto:2: i line: token v=3: no such image"},
      {p + "i w40 h30 f0 v=1 n\"x\"\ni w40 h30 f0 v=0 n\"y\"\n",
       "token v=1: the links form a cycle"},
      {p + i + "k i0 t0 p\"1 1 2 2\"\n",
       "a.pto:3: k line: token p: a mask needs at least 3 points (x y pairs), got 4 numbers"},
      {p + i + "k i0 t0 p\"1 1 2 2 3\"\n", "a mask needs at least 3 points"},
      {p + i + "k i1 t0 p\"1 1 2 2 3 3\"\n",
       "a.pto:3: k line: token i1: no such image (1 before it)"},
      {p + i + "k i0 t9 p\"1 1 2 2 3 3\"\n", "token t9: expected a whole number in [0, 4]"},
      {p + i + "k i0 t0 p\"1 1 2 nan 3 3\"\n", "token pnan: expected a finite number"},
      {p + i + "k t0 p\"1 1 2 2 3 3\"\n", "a mask needs i (its image) and p (its points)"},
      {"p f2 w400 h200\n" + i, "a.pto:1: p line: the panorama needs v (its field of view)"},
      {"p f2 h200 v360\n" + i, "the panorama needs w and h"},
      {"p f2 w400 h200 v360 S0,500,0,200\n" + i,
       "token S0,500,0,200: the crop must be a non-empty rectangle inside the 400x200"},
      {"p f2 w400 h200 v360 T\"INT7\"\n" + i, "token T\"INT7\": expected UINT8, UINT16 or FLOAT"},
      {p + p + i, "a.pto:2: p line: a second p line"},
      {i, "a.pto: no p line (the panorama)"},
      {p, "a.pto: no i lines (the images)"},
      {p + "m i9\n" + i, "a.pto:2: m line: token i9: expected a whole number in [0, 7]"},
      {p + "i w40 h30 f0 v50 n\"x" + '\0' + "y\"\n", "a NUL byte: not a text project"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_pto(text, "a.pto");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
          << e.what() << "\nexpected: " << expected;
    }
  }
}

// A project of a million image lines (20 MB) stops at the bound, in bounded time; one over the
// byte bound is refused before it is read.
TEST(PtoProject, AMillionImagesAreRefusedAtTheBound) {
  std::string text = "p f2 w400 h200 v360\n";
  const std::string line = "i w4 h3 f0 v50 n\"x\"\n";
  text.reserve(text.size() + line.size() * 1000000);
  for (int k = 0; k < 1000000; ++k) text += line;
  const auto start = std::chrono::steady_clock::now();
  try {
    parse_pto(text, "big.pto");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("big.pto:65538: i line: more than 65536 images"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
  try {
    parse_pto(std::string(static_cast<size_t>(kMaxPtoBytes) + 1, '#'), "huge.pto");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(
        std::string(e.what()).find("huge.pto: a project of 67108865 bytes (at most 67108864)"),
        std::string::npos);
  }
}

PtoProject pano_of(int f, double v, int64_t w = 1000, int64_t h = 500,
                   const std::string& more = "") {
  return parse_pto("p f" + std::to_string(f) + " w" + std::to_string(w) + " h" + std::to_string(h) +
                       " v" + std::to_string(v) + " " + more + "\ni w40 h30 f0 v50 n\"x\"\n",
                   "a.pto");
}

// libpano13's scaling: the panorama's right edge, on the horizon, is hfov/2 from the centre (its
// longitude for the cylinders and maps, its angle off the axis for the others); the centre looks
// ahead, square pixels (the vertical scale at the centre equals the horizontal).
TEST(PanoSpec, EachFormatPutsHalfItsFieldAtTheEdgeWithSquarePixels) {
  const std::vector<std::pair<int, double>> formats{
      {0, 120}, {1, 200}, {2, 360},  {3, 200},  {4, 200},  {5, 300},  {6, 120},  {7, 360},
      {8, 360}, {9, 300}, {11, 360}, {14, 180}, {15, 300}, {19, 200}, {20, 200}, {21, 360}};
  for (const auto& [f, v] : formats) {
    const PtoProject p = pano_of(f, v, 1000, 400);
    const Projection q = make_projection(parse_spec(pano_spec(p)), {1000, 400});
    Ray centre, edge, up;
    ASSERT_TRUE(to_ray(q, 500, 200, centre)) << f;
    EXPECT_NEAR((centre - Ray(0, 0, 1)).norm(), 0, 1e-9) << f;
    ASSERT_TRUE(to_ray(q, 1000, 200, edge)) << f;
    EXPECT_NEAR(rad2deg(std::acos(std::clamp(edge.z(), -1.0, 1.0))), v / 2, 1e-7)
        << "f" << f << " " << pano_spec(p);
    Ray right;
    ASSERT_TRUE(to_ray(q, 500.5, 200, right) && to_ray(q, 500, 199.5, up)) << f;
    const double step = std::acos(right.dot(centre));  // (to the third order of the half pixel)
    EXPECT_NEAR(step, std::acos(up.dot(centre)), 1e-5 * step) << f;
  }
}

TEST(PanoSpec, RefusesWhatPanoprojLacksNamingTheToken) {
  const std::vector<std::pair<PtoProject, std::string>> cases{
      {pano_of(10, 100),
       "a.pto:1: p line: token f10: this panorama projection is not supported (0-9, 11, 14, 15, "
       "19, 20 and 21 are)"},
      {pano_of(12, 100),
       "token f12: libpano13's Panini (f12) is not the Panini projection vertically: use f19"},
      {pano_of(16, 100), "token f16: this panorama projection is not supported"},
      {pano_of(0, 180), "token f0: a rectilinear panorama needs v below 180"},
      {pano_of(2, 360, 1000, 600),
       "token f2: an equirect panorama of v360 at 1000x600 spans more than 180 degrees"},
      {pano_of(19, 200, 1000, 500, "P\"100 10 0\""),
       "token f19: the General Panini's tops and bots"},
  };
  for (const auto& [p, expected] : cases) {
    try {
      pano_spec(p);
      ADD_FAILURE() << expected;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  PtoProject p = pano_of(2, 360);
  p.images[0].lens_type = 5;
  EXPECT_THROW(
      {
        try {
          image_spec(p, p.images[0]);
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find(
                        "a.pto:2: i line: token f5: this lens type is not supported"),
                    std::string::npos);
          throw;
        }
      },
      Error);
}

// An image's lens: the centre of the frame (shifted by d, e) looks along the image's axis, which
// the rotation points at (yaw, pitch) in the panorama; the half width is hfov/2 off axis (no
// polynomial); with b, a ray at ideal radius r lands at r (1 - b + b r^2) (r in half the shorter
// side).
TEST(ImageSpec, EachLensTypeMeetsLibpano13sScaling) {
  for (int f : {0, 1, 2, 3, 4, 8, 10, 20, 21}) {
    PtoProject p = pano_of(2, 360);
    PtoImage& im = p.images[0];
    im.lens_type = f, im.width = 600, im.height = 400, im.hfov = f == 4 ? 120 : 100, im.d = -7,
    im.e = -3;
    im.yaw = 40, im.pitch = 10;
    const Projection lens = make_projection(parse_spec(image_spec(p, im)), {600, 400});
    const Ray axis = rotation_from_ypr(40, 10, 0) * Ray(0, 0, 1);
    double x, y;
    ASSERT_TRUE(to_pixel(lens, image_rotation(im) * axis, x, y)) << f;
    EXPECT_NEAR(x, 293, 1e-9) << f;
    EXPECT_NEAR(y, 197, 1e-9) << f;
    Ray edge;
    ASSERT_TRUE(to_ray(lens, 593, 197, edge)) << f;
    EXPECT_NEAR(rad2deg(std::acos(edge.z())), im.hfov / 2, 1e-9) << f;
  }
  PtoProject p = pano_of(2, 360);
  PtoImage& im = p.images[0];
  im.width = 600, im.height = 400, im.hfov = 90, im.b = 0.1;
  const Projection lens = make_projection(parse_spec(image_spec(p, im)), {600, 400});
  const double f = 300;  // hfov 90 over 600 px
  const double r = 0.8;  // in units of 200 px
  const double t = std::atan(r * 200 / f);
  double x, y;
  ASSERT_TRUE(to_pixel(lens, Ray(std::sin(t), 0, std::cos(t)), x, y));
  EXPECT_NEAR(x - 300, r * 200 * (1 - 0.1 + 0.1 * r * r), 1e-9);
}

TEST(LayerMasks, PolygonsCropsAndWhereEachMaskTypeApplies) {
  const std::vector<double> concave{0, 0, 10, 0, 10, 10, 5, 2, 0, 10};
  EXPECT_TRUE(inside_polygon(concave, 2, 1));
  EXPECT_FALSE(inside_polygon(concave, 5, 5));  // in the notch
  EXPECT_FALSE(inside_polygon(concave, 11, 1));
  PtoImage circle;
  circle.lens_type = 2, circle.width = 100, circle.height = 100,
  circle.crop = PtoRect{10, 90, 0, 100};
  EXPECT_TRUE(inside_crop(circle, 50, 50));
  EXPECT_TRUE(inside_crop(circle, 50, 11));
  EXPECT_FALSE(inside_crop(circle, 12, 12));  // inside the rectangle, outside the circle
  const PtoProject p = parse_pto(
      "p f2 w400 h200 v360\n"
      "i w40 h30 f0 v50 j0 n\"a\"\ni w40 h30 f0 v=0 j=0 n\"b\"\ni w40 h30 f0 v60 j2 n\"c\"\n"
      "k i0 t1 p\"1 1 2 1 2 2\"\nk i0 t2 p\"1 1 2 1 2 2\"\nk i0 t3 p\"1 1 2 1 2 2\"\nk i2 t4 p\"1 "
      "1 2 1 2 2\"\n"
      "k i0 t4 p\"1 1 2 1 2 2\"\n",
      "a.pto");
  // Image 1 (image 0's stack and lens): the include mask (t1) and the stack's exclude mask (t2)
  // through the panorama, image 0's lens mask in its own pixels; image 2: t1 and t3 (outside the
  // stack), its own lens mask.
  const auto types = [&](const std::vector<PanoExclusion>& v) {
    std::vector<int> t;
    for (const PanoExclusion& e : v) t.push_back(e.mask->type);
    return t;
  };
  EXPECT_EQ(types(pano_exclusions(p, 1)), (std::vector<int>{1, 2}));
  EXPECT_EQ(types(pano_exclusions(p, 2)), (std::vector<int>{1, 3}));
  EXPECT_TRUE(pano_exclusions(p, 0).empty());
  EXPECT_EQ(image_masks(p, 1).size(), 1u);
  EXPECT_EQ(image_masks(p, 1)[0]->type, 4);
  EXPECT_EQ(image_masks(p, 2).size(), 1u);
  EXPECT_EQ(image_masks(p, 0).size(), 2u);  // its t2 and its t4
}

// The image's alpha: cleared exactly where the crop and the pixel-centre polygon tests say, for
// a file at the project's size and one twice as large (its centres mapped back).
TEST(LayerMasks, TheSourcesAlphaIsThePerPixelTests) {
  const PtoProject p = parse_pto(
      "p f2 w400 h200 v360\ni w40 h30 f0 v50 S3,37,2,27 n\"a\"\n"
      "k i0 t0 p\"5 5 30 4 20 25 12 15\"\nk i0 t4 p\"25 20 39 20 39 29 25 29 32 24\"\n",
      "a.pto");
  for (const double scale : {1.0, 2.0}) {
    const Size size{static_cast<int64_t>(40 * scale), static_cast<int64_t>(30 * scale)};
    Image im(size, 2, PixelType::U8, 1);
    for (int64_t y = 0; y < size.height; ++y)
      for (int64_t x = 0; x < size.width; ++x) test::set(im, x, y, 1, 1.0);
    mask_source(p, 0, scale, scale, im);
    int64_t cleared = 0;
    for (int64_t y = 0; y < size.height; ++y)
      for (int64_t x = 0; x < size.width; ++x) {
        const double hx = (x + 0.5) / scale - 0.5, hy = (y + 0.5) / scale - 0.5;
        const bool keep = inside_crop(p.images[0], hx, hy) &&
                          !inside_polygon(p.masks[0].xy, hx, hy) &&
                          !inside_polygon(p.masks[1].xy, hx, hy);
        ASSERT_EQ(test::get(im, x, y, 1), keep ? 255 : 0) << scale << " " << x << "," << y;
        cleared += !keep;
      }
    EXPECT_GT(cleared, 300 * scale * scale);
  }
}

class Stitch : public TempDirTest {
 protected:
  std::string project(const std::string& text) {
    const std::string path = this->path("p" + std::to_string(projects_++) + ".pto");
    std::ofstream(path) << text;
    return path;
  }
  int projects_ = 0;
};

// An equirect image (f4, v360) onto an equirect panorama of its size, turned by yaw 90: the
// layer is the image rolled by a quarter turn, exactly (nearest: the same pixels; bilinear at
// integer shifts: the same).
TEST_F(Stitch, AnEquirectImageTurnedAQuarterIsItsRolledPixels) {
  Image src = test::pattern({64, 32}, 3, PixelType::U8, -1);
  write_image(src, path("e.png"), {});
  for (const char* interp : {"i6", "i5"}) {
    const std::string pto = project(std::string("p f2 w64 h32 v360 n\"TIFF_m c:NONE r:CROP\"\nm ") +
                                    interp + "\ni w64 h32 f4 v360 r0 p0 y90 n\"e.png\"\n");
    const Arguments args = test::job_args("stitch", {{"project", pto}, {"output", path("")}});
    const StitchPlan plan = plan_stitch(args, StitchMade::LayerArrays);
    const RenderedLayer r = render_layer(plan, plan.layers[0]);
    ASSERT_EQ(r.image.size(), (Size{64, 32}));
    EXPECT_EQ(r.x, 0);
    for (int64_t y = 0; y < 32; ++y)
      for (int64_t x = 0; x < 64; ++x) {
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(test::get(r.image, x, y, c), test::get(src, (x + 64 - 16) % 64, y, c))
              << interp << x << "," << y;
        ASSERT_EQ(test::get(r.image, x, y, 3), 255);
      }
  }
}

// Layers keep each image's samples unless the project (T) or --depth says otherwise.
TEST_F(Stitch, LayersKeepTheImagesDepthUnlessTold) {
  write_image(test::pattern({60, 40}, 3, PixelType::U16, -1), path("deep.png"), {});
  const std::string body = "i w60 h40 f0 v50 r0 p0 y0 n\"deep.png\"\n";
  const auto depth_of = [&](const std::string& pano,
                            std::vector<std::pair<const char*, OptionValue>> more) {
    more.push_back({"project", project(pano + body)});
    more.push_back({"output", path("")});
    const StitchPlan plan = plan_stitch(test::job_args("stitch", more), StitchMade::LayerArrays);
    return render_layer(plan, plan.layers[0]).image.type();
  };
  EXPECT_EQ(depth_of("p f2 w400 h200 v360\n", {}), PixelType::U16);
  EXPECT_EQ(depth_of("p f2 w400 h200 v360 T\"UINT8\"\n", {}), PixelType::U8);
  EXPECT_EQ(depth_of("p f2 w400 h200 v360 T\"UINT8\"\n", {{"depth", std::string("float")}}),
            PixelType::F32);
}

// The job: one layer file per image, placed where the render says; refusals leave nothing.
TEST_F(Stitch, WritesALayerPerImageAndRefusesBadInputsWritingNothing) {
  write_image(test::pattern({60, 40}, 3, PixelType::U8, -1), path("a.png"), {});
  write_image(test::pattern({120, 80}, 3, PixelType::U8, -1), path("big.png"), {});
  write_image(test::pattern({60, 60}, 3, PixelType::U8, -1), path("square.png"), {});
  const std::string text =
      "p f2 w400 h200 v360 n\"TIFF_m c:NONE r:CROP\"\nm i5\n"
      "i w60 h40 f0 v50 r0 p0 y0 n\"a.png\"\ni w60 h40 f0 v50 r0 p0 y90 d3 n\"a.png\"\n";
  const std::string pto = project(text);
  const Report r =
      test::run_job("stitch", test::job_args("stitch", {{"project", pto}, {"output", path("l_")}}));
  ASSERT_EQ(test::list(r, "layers").size(), 2u);
  EXPECT_TRUE(std::filesystem::exists(path("l_0000.tif")) &&
              std::filesystem::exists(path("l_0001.tif")));
  const Image back = read_image(path("l_0001.tif"));
  const auto& offset = test::list(test::item(test::list(r, "layers")[1]), "offset");
  EXPECT_EQ(back.size(), test::size(test::item(test::list(r, "layers")[1]), "size"));
  EXPECT_EQ(back.channels(), 4);
  EXPECT_GT(std::get<int64_t>(offset[0].value), 200);  // yaw 90: right of the centre
  // Another file of the project's aspect is scaled to it; another aspect is refused.
  const Report scaled = test::run_job(
      "stitch",
      test::job_args("stitch",
                     {{"project", pto},
                      {"output", path("s_")},
                      {"images", std::vector<std::string>{path("big.png"), path("a.png")}}}));
  EXPECT_EQ(test::list(scaled, "layers").size(), 2u);
  const std::vector<std::pair<std::vector<std::pair<const char*, OptionValue>>, std::string>> bad{
      {{{"project", pto}, {"output", path("l_")}}, "l_0000.tif exists"},
      {{{"project", pto},
        {"output", path("x_")},
        {"images", std::vector<std::string>{path("square.png"), path("a.png")}}},
       "square.png: 60x60 where the project (line 3) says 60x40: another aspect cannot be scaled "
       "to it"},
      {{{"project", pto},
        {"output", path("x_")},
        {"images", std::vector<std::string>{path("a.png")}}},
       "images: 1 files for a project of 2 images"},
      {{{"project", pto}, {"output", path("x_")}, {"image", int64_t{2}}},
       "image: 2 (the project has images 0 to 1)"},
      {{{"project", project(text + "i w60 h40 f0 v50 n\"gone.png\"\n")}, {"output", path("x_")}},
       "gone.png"},
      {{{"project", project("p f2 w400000 h200000 v360\ni w60 h40 f0 v50 n\"a.png\"\n")},
        {"output", path("x_")},
        {"memory_limit", std::string("64M")}},
       "memory"},
  };
  for (const auto& [given, expected] : bad) {
    try {
      test::run_job("stitch", test::job_args("stitch", given));
      ADD_FAILURE() << expected;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(path("x_0000.tif"))) << expected;
  }
}

}  // namespace
}  // namespace panoproj
