// The dual-fisheye module (module.hpp): a 360 camera's two fisheye lenses side by side or top and
// bottom, each turned by its own rotation, blended across their overlap.
#include <algorithm>
#include <sstream>

#include "projections/module.hpp"
#include "panoproj/rotation.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

ParamDef lens_center(const char* key, int lens) {
  return number(key, "", -kInf, kInf, true, true,
                lens == 0 ? "lens 0's centre in the whole image's pixels, OpenCV convention; default: its half's centre"
                          : "lens 1's centre in the whole image's pixels, OpenCV convention; default: its half's centre");
}

std::vector<ProjectionDef> catalog() {
  return {
      {"dual-fisheye",
       "the two back-to-back fisheye lenses of a 360 camera, side by side or top/bottom, blended "
       "across their overlap",
       {number("fov", "190", 0, 360, true, false, "lens 0's full field of view (deg)"),
        number("fov2", "", 0, 360, true, false, "lens 1's full field of view (deg); default: fov"),
        choice("model", "equidistant", "equidistant|equisolid|orthographic|stereographic",
               "lens law of both lenses"),
        choice("layout", "side-by-side", "side-by-side|top-bottom",
               "lens 0 on the left (top), lens 1 on the right (bottom)"),
        number("radius", "", 0, kInf, true, true,
               "lens 0's image-circle radius in pixels; default: half its half's shorter side"),
        number("radius2", "", 0, kInf, true, true,
               "lens 1's image-circle radius in pixels; default: radius"),
        lens_center("cx", 0), lens_center("cy", 0), lens_center("cx2", 1), lens_center("cy2", 1),
        angle("yaw", "0", "lens 0's yaw (deg; as --yaw: positive turns it right)"),
        angle("pitch", "0", "lens 0's pitch (deg)"), angle("roll", "0", "lens 0's roll (deg)"),
        angle("yaw2", "180", "lens 1's yaw (deg; 180: back to back)"),
        angle("pitch2", "0", "lens 1's pitch (deg)"), angle("roll2", "0", "lens 1's roll (deg)"),
        number("feather", "", 0, 360, false, false,
               "width of the blend across the overlap (deg, centred on its midline); default: the "
               "whole overlap; 0: a hard cut")}}};
}

// The lens fields, rotations and feather (the frame is checked by make): the feather must fit in
// the overlap, psi_0 + psi_1 - the angle between the lens axes (the overlap's width along the
// great circle through both axes; for back-to-back lenses, everywhere).
struct Lenses {
  std::array<double, 2> psi;
  std::array<Eigen::Matrix3d, 2> rot;
  double feather;  // radians
};
Lenses lenses_of(const ProjectionSpec& s) {
  Lenses d;
  const double fov2 = s.number("fov2") ? *s.number("fov2") : *s.number("fov");
  check_fisheye_fov(s, "fov", *s.number("fov"));
  check_fisheye_fov(s, "fov2", fov2);
  d.psi = {0.5 * rad(s, "fov"), 0.5 * deg2rad(fov2)};
  d.rot = {rotation_from_ypr(*s.number("yaw"), *s.number("pitch"), *s.number("roll")),
           rotation_from_ypr(*s.number("yaw2"), *s.number("pitch2"), *s.number("roll2"))};
  const Ray a = d.rot[0].col(2), b = d.rot[1].col(2);
  const double overlap = d.psi[0] + d.psi[1] - std::atan2(a.cross(b).norm(), a.dot(b));
  d.feather = s.number("feather") ? rad(s, "feather") : std::max(0.0, overlap);
  if (d.feather > std::max(0.0, overlap) + 1e-12) {
    std::ostringstream o;
    o << "feather=" << *s.number("feather") << " is wider than the lenses' overlap of " << rad2deg(std::max(0.0, overlap))
      << " deg (fov/2 + fov2/2 - the angle between the lens axes): give feather <= " << rad2deg(std::max(0.0, overlap))
      << (overlap > 0 ? "" : ", or wider lenses");
    fail(s, o.str());
  }
  return d;
}

// Lens k's circle inside its half (the halves must split the frame evenly).
Projection make(const ProjectionSpec& s, Size size) {
  const Lenses d = lenses_of(s);
  const bool tb = s.choice("layout") == "top-bottom";
  const int64_t along = tb ? size.height : size.width;
  if (along % 2 != 0) {
    std::ostringstream o;
    o << "layout=" << s.choice("layout") << " needs an even " << (tb ? "height" : "width") << " to split into two lenses; got "
      << size.width << "x" << size.height;
    fail(s, o.str());
  }
  const double hw = tb ? static_cast<double>(size.width) : 0.5 * static_cast<double>(size.width);
  const double hh = tb ? 0.5 * static_cast<double>(size.height) : static_cast<double>(size.height);
  const double r0 = s.given("radius") ? *s.number("radius") : 0.5 * std::min(hw, hh);
  const double r[2] = {r0, s.given("radius2") ? *s.number("radius2") : r0};
  const char* keys[2][3] = {{"cx", "cy", "radius"}, {"cx2", "cy2", "radius2"}};
  std::array<Fisheye, 2> lenses{Fisheye({1, 1}, 1, FisheyeModel::Equidistant, true, 0, 0, 1, 1),
                                Fisheye({1, 1}, 1, FisheyeModel::Equidistant, true, 0, 0, 1, 1)};
  const double mid = 0.5 * static_cast<double>(along);
  for (int k = 0; k < 2; ++k) {
    const double cx = s.given(keys[k][0]) ? *s.number(keys[k][0]) + kCvPixelShift : (tb ? 0.5 : 0.5 + k) * hw;
    const double cy = s.given(keys[k][1]) ? *s.number(keys[k][1]) + kCvPixelShift : (tb ? 0.5 + k : 0.5) * hh;
    const double c = tb ? cy : cx;
    if (k == 0 ? c + r[k] > mid * (1 + 1e-9) : c - r[k] < mid * (1 - 1e-9)) {
      std::ostringstream o;
      o << "lens " << k << "'s image circle (" << keys[k][tb ? 1 : 0] << "=" << c - kCvPixelShift << ", " << keys[k][2] << "="
        << r[k] << ") crosses the middle " << (tb ? "y" : "x") << "=" << mid << " into the other lens's half (expected "
        << (k == 0 ? "centre + radius <= " : "centre - radius >= ") << mid << ")";
      fail(s, o.str());
    }
    lenses[k] = Fisheye(size, d.psi[k], fisheye_model(s.choice("model")), true, cx, cy, r[k], r[k]);
  }
  return DualFisheye(size, tb, lenses, d.rot, d.feather);
}

// Two circles of `density` pixels per radian at their centres, the larger one setting the
// halves' size (of whole pixels).
Size size_for(const ProjectionSpec& s, double density) {
  const auto model = fisheye_model(s.choice("model"));
  const double fov2 = s.number("fov2") ? *s.number("fov2") : *s.number("fov");
  const double r0 = s.given("radius") ? *s.number("radius") : density * Fisheye::law(model, 0.5 * rad(s, "fov"));
  const double r1 = s.given("radius2") ? *s.number("radius2") : s.given("radius") ? r0 : density * Fisheye::law(model, 0.5 * deg2rad(fov2));
  const double r = std::max(r0, r1);
  const bool tb = s.choice("layout") == "top-bottom";
  double w = tb ? 2.0 * r : 4.0 * r;
  double h = tb ? 4.0 * r : 2.0 * r;
  auto px = [](double v) { return std::max<int64_t>(1, std::llround(v)); };
  if (tb) h = 2.0 * static_cast<double>(px(0.5 * h));
  else w = 2.0 * static_cast<double>(px(0.5 * w));
  return framed_size(s, w, h);
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  const auto& q = std::get<DualFisheye>(p);
  std::array<Fisheye, 2> lenses{q.lens(0), q.lens(1)};
  for (auto& l : lenses) l = fisheye_scaled(l, size, sx, sy);
  return DualFisheye(size, q.top_bottom(), lenses, {q.rotation(0), q.rotation(1)}, q.feather());
}

// Each ray back through the lens it lies deeper inside (in the overlap, the other half of the
// frame): lenses to 360 degrees and to 0.01, a turned top/bottom pair of unequal lenses.
std::vector<ProjectionCase> cases() {
  return {{"dual-fisheye:fov=200", {{2, 1}, kPhotoFrame, kHugeFrame}},
          {"dual-fisheye:fov=359.99,model=equisolid", {kPhotoFrame}},
          {"dual-fisheye:fov=0.01", {kPhotoFrame}},
          {"dual-fisheye:fov=190,fov2=220,layout=top-bottom,yaw2=175,pitch2=5,roll2=90", {{2048, 4096}}}};
}

}  // namespace

const ProjectionModule kDualFisheyeModule{catalog,
                                          [](const ProjectionSpec& s) { lenses_of(s); },
                                          make,
                                          size_for,
                                          rescale,
                                          cases,
                                          nullptr,
                                          [](const Projection& p) {
                                            SamplingFacts f = framed_facts(p);
                                            f.dual = &std::get<DualFisheye>(p);
                                            return f;
                                          }};

}  // namespace panoproj
