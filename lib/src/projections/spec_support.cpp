// Helpers the projection modules share (spec_support.hpp).
#include "projections/spec_support.hpp"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "panoproj/error.hpp"

namespace panoproj::spec_support {

ParamDef number(const char* key, const char* def, double lo, double hi, bool lo_open, bool hi_open, const char* help) {
  return {key, ParamType::Number, def, lo, hi, lo_open, hi_open, "", help};
}
ParamDef choice(const char* key, const char* def, const char* choices, const char* help) {
  return {key, ParamType::Choice, def, 0, 0, false, false, choices, help};
}
ParamDef coefficient(const char* key) {
  return number(key, "0", -kInf, kInf, true, true, "distortion coefficient (OpenCV's, theta in radians)");
}
ParamDef lon0() { return number("lon0", "0", -360, 360, false, false, "central longitude (deg)"); }
ParamDef lat0() { return number("lat0", "0", -90, 90, false, false, "central latitude (deg)"); }
ParamDef center(const char* key) {
  return number(key, "", -kInf, kInf, true, true,
                "centre in pixels, OpenCV convention (pixel centres at integers); default: the "
                "frame's centre");
}
ParamDef angle(const char* key, const char* def, const char* help) { return number(key, def, -360, 360, false, false, help); }
ParamDef map_aspect() {
  return choice("aspect", "keep", "keep|stretch",
                "keep: square pixels, the outline inscribed and centred; stretch: the outline fills the frame");
}

ParamDef map_hfov() {
  return number("hfov", "", 0, 360, true, false,
                "longitudes the width spans at the equator (deg; square pixels, centred); default: "
                "the whole outline");
}

void fail(const ProjectionSpec& s, const std::string& what) { throw Error(s.name() + ": " + what); }

double rad(const ProjectionSpec& s, const char* key) { return deg2rad(*s.number(key)); }

double center_of(const ProjectionSpec& s, const char* key, double extent) {
  return s.given(key) ? *s.number(key) + kCvPixelShift : 0.5 * extent;
}

void fail_fold(const ProjectionSpec& s, const char* coefficients, double fold, double half_field) {
  std::ostringstream o;
  o << coefficients << " fold the lens law back at theta=" << rad2deg(fold) << " deg, inside fov/2 = "
    << rad2deg(half_field) << " deg (give fov=" << std::floor(2 * rad2deg(fold) * 1e3) / 1e3
    << " or less: the law must increase up to the image circle)";
  fail(s, o.str());
}

std::array<double, 2> focal_lengths(const ProjectionSpec& s, double f0) {
  const double fx = s.given("fx") ? *s.number("fx") : s.given("fy") ? *s.number("fy") : f0;
  return {fx, s.given("fy") ? *s.number("fy") : fx};
}

void check_latitude_span(const ProjectionSpec& s, bool open) {
  const double top = *s.number("lat0") + 0.5 * *s.number("vfov");
  const double bottom = *s.number("lat0") - 0.5 * *s.number("vfov");
  const double lim = 90.0 + 1e-9;
  if ((open ? top >= 90.0 || bottom <= -90.0 : top > lim || bottom < -lim)) {
    std::ostringstream o;
    o << "lat0=" << *s.number("lat0") << " with vfov=" << *s.number("vfov") << " spans latitudes " << bottom << ".." << top
      << " (expected within " << (open ? "(-90, 90)" : "[-90, 90]") << ")";
    fail(s, o.str());
  }
}

Size framed_size(const ProjectionSpec& s, double w, double h) {
  auto px = [](double v) { return std::max<int64_t>(1, std::llround(v)); };
  const Size size{px(w), px(h)};
  if (!(w < 1e12 && h < 1e12) || size.width * size.height > kMaxDefaultPixels) {
    std::ostringstream o;
    o << std::fixed << std::setprecision(0) << "the default output size for " << s.str() << " would be " << w << "x" << h
      << " pixels (over " << (kMaxDefaultPixels >> 20) << " Mpx); give " << option_text("size") << " WxH";
    throw Error(o.str());
  }
  return size;
}

Size map_size(const ProjectionSpec& s, const MapFrame& frame, double density) {
  return framed_size(s, density * (frame.xmax - frame.xmin), density * (frame.ymax - frame.ymin));
}

}  // namespace panoproj::spec_support
