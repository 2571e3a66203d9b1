// The projection table and the spec-string parser.
#include "panoproj/spec.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

constexpr double kInf = HUGE_VAL;

ParamDef number(const char* key, const char* def, double lo, double hi, bool lo_open,
                bool hi_open, const char* help) {
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

ParamDef lens_center(const char* key, int lens) {
  return number(key, "", -kInf, kInf, true, true,
                lens == 0 ? "lens 0's centre in the whole image's pixels, OpenCV convention; default: its half's centre"
                          : "lens 1's centre in the whole image's pixels, OpenCV convention; default: its half's centre");
}
ParamDef angle(const char* key, const char* def, const char* help) { return number(key, def, -360, 360, false, false, help); }

// fov, fx, fy, cx, cy, then the law's own keys. fov_default "": the law's whole domain.
std::vector<ParamDef> lens_params(const char* fov_default, std::vector<ParamDef> law) {
  std::vector<ParamDef> p{
      number("fov", fov_default, 0, 360, true, false,
             "full field of view across the image circle (deg); default: the model's whole domain if R stays finite there, else 180"),
      number("fx", "", 0, kInf, true, true, "focal length in pixels along x; default: the image circle fills the shorter side"),
      number("fy", "", 0, kInf, true, true, "focal length in pixels along y; default: fx"),
      center("cx"), center("cy")};
  p.insert(p.end(), law.begin(), law.end());
  return p;
}
std::vector<ProjectionDef> make_catalog() {
  const ParamDef pin_hfov = number("hfov", "", 0, 180, true, true,
                                   "horizontal field of view (deg); default 90 unless focal or "
                                   "vfov is given");
  const ParamDef pin_vfov = number("vfov", "", 0, 180, true, true,
                                   "vertical field of view (deg); default: square pixels");
  return {
      {"pinhole", Kind::Pinhole, "rectilinear camera (fov < 180 deg)",
       {pin_hfov, pin_vfov,
        number("focal", "", 0, kInf, true, true, "focal length in pixels (instead of hfov)"),
        center("cx"), center("cy")}},
      {"brown-conrady", Kind::BrownConrady,
       "calibrated pinhole camera with OpenCV's radial and tangential distortion (k1, k2, p1, p2, k3)",
       {number("fov", "", 0, 180, true, true,
               "full field of view the model is used in (deg); default: up to where the radial distortion folds, at most 160"),
        number("fx", "", 0, kInf, true, true, "focal length in pixels along x; default: half the width (hfov 90 undistorted)"),
        number("fy", "", 0, kInf, true, true, "focal length in pixels along y; default: fx"), center("cx"), center("cy"),
        coefficient("k1"), coefficient("k2"), coefficient("p1"), coefficient("p2"), coefficient("k3")}},
      {"fisheye", Kind::Fisheye, "fisheye lens with a radial law, fov up to 360 deg",
       {number("fov", "180", 0, 360, true, false, "full field of view across the image circle"),
        choice("model", "equidistant", "equidistant|equisolid|orthographic|stereographic",
               "lens law (orthographic: fov <= 180; stereographic: fov < 360)"),
        choice("clip", "circle", "circle|none",
               "circle: pixels outside the image circle are invalid; none: keep rays past fov/2"),
        choice("aspect", "keep", "keep|stretch",
               "keep: a circle of square pixels; stretch: an ellipse filling the frame"),
        number("radius", "", 0, kInf, true, true,
               "image-circle radius in pixels (aspect=keep); default: half the shorter side"),
        center("cx"), center("cy")}},
      {"dual-fisheye", Kind::DualFisheye,
       "the two back-to-back fisheye lenses of a 360 camera, side by side or top/bottom, blended across their overlap",
       {number("fov", "190", 0, 360, true, false, "lens 0's full field of view (deg)"),
        number("fov2", "", 0, 360, true, false, "lens 1's full field of view (deg); default: fov"),
        choice("model", "equidistant", "equidistant|equisolid|orthographic|stereographic", "lens law of both lenses"),
        choice("layout", "side-by-side", "side-by-side|top-bottom", "lens 0 on the left (top), lens 1 on the right (bottom)"),
        number("radius", "", 0, kInf, true, true, "lens 0's image-circle radius in pixels; default: half its half's shorter side"),
        number("radius2", "", 0, kInf, true, true, "lens 1's image-circle radius in pixels; default: radius"),
        lens_center("cx", 0), lens_center("cy", 0), lens_center("cx2", 1), lens_center("cy2", 1),
        angle("yaw", "0", "lens 0's yaw (deg; rotation.hpp's convention)"), angle("pitch", "0", "lens 0's pitch (deg)"),
        angle("roll", "0", "lens 0's roll (deg)"), angle("yaw2", "180", "lens 1's yaw (deg; 180: back to back)"),
        angle("pitch2", "0", "lens 1's pitch (deg)"), angle("roll2", "0", "lens 1's roll (deg)"),
        number("feather", "", 0, 360, false, false,
               "width of the blend across the overlap (deg, centred on its midline); default: the whole overlap; 0: a hard cut")}},
      {"kannala-brandt", Kind::Lens, "calibrated fisheye, OpenCV's fisheye model (k1..k4), fov up to 360 deg",
       lens_params("180", {coefficient("k1"), coefficient("k2"), coefficient("k3"), coefficient("k4")})},
      {"double-sphere", Kind::Lens, "calibrated fisheye, Double Sphere model (Usenko et al. 2018)",
       lens_params("", {number("xi", "0", -1, 1, false, false, "xi: the second sphere's offset"),
                        number("alpha", "0.5", 0, 1, false, false, "alpha")})},
      {"unified", Kind::Lens, "calibrated fisheye or catadioptric, unified model (Mei and Rives 2007)",
       lens_params("", {number("xi", "1", 0, kInf, false, true, "xi: the sphere's offset (0: pinhole, 1: stereographic)")})},
      {"extended-unified", Kind::Lens, "calibrated fisheye, extended unified model (Khomutenko et al. 2016)",
       lens_params("", {number("alpha", "0.5", 0, 1, false, false, "alpha"),
                        number("beta", "1", 0, kInf, true, true, "beta (1: the unified model)")})},
      {"ptlens", Kind::Lens,
       "rectilinear lens with Panorama Tools' a, b, c radial polynomial (lensfun's ptlens model)",
       {number("hfov", "90", 0, 180, true, true, "horizontal field of view of the ideal (undistorted) pinhole (deg)"),
        number("fov", "", 0, 180, true, true,
               "full field of view the model is used in (deg); default: up to where the polynomial folds, at most 160"),
        number("a", "0", -kInf, kInf, true, true, "a of r_src = (a r^3 + b r^2 + c r + 1 - a - b - c) r_dst"),
        number("b", "0", -kInf, kInf, true, true, "b"), number("c", "0", -kInf, kInf, true, true, "c"),
        center("cx"), center("cy")}},
      {"equirect", Kind::Equirect, "equirectangular (spherical) panorama, full or partial",
       {number("hfov", "360", 0, 360, true, false, "longitude span (deg)"),
        number("vfov", "180", 0, 180, true, false, "latitude span (deg)"), lon0(), lat0()}},
      {"cylindrical", Kind::Cylindrical, "cylindrical panorama (vertical extent vfov < 180 deg)",
       {number("hfov", "360", 0, 360, true, false, "longitude span (deg)"),
        number("vfov", "100", 0, 180, true, true, "vertical span (deg), linear in tan(latitude)"),
        lon0(), lat0()}},
      {"cubemap", Kind::Cubemap, "six 90-degree faces: front right back left up down",
       {choice("layout", "6x1", "files|6x1|1x6|3x2|cross",
               "files: six images (path pattern with {face} and/or {index}); cross is 4x3"),
        {"face", ParamType::Integer, "", 1, 1 << 30, false, false, "",
         "face size in pixels; default: from the source's resolution"}}},
      {"aitoff", Kind::Aitoff, "Aitoff world map (2:1 ellipse)", {lon0()}},
      {"hammer", Kind::Hammer, "Hammer(-Wagner) equal-area world map",
       {number("w", "0.5", 0, 1, true, true, "Wagner's W (0.5: Hammer, 0.25: Eckert-Greifendorff)"),
        lon0()}},
      {"eckert-greifendorff", Kind::Hammer, "Eckert-Greifendorff equal-area map (Hammer W = 0.25)",
       {number("w", "0.25", 0, 1, true, true, "Wagner's W"), lon0()}},
      {"bonne", Kind::Bonne, "Bonne equal-area map (phi1 = 0: sinusoidal; 90: Werner)",
       {number("phi1", "45", -90, 90, false, false, "standard parallel (deg)"), lon0()}},
  };
}

std::string list_names() {
  std::string s;
  for (const auto& d : projection_catalog()) s += (s.empty() ? "" : ", ") + std::string(d.name);
  return s;
}

std::string range_text(const ParamDef& p) {
  std::ostringstream o;
  if (p.type == ParamType::Choice) return std::string("one of ") + p.choices;
  if (std::isfinite(p.lo)) o << p.lo << (p.lo_open ? " < " : " <= ");
  o << p.key;
  if (std::isfinite(p.hi)) o << (p.hi_open ? " < " : " <= ") << p.hi;
  if (!std::isfinite(p.lo) && !std::isfinite(p.hi)) o << " finite";
  return o.str();
}

// Checks one value against its definition; returns the canonical text.
std::string validate(const ProjectionDef& d, const ParamDef& p, const std::string& text) {
  const std::string where = std::string(d.name) + ": " + p.key + "=" + text;
  if (p.type == ParamType::Choice) {
    std::string choices = std::string("|") + p.choices + "|";
    if (text.empty() || text.find('|') != std::string::npos ||
        choices.find("|" + text + "|") == std::string::npos)
      throw Error(where + " is not a valid value (expected " + range_text(p) + ")");
    return text;
  }
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size())
    throw Error(where + " is not a number (expected " + range_text(p) + ")");
  if (!std::isfinite(v)) throw Error(where + " is not finite (expected " + range_text(p) + ")");
  if (p.type == ParamType::Integer && v != std::floor(v))
    throw Error(where + " is not a whole number (expected " + range_text(p) + ")");
  const bool lo_ok = p.lo_open ? v > p.lo : v >= p.lo;
  const bool hi_ok = p.hi_open ? v < p.hi : v <= p.hi;
  if (!lo_ok || !hi_ok) throw Error(where + " is out of range (expected " + range_text(p) + ")");
  return text;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return std::string(s.substr(b, e - b + 1));
}

}  // namespace

const std::vector<ProjectionDef>& projection_catalog() {
  static const std::vector<ProjectionDef> catalog = make_catalog();
  return catalog;
}

const ProjectionDef& projection_def(Kind kind, std::string_view name) {
  for (const auto& d : projection_catalog())
    if (d.kind == kind && (name.empty() || name == d.name)) return d;
  throw Error("unknown projection: " + std::string(name));
}

ProjectionSpec::ProjectionSpec(const ProjectionDef& def, std::map<std::string, std::string> values)
    : def_(&def), name_(def.name), values_(std::move(values)) {}

std::optional<double> ProjectionSpec::number(std::string_view key) const {
  for (const auto& p : def_->params) {
    if (key != p.key) continue;
    auto it = values_.find(std::string(key));
    const std::string text = it != values_.end() ? it->second : p.default_text;
    if (text.empty()) return std::nullopt;
    return std::strtod(text.c_str(), nullptr);
  }
  throw Error(std::string("internal: ") + def_->name + " has no key " + std::string(key));
}

std::string ProjectionSpec::choice(std::string_view key) const {
  for (const auto& p : def_->params) {
    if (key != p.key) continue;
    auto it = values_.find(std::string(key));
    return it != values_.end() ? it->second : p.default_text;
  }
  throw Error(std::string("internal: ") + def_->name + " has no key " + std::string(key));
}

std::string ProjectionSpec::str() const {
  std::string s = name_;
  char sep = ':';
  for (const auto& p : def_->params) {
    auto it = values_.find(p.key);
    if (it == values_.end()) continue;
    s += sep + std::string(p.key) + "=" + it->second;
    sep = ',';
  }
  return s;
}

ProjectionSpec parse_spec(std::string_view text) {
  if (const std::string t = trim(text); !t.empty() && t[0] == '@') {
    const std::string from_file = spec_from_file(t.substr(1));
    if (!from_file.empty() && from_file[0] == '@') throw Error(t + ": a spec file cannot name another");
    return parse_spec(from_file);
  }
  const auto colon = text.find(':');
  const std::string name = trim(text.substr(0, colon));
  const ProjectionDef* def = nullptr;
  for (const auto& d : projection_catalog())
    if (name == d.name) def = &d;
  if (!def)
    throw Error("unknown projection '" + name + "' (expected one of: " + list_names() + ")");

  std::map<std::string, std::string> values;
  if (colon != std::string_view::npos) {
    std::string_view rest = text.substr(colon + 1);
    while (true) {
      const auto comma = rest.find(',');
      const std::string item = trim(rest.substr(0, comma));
      const auto eq = item.find('=');
      if (eq == std::string::npos)
        throw Error(std::string(def->name) + ": '" + item + "' is not key=value");
      const std::string key = trim(item.substr(0, eq)), value = trim(item.substr(eq + 1));
      const ParamDef* p = nullptr;
      for (const auto& q : def->params)
        if (key == q.key) p = &q;
      if (!p) {
        std::string keys;
        for (const auto& q : def->params) keys += (keys.empty() ? "" : ", ") + std::string(q.key);
        throw Error(std::string(def->name) + ": unknown key '" + key + "' (expected one of: " +
                    (keys.empty() ? "none" : keys) + ")");
      }
      if (values.count(key)) throw Error(std::string(def->name) + ": " + key + " given twice");
      values[key] = validate(*def, *p, value);
      if (comma == std::string_view::npos) break;
      rest = rest.substr(comma + 1);
    }
  }
  return ProjectionSpec(*def, std::move(values));
}

}  // namespace panoproj
