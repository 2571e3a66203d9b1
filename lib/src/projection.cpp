// Projection factories (parameter validation against the frame), default sizes and row forms.
#include "panoproj/projection.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <type_traits>

#include "panoproj/error.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {

// ---- Cubemap ------------------------------------------------------------------------------
std::array<int, 2> Cubemap::grid(CubeLayout layout) {
  switch (layout) {
    case CubeLayout::Files:
    case CubeLayout::Row6x1: return {6, 1};
    case CubeLayout::Column1x6: return {1, 6};
    case CubeLayout::Grid3x2: return {3, 2};
    case CubeLayout::Cross4x3: return {4, 3};
  }
  return {6, 1};
}

Cubemap::Cubemap(int64_t face_size, CubeLayout layout)
    : f_(face_size), fd_(static_cast<double>(face_size)), layout_(layout) {
  const auto g = grid(layout);
  cols_ = g[0];
  rows_ = g[1];
  size_ = {cols_ * f_, rows_ * f_};
  // Cell (column, row) of each face.
  std::array<std::array<int, 2>, 6> cells{};
  switch (layout) {
    case CubeLayout::Files:
    case CubeLayout::Row6x1:
      for (int i = 0; i < 6; ++i) cells[i] = {i, 0};
      break;
    case CubeLayout::Column1x6:
      for (int i = 0; i < 6; ++i) cells[i] = {0, i};
      break;
    case CubeLayout::Grid3x2:
      for (int i = 0; i < 6; ++i) cells[i] = {i % 3, i / 3};
      break;
    case CubeLayout::Cross4x3:
      cells = {{{1, 1}, {2, 1}, {3, 1}, {0, 1}, {1, 0}, {1, 2}}};
      break;
  }
  cell_face_.fill(-1);
  for (int i = 0; i < 6; ++i) {
    origin_[i] = {cells[i][0] * f_, cells[i][1] * f_};
    cell_face_[cells[i][1] * cols_ + cells[i][0]] = i;
  }
}

// ---- Bonne --------------------------------------------------------------------------------
Bonne::Bonne(Size size, double phi1, double lon0)
    : MapProjection(lon0), p1_(std::fabs(phi1)), sign_(phi1 < 0 ? -1.0 : 1.0),
      t_(std::tan(std::fabs(phi1))), cot_(0.0), small_(std::fabs(phi1) < kSmallPhi1) {
  if (!small_) cot_ = std::cos(p1_) / std::sin(p1_);
  // Bounding box: X peaks on the outline lambda = +-pi; Y is monotonic in |lambda| on each
  // parallel (|E| < pi), so its extremes lie on lambda = 0 or on the outline. Dense sampling
  // then golden-section refinement of each extreme.
  auto outline = [&](double phi, int which) {
    double X, Y;
    forward(kPi, phi, X, Y);
    return which == 0 ? X : (which == 1 ? Y : -Y);
  };
  double ext[3];
  for (int which = 0; which < 3; ++which) {
    constexpr int kSamples = 2048;
    int best = 0;
    double best_v = -HUGE_VAL;
    for (int i = 0; i <= kSamples; ++i) {
      const double v = outline(-kHalfPi + kPi * i / kSamples, which);
      if (v > best_v) best_v = v, best = i;
    }
    double a = -kHalfPi + kPi * std::max(0, best - 1) / kSamples;
    double b = -kHalfPi + kPi * std::min(kSamples, best + 1) / kSamples;
    const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 80; ++it) {
      const double c = b - gr * (b - a), d = a + gr * (b - a);
      if (outline(c, which) > outline(d, which)) b = d; else a = c;
    }
    ext[which] = std::max(best_v, outline(0.5 * (a + b), which));
  }
  // lambda = 0 reaches Y = +-pi/2 - phi1 (mirrored for a southern phi1).
  const double ymax = std::max(ext[1], sign_ > 0 ? kHalfPi - p1_ : p1_ + kHalfPi);
  const double ymin = std::min(-ext[2], sign_ > 0 ? -kHalfPi - p1_ : p1_ - kHalfPi);
  frame_ = {size, -ext[0], ext[0], ymin, ymax};
}

// ---- factories ----------------------------------------------------------------------------
namespace {

[[noreturn]] void fail(const ProjectionSpec& s, const std::string& what) {
  throw Error(s.name() + ": " + what);
}

double rad(const ProjectionSpec& s, const char* key) { return deg2rad(*s.number(key)); }

FisheyeModel fisheye_model(const std::string& m) {
  if (m == "equisolid") return FisheyeModel::Equisolid;
  if (m == "orthographic") return FisheyeModel::Orthographic;
  if (m == "stereographic") return FisheyeModel::Stereographic;
  return FisheyeModel::Equidistant;
}

CubeLayout cube_layout(const std::string& l) {
  if (l == "files") return CubeLayout::Files;
  if (l == "1x6") return CubeLayout::Column1x6;
  if (l == "3x2") return CubeLayout::Grid3x2;
  if (l == "cross") return CubeLayout::Cross4x3;
  return CubeLayout::Row6x1;
}

// A fisheye field `key` against the law's domain.
void check_fisheye_fov(const ProjectionSpec& s, const char* key, double fov) {
  const auto model = fisheye_model(s.choice("model"));
  std::ostringstream o;
  o << key << "=" << fov;
  if (model == FisheyeModel::Orthographic && fov > 180) fail(s, o.str() + " is too wide for model=orthographic (expected <= 180)");
  if (model == FisheyeModel::Stereographic && fov >= 360)
    fail(s, o.str() + " is not reachable with model=stereographic (expected < 360)");
}

void check_fisheye(const ProjectionSpec& s) {
  check_fisheye_fov(s, "fov", *s.number("fov"));
  if (s.given("radius") && s.choice("aspect") == "stretch")
    fail(s, "radius applies to aspect=keep only (stretch fills the frame)");
}

// The error for a lens law that `coefficients` make fold back at `fold` (radians off axis), inside
// the field's half angle `half_field`: it names the largest field that works.
[[noreturn]] void fail_fold(const ProjectionSpec& s, const char* coefficients, double fold, double half_field) {
  std::ostringstream o;
  o << coefficients << " fold the lens law back at theta=" << rad2deg(fold) << " deg, inside fov/2 = "
    << rad2deg(half_field) << " deg (give fov=" << std::floor(2 * rad2deg(fold) * 1e3) / 1e3
    << " or less: the law must increase up to the image circle)";
  fail(s, o.str());
}

// A calibrated camera's focal lengths (fx, fy): as given (one alone serves both), else f0.
std::array<double, 2> focal_lengths(const ProjectionSpec& s, double f0) {
  const double fx = s.given("fx") ? *s.number("fx") : s.given("fy") ? *s.number("fy") : f0;
  return {fx, s.given("fy") ? *s.number("fy") : fx};
}

// A Brown-Conrady spec's coefficients and field (theta_max): the field must end before the radial
// factor r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing, and the map's Jacobian must stay
// positive over it (tangential terms).
BrownConrady brown_of(const ProjectionSpec& s) {
  const std::array<double, 5> d{*s.number("k1"), *s.number("k2"), *s.number("p1"), *s.number("p2"), *s.number("k3")};
  // The radial factor's slope 1 + 3 k1 r^2 + 5 k2 r^4 + 7 k3 r^6: its first zero up to r_cap.
  auto slope = [&](double r) {
    const double r2 = r * r;
    return 1.0 + r2 * (3.0 * d[0] + r2 * (5.0 * d[1] + r2 * 7.0 * d[4]));
  };
  const double r_cap = std::tan(deg2rad(s.number("fov") ? 0.5 * *s.number("fov") : 80.0));
  const double fold = first_fold(slope, r_cap);
  if (fold >= 0 && s.number("fov")) fail_fold(s, "k1, k2, k3", std::atan(fold), 0.5 * rad(s, "fov"));
  const double theta_max = std::atan(fold >= 0 ? fold : r_cap);
  const BrownConrady cam({1, 1}, 1, 1, 0, 0, d, theta_max);
  for (int i = 0; i < 32; ++i)
    for (int a = 0; a < 64; ++a) {
      const double r = std::tan(theta_max) * (i + 0.5) / 32, phi = 2.0 * kPi * a / 64;
      double j[4];
      cam.jacobian(r * std::cos(phi), r * std::sin(phi), j);
      if (!(j[0] * j[3] - j[1] * j[2] > 0.0)) {
        std::ostringstream o;
        o << "p1, p2 fold the image " << rad2deg(std::atan(r)) << " deg off axis (expected a distortion without folds: "
          << "give a smaller fov)";
        fail(s, o.str());
      }
    }
  return cam;
}

// A lens spec's law and field (theta_max): the field must lie in the law's domain, where R
// increases (the polynomial laws: checked) and stays finite. PTLens's law depends on the frame
// (its radii are in units of half the shorter side): `frame`, or a square one for checks.
Lens lens_of(const ProjectionSpec& s, Size frame = {1, 1}) {
  LensLaw law;
  const std::string& n = s.name();
  double fx = 1.0;
  if (n == "kannala-brandt") {
    law = KannalaBrandtLaw{{*s.number("k1"), *s.number("k2"), *s.number("k3"), *s.number("k4")}};
  } else if (n == "double-sphere") {
    law = DoubleSphereLaw{*s.number("xi"), *s.number("alpha")};
  } else if (n == "unified") {
    law = UnifiedLaw{*s.number("xi")};
  } else if (n == "extended-unified") {
    law = ExtendedUnifiedLaw{*s.number("alpha"), *s.number("beta")};
  } else {
    const auto w = static_cast<double>(frame.width), h = static_cast<double>(frame.height);
    fx = 0.5 * w / std::tan(0.5 * rad(s, "hfov"));
    law = PTLensLaw{*s.number("a"), *s.number("b"), *s.number("c"), fx / (0.5 * std::min(w, h))};
  }
  const double limit = std::visit([](const auto& l) { return l.limit(); }, law);
  const bool bounded = std::visit([](const auto& l) { return l.bounded(); }, law);
  const auto* kb = std::get_if<KannalaBrandtLaw>(&law);
  const auto* pt = std::get_if<PTLensLaw>(&law);
  std::ostringstream o;
  // Default field: the whole domain where R stays finite up to its edge; else 180 degrees if the
  // domain is wider; PTLens (a rectilinear lens): up to where its law folds, at most 160.
  double theta_max = limit;
  if (s.number("fov")) {
    theta_max = 0.5 * rad(s, "fov");
  } else if (pt) {
    theta_max = deg2rad(80.0);
  } else if (!bounded) {
    if (limit <= kHalfPi) {
      o << "R grows without bound toward the model's domain edge at " << rad2deg(limit)
        << " deg off axis: give fov below " << 2 * rad2deg(limit);
      fail(s, o.str());
    }
    theta_max = std::fmin(kHalfPi, limit * (1 - 1e-3));  // short of an edge just past 90 degrees
  }
  if (bounded ? theta_max > limit * (1 + 1e-12) : theta_max >= limit * (1 - 1e-9)) {
    o << "fov=" << 2 * rad2deg(theta_max) << " is past the model's domain (expected fov " << (bounded ? "<= " : "< ")
      << 2 * rad2deg(limit) << ")";
    fail(s, o.str());
  }
  if (const double slope0 = std::visit([](const auto& l) { return l.slope0(); }, law); !(slope0 > 0)) {
    o << "the law does not increase from the centre (R'(0) = " << slope0
      << (pt ? "; expected a + b + c < 1)" : "; expected a positive value)");
    fail(s, o.str());
  }
  // Where a polynomial law stops increasing: refused inside a given field, the default's end.
  double fold = -1.0;
  if (kb) fold = first_fold([kb](double t) { return kb->slope(t); }, theta_max);
  if (pt) {
    const double u = first_fold([pt](double x) { return pt->slope(x); }, pt->s * std::tan(theta_max));
    fold = u < 0 ? -1.0 : std::atan(u / pt->s);
  }
  if (fold >= 0 && (kb || s.number("fov"))) fail_fold(s, kb ? "k1..k4" : "a, b, c", fold, theta_max);
  if (fold >= 0) theta_max = fold;
  const Lens lens({1, 1}, fx, fx, 0, 0, law, theta_max);
  if (!(std::isfinite(lens.rd_max()) && lens.rd_max() > 0)) {
    o << "the law reaches R = " << lens.rd_max() << " at fov/2 = " << rad2deg(theta_max)
      << " deg (expected a finite value: give a smaller fov" << (n == "kannala-brandt" ? " or smaller coefficients" : "") << ")";
    fail(s, o.str());
  }
  return lens;
}

// A dual fisheye's lens fields, rotations and feather (the frame is checked by make_projection):
// the feather must fit in the overlap, psi_0 + psi_1 - the angle between the lens axes (the
// overlap's width along the great circle through both axes; for back-to-back lenses, everywhere).
struct DualSpec {
  std::array<double, 2> psi;
  std::array<Eigen::Matrix3d, 2> rot;
  double feather;  // radians
};
DualSpec dual_of(const ProjectionSpec& s) {
  DualSpec d;
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

// The dual fisheye on a frame of `size`: lens k's circle inside its half (the halves must split
// the frame evenly).
DualFisheye dual_on(const ProjectionSpec& s, Size size) {
  const DualSpec d = dual_of(s);
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

void check_latitude_span(const ProjectionSpec& s, bool open) {
  const double top = *s.number("lat0") + 0.5 * *s.number("vfov");
  const double bottom = *s.number("lat0") - 0.5 * *s.number("vfov");
  const double lim = 90.0 + 1e-9;
  if ((open ? top >= 90.0 || bottom <= -90.0 : top > lim || bottom < -lim)) {
    std::ostringstream o;
    o << "lat0=" << *s.number("lat0") << " with vfov=" << *s.number("vfov")
      << " spans latitudes " << bottom << ".." << top << " (expected within "
      << (open ? "(-90, 90)" : "[-90, 90]") << ")";
    fail(s, o.str());
  }
}

void check_pinhole(const ProjectionSpec& s) {
  if (s.given("hfov") && s.given("focal")) fail(s, "give hfov or focal, not both");
  if (s.given("vfov") && s.given("focal")) fail(s, "give vfov or focal, not both");
}

// Validation that does not depend on the frame (shared by make_projection and default_size).
void check_spec(const ProjectionSpec& s) {
  switch (s.kind()) {
    case Kind::Pinhole: check_pinhole(s); break;
    case Kind::Fisheye: check_fisheye(s); break;
    case Kind::DualFisheye: dual_of(s); break;
    case Kind::Lens: lens_of(s); break;
    case Kind::BrownConrady: brown_of(s); break;
    case Kind::Equirect: check_latitude_span(s, false); break;
    case Kind::Cylindrical: check_latitude_span(s, true); break;
    default: break;
  }
}

}  // namespace

Projection make_projection(const ProjectionSpec& s, Size size) {
  check_spec(s);
  if (size.width < 1 || size.height < 1) {
    std::ostringstream o;
    o << "size " << size.width << "x" << size.height << " is empty (expected at least 1x1)";
    fail(s, o.str());
  }
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  auto cx = [&](const char* key, double extent) {
    return s.given(key) ? *s.number(key) + kCvPixelShift : 0.5 * extent;
  };
  switch (s.kind()) {
    case Kind::Pinhole: {
      double fx, fy;
      if (s.given("focal")) {
        fx = fy = *s.number("focal");
      } else if (s.given("hfov")) {
        fx = 0.5 * w / std::tan(0.5 * rad(s, "hfov"));
        fy = s.given("vfov") ? 0.5 * h / std::tan(0.5 * rad(s, "vfov")) : fx;
      } else if (s.given("vfov")) {
        fx = fy = 0.5 * h / std::tan(0.5 * rad(s, "vfov"));
      } else {
        fx = fy = 0.5 * w / std::tan(deg2rad(45.0));  // hfov 90
      }
      return Pinhole(size, fx, fy, cx("cx", w), cx("cy", h));
    }
    case Kind::Fisheye: {
      const double psi_max = 0.5 * rad(s, "fov");
      double rx, ry;
      if (s.choice("aspect") == "stretch") {
        rx = 0.5 * w;
        ry = 0.5 * h;
      } else {
        rx = ry = s.given("radius") ? *s.number("radius") : 0.5 * std::min(w, h);
      }
      return Fisheye(size, psi_max, fisheye_model(s.choice("model")), s.choice("clip") == "circle",
                     cx("cx", w), cx("cy", h), rx, ry);
    }
    case Kind::DualFisheye: return dual_on(s, size);
    case Kind::BrownConrady: {
      const BrownConrady unit = brown_of(s);
      const auto [fx, fy] = focal_lengths(s, 0.5 * w);
      return BrownConrady(size, fx, fy, cx("cx", w), cx("cy", h), unit.coefficients(), unit.theta_max());
    }
    case Kind::Lens: {
      const Lens unit = lens_of(s, size);
      if (s.name() == "ptlens") return Lens(size, unit.fx(), unit.fx(), cx("cx", w), cx("cy", h), unit.law(), unit.theta_max());
      // Default focal length: the image circle fills the shorter side.
      const auto [fx, fy] = focal_lengths(s, 0.5 * std::min(w, h) / unit.rd_max());
      return Lens(size, fx, fy, cx("cx", w), cx("cy", h), unit.law(), unit.theta_max());
    }
    case Kind::Equirect:
      return Equirect(size, rad(s, "hfov"), rad(s, "vfov"), rad(s, "lon0"), rad(s, "lat0"));
    case Kind::Cylindrical:
      return Cylindrical(size, rad(s, "hfov"), rad(s, "vfov"), rad(s, "lon0"), rad(s, "lat0"));
    case Kind::Cubemap: {
      const auto layout = cube_layout(s.choice("layout"));
      const auto g = Cubemap::grid(layout);
      const int64_t f = size.width / g[0];
      if (f * g[0] != size.width || f * g[1] != size.height) {
        std::ostringstream o;
        o << "layout=" << s.choice("layout") << " needs a " << g[0] << "F x " << g[1]
          << "F image with square faces; got " << size.width << "x" << size.height
          << " (check the size or the layout)";
        fail(s, o.str());
      }
      if (s.given("face") && static_cast<int64_t>(*s.number("face")) != f) {
        std::ostringstream o;
        o << "face=" << *s.number("face") << " does not match the image (faces of " << f
          << " px)";
        fail(s, o.str());
      }
      return Cubemap(f, layout);
    }
    case Kind::Aitoff: return Aitoff(size, rad(s, "lon0"));
    case Kind::Hammer: return Hammer(size, *s.number("w"), rad(s, "lon0"));
    case Kind::Bonne: return Bonne(size, rad(s, "phi1"), rad(s, "lon0"));
  }
  fail(s, "internal: unhandled projection kind");
}

Size default_size(const ProjectionSpec& s, double density) {
  check_spec(s);
  auto px = [](double v) { return std::max<int64_t>(1, std::llround(v)); };
  double w = 0, h = 0;
  switch (s.kind()) {
    case Kind::Pinhole: {
      // Focal length = density (pixels per radian on the axis).
      const double f = s.given("focal") ? *s.number("focal") : density;
      const double hf = s.given("hfov") ? rad(s, "hfov") : (s.given("vfov") ? 0.0 : deg2rad(90));
      const double vf = s.given("vfov") ? rad(s, "vfov") : hf;
      w = 2.0 * f * std::tan(0.5 * (hf > 0 ? hf : vf));
      h = 2.0 * f * std::tan(0.5 * vf);
      break;
    }
    case Kind::Fisheye: {
      const double r = s.given("radius")
                           ? *s.number("radius")
                           : density * Fisheye::law(fisheye_model(s.choice("model")),
                                                    0.5 * rad(s, "fov"));
      w = h = 2.0 * r;
      break;
    }
    case Kind::DualFisheye: {
      // Two circles of `density` pixels per radian at their centres, the larger one setting the
      // halves' size.
      const auto model = fisheye_model(s.choice("model"));
      const double fov2 = s.number("fov2") ? *s.number("fov2") : *s.number("fov");
      const double r0 = s.given("radius") ? *s.number("radius") : density * Fisheye::law(model, 0.5 * rad(s, "fov"));
      const double r1 = s.given("radius2") ? *s.number("radius2") : s.given("radius") ? r0 : density * Fisheye::law(model, 0.5 * deg2rad(fov2));
      const double r = std::max(r0, r1);
      const bool tb = s.choice("layout") == "top-bottom";
      w = tb ? 2.0 * r : 4.0 * r;
      h = tb ? 4.0 * r : 2.0 * r;
      // Halves of whole pixels.
      if (tb) h = 2.0 * static_cast<double>(px(0.5 * h));
      else w = 2.0 * static_cast<double>(px(0.5 * w));
      break;
    }
    case Kind::BrownConrady: {
      // The frame of a 90-degree undistorted pinhole at the given focal lengths, else at
      // `density` pixels per radian at the centre.
      brown_of(s);
      const auto [fx, fy] = focal_lengths(s, density);
      w = 2.0 * fx;
      h = 2.0 * fy;
      break;
    }
    case Kind::Lens: {
      if (s.name() == "ptlens") {  // a square frame (PTLens radii are in its half side)
        lens_of(s);
        w = h = 2.0 * density / (1.0 - *s.number("a") - *s.number("b") - *s.number("c")) * std::tan(0.5 * rad(s, "hfov"));
        break;
      }
      // The image circle's diameter at the given focal lengths, else at `density` pixels per
      // radian at the centre (f R'(0) = density).
      const Lens unit = lens_of(s);
      const auto [fx, fy] = focal_lengths(s, density / unit.center_density());
      w = 2.0 * fx * unit.rd_max();
      h = 2.0 * fy * unit.rd_max();
      break;
    }
    case Kind::Equirect:
      w = density * rad(s, "hfov");
      h = density * rad(s, "vfov");
      break;
    case Kind::Cylindrical: {
      const double top = rad(s, "lat0") + 0.5 * rad(s, "vfov");
      const double bottom = rad(s, "lat0") - 0.5 * rad(s, "vfov");
      w = density * rad(s, "hfov");
      h = density * (std::tan(top) - std::tan(bottom));
      break;
    }
    case Kind::Cubemap: {
      const auto g = Cubemap::grid(cube_layout(s.choice("layout")));
      const int64_t f = s.given("face") ? static_cast<int64_t>(*s.number("face")) : px(2 * density);
      return {f * g[0], f * g[1]};
    }
    case Kind::Aitoff:
    case Kind::Hammer:
    case Kind::Bonne: {
      // All three have unit scale at their centre: size the frame in plane units.
      const Projection unit = make_projection(s, {1000, 1000});
      const MapFrame& fr = std::visit(
          [](const auto& p) -> const MapFrame& {
            if constexpr (requires { p.frame(); }) return p.frame();
            else throw Error("internal: no map frame");
          },
          unit);
      w = density * (fr.xmax - fr.xmin);
      h = density * (fr.ymax - fr.ymin);
      break;
    }
  }
  const Size size{px(w), px(h)};
  if (!(w < 1e12 && h < 1e12) || size.width * size.height > kMaxDefaultPixels) {
    std::ostringstream o;
    o << std::fixed << std::setprecision(0) << "the default output size for " << s.str() << " would be " << w << "x"
      << h << " pixels (over " << (kMaxDefaultPixels >> 20) << " Mpx); give " << option_text("size") << " WxH";
    throw Error(o.str());
  }
  return size;
}

// ---- row forms ----------------------------------------------------------------------------
void to_ray_row(const Projection& p, double y, int64_t x0, int64_t n, Ray* rays, uint8_t* ok) {
  std::visit(
      [&](const auto& q) {
        for (int64_t i = 0; i < n; ++i) {
          ok[i] = q.to_ray(static_cast<double>(x0 + i) + 0.5, y, rays[i]) ? 1 : 0;
        }
      },
      p);
}

void to_pixel_row(const Projection& p, const Ray* rays, int64_t n, double* xs, double* ys,
                  uint8_t* ok) {
  std::visit(
      [&](const auto& q) {
        for (int64_t i = 0; i < n; ++i) {
          if (ok[i]) ok[i] = q.to_pixel(rays[i], xs[i], ys[i]) ? 1 : 0;
        }
      },
      p);
}

// ---- Rescaling --------------------------------------------------------------------------------
namespace {
// Fisheye q on a frame of `size`, its positions scaled by (sx, sy).
Fisheye fisheye_scaled(const Fisheye& q, Size size, double sx, double sy) {
  return Fisheye(size, q.psi_max(), q.model(), q.clip(), q.cx() * sx, q.cy() * sy, q.rx() * sx, q.ry() * sy);
}
}  // namespace

Projection rescaled(const Projection& p, Size size) {
  const Size old = size_of(p);
  const double sx = static_cast<double>(size.width) / static_cast<double>(old.width);
  const double sy = static_cast<double>(size.height) / static_cast<double>(old.height);
  return std::visit(
      [&](const auto& q) -> Projection {
        using P = std::decay_t<decltype(q)>;
        if constexpr (std::is_same_v<P, Pinhole>) {
          return Pinhole(size, q.fx() * sx, q.fy() * sy, q.cx() * sx, q.cy() * sy);
        } else if constexpr (std::is_same_v<P, Fisheye>) {
          return fisheye_scaled(q, size, sx, sy);
        } else if constexpr (std::is_same_v<P, DualFisheye>) {
          std::array<Fisheye, 2> lenses{q.lens(0), q.lens(1)};
          for (auto& l : lenses) l = fisheye_scaled(l, size, sx, sy);
          const DualFisheye d(size, q.top_bottom(), lenses, {q.rotation(0), q.rotation(1)}, q.feather());
          return q.only() >= 0 ? d.only(q.only()) : d;
        } else if constexpr (std::is_same_v<P, BrownConrady>) {
          return BrownConrady(size, q.fx() * sx, q.fy() * sy, q.cx() * sx, q.cy() * sy, q.coefficients(), q.theta_max());
        } else if constexpr (std::is_same_v<P, Lens>) {
          return Lens(size, q.fx() * sx, q.fy() * sy, q.cx() * sx, q.cy() * sy, q.law(), q.theta_max());
        } else if constexpr (std::is_same_v<P, Equirect>) {
          return Equirect(size, q.axis().hfov, q.vfov(), q.axis().lon0, q.lat_top() - 0.5 * q.vfov());
        } else if constexpr (std::is_same_v<P, Cylindrical>) {
          const double top = std::atan(q.t_top()), bottom = std::atan(q.t_bottom());
          return Cylindrical(size, q.axis().hfov, top - bottom, q.axis().lon0, 0.5 * (top + bottom));
        } else if constexpr (std::is_same_v<P, Cubemap>) {
          const auto g = Cubemap::grid(q.layout());
          if (size.width % g[0] != 0 || size.width / g[0] * g[1] != size.height || size.width < g[0])
            throw Error("a cubemap of " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                        " px does not hold whole square faces in its layout");
          return Cubemap(size.width / g[0], q.layout());
        } else if constexpr (std::is_same_v<P, Aitoff>) {
          return Aitoff(size, q.lon0());
        } else if constexpr (std::is_same_v<P, Hammer>) {
          return Hammer(size, q.w(), q.lon0());
        } else {
          return Bonne(size, q.mirror() * q.abs_phi1(), q.lon0());
        }
      },
      p);
}

}  // namespace panoproj
