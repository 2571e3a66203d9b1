// Rigs of perspective views (views.hpp): cube, rings and a YAML file's list of views.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>

#include "base/input_check.hpp"
#include "base/mapping_list.hpp"
#include "base/text.hpp"
#include "jobs/views/views.hpp"
#include "panoproj/conventions.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/options.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {
namespace {

constexpr size_t kMaxViews = 1000;
constexpr int64_t kMaxViewSide = 65536;
constexpr size_t kMaxRigFile = size_t{1} << 20;

double number(const std::string& text, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
    throw Error(what + ": '" + shown(text) + "' (expected a finite number)");
  return v;
}

int64_t whole(const std::string& text, const std::string& what, int64_t lo, int64_t hi) {
  const double v = number(text, what);
  if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
    throw Error(what + ": " + shown(text) + " (expected a whole number from " + std::to_string(lo) +
                " to " + std::to_string(hi) + ")");
  return static_cast<int64_t>(v);
}

void check_view(const ViewSpec& v, const std::string& where) {
  if (v.name.empty() || v.name.size() > 64 ||
      v.name.find_first_not_of(
          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") != std::string::npos)
    throw Error(where + "name '" + shown(v.name) +
                "' (expected 1 to 64 letters, digits, '_' or '-': it goes into file names)");
  const std::string of = where + "view " + v.name + ": ";
  for (auto [angle, key] : {std::pair{v.yaw, "yaw"}, {v.pitch, "pitch"}, {v.roll, "roll"}})
    if (!(std::abs(angle) <= 360))
      throw Error(of + key + " " + number_text(angle, 10) + " (expected -360 to 360 degrees)");
  if (!(v.hfov > 0 && v.hfov <= 179))
    throw Error(of + "hfov " + number_text(v.hfov, 10) +
                " (expected more than 0, at most 179 degrees: a pinhole sees less than 180)");
  if (!(v.vfov == 0 || (v.vfov > 0 && v.vfov <= 179)))
    throw Error(of + "vfov " + number_text(v.vfov, 10) +
                " (expected more than 0, at most 179 degrees)");
  if (v.width == 0 && v.height != 0)
    throw Error(of + "a height without a width (give size WxH, or the width alone)");
  if (v.width < 0 || v.height < 0 || v.width > kMaxViewSide || v.height > kMaxViewSide)
    throw Error(of + "size " + std::to_string(v.width) + "x" + std::to_string(v.height) +
                " (expected 1 to " + std::to_string(kMaxViewSide) + " pixels a side)");
  if (v.vfov > 0 && v.height > 0)
    throw Error(of + "both vfov and a height (the height follows from vfov: give one)");
}

// One key of a view (from a YAML mapping).
void set_key(ViewSpec& v, const std::string& key, const std::string& value,
             std::set<std::string>& seen, const std::string& where) {
  const std::string k = key == "fov" ? "hfov" : key;
  if (!seen.insert(k).second) throw Error(where + "'" + key + "' given twice in one view");
  const std::string what = where + key;
  if (k == "name")
    v.name = value;
  else if (k == "yaw")
    v.yaw = number(value, what);
  else if (k == "pitch")
    v.pitch = number(value, what);
  else if (k == "roll")
    v.roll = number(value, what);
  else if (k == "hfov")
    v.hfov = number(value, what);
  else if (k == "vfov")
    v.vfov = number(value, what);
  else if (k == "size") {
    const Size s = parse_size(value, what);
    v.width = s.width, v.height = s.height;  // (the sides' range: check_view)
  } else if (k == "width")
    v.width = whole(value, what, 1, kMaxViewSide);
  else if (k == "height")
    v.height = whole(value, what, 1, kMaxViewSide);
  else
    throw Error(where + "unknown key '" + shown(key) +
                "' (expected name, yaw, pitch, roll, hfov or fov, vfov, size, width, height)");
}

std::vector<ViewSpec> cube() {
  constexpr const char* kNames[6] = {"front", "right", "back", "left", "up", "down"};
  constexpr double kAngles[6][2] = {{0, 0}, {90, 0}, {180, 0}, {-90, 0}, {0, 90}, {0, -90}};
  std::vector<ViewSpec> views;
  for (int f = 0; f < 6; ++f)
    views.push_back({kNames[f], kAngles[f][0], kAngles[f][1], 0, 90, 0, 0, 0});
  return views;
}

// ring:n=8,fov=90,vfov=..,pitch=0,yaw=0
std::vector<ViewSpec> ring(const std::string& keys) {
  int64_t n = 8;
  double fov = 90, vfov = 0, pitch = 0, yaw = 0;
  size_t at = 0;
  while (at < keys.size()) {
    const size_t comma = std::min(keys.find(',', at), keys.size());
    const std::string kv = trim(std::string_view(keys).substr(at, comma - at));
    at = comma + 1;
    const size_t eq = kv.find('=');
    if (eq == std::string::npos)
      throw Error("rig ring: '" + shown(kv) +
                  "' (expected key=value, e.g. ring:n=8,fov=90,pitch=0)");
    const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1), what = "rig ring: " + k;
    if (k == "n")
      n = whole(v, what, 1, 360);
    else if (k == "fov" || k == "hfov")
      fov = number(v, what);
    else if (k == "vfov")
      vfov = number(v, what);
    else if (k == "pitch")
      pitch = number(v, what);
    else if (k == "yaw")
      yaw = number(v, what);
    else
      throw Error("rig ring: unknown key '" + shown(k) + "' (expected n, fov, vfov, pitch, yaw)");
  }
  std::vector<ViewSpec> views;
  for (int64_t i = 0; i < n; ++i) {
    const double y = yaw + 360.0 * static_cast<double>(i) / static_cast<double>(n);
    char name[48];
    const long named = std::lround(std::fmod(std::fmod(y, 360) + 360, 360)) % 360;
    if (pitch == 0)
      std::snprintf(name, sizeof name, "y%03ld", named);
    else
      std::snprintf(name, sizeof name, "y%03ld_p%ld", named, std::lround(pitch));
    views.push_back({name, y > 180 ? y - 360 : y, pitch, 0, fov, vfov, 0, 0});
  }
  return views;
}

// A block or flow YAML list of mappings of scalars (the subset a rig needs), optionally under a
// top key "views:".
// read_head refuses directories, FIFOs and devices before reading.
std::string read_rig_file(const std::string& path) {
  std::string text =
      read_head(path, kMaxRigFile + 1, "the rig file", "a YAML list of views after @");
  if (text.size() > kMaxRigFile)
    throw Error("rig file '" + path + "': over 1 MB (expected a list of views)");
  return text;
}

// `label` names the text in errors ("rig file 'x.yaml'", "rig").
std::vector<ViewSpec> yaml_views(const std::string& text, const std::string& label) {
  std::vector<ViewSpec> views;
  for (const Mapping& m : parse_mapping_list(
           text, label, {"view", "views", "views", "{name: front, yaw: 0, hfov: 90}"}, kMaxViews)) {
    views.emplace_back();
    views.back().name.clear();
    std::set<std::string> seen;
    for (size_t k = 0; k < m.entries.size(); ++k)
      set_key(views.back(), m.entries[k].first, m.entries[k].second, seen,
              label + " line " + std::to_string(m.lines[k]) + ": ");
  }
  for (size_t i = 0; i < views.size(); ++i)
    if (views[i].name.empty())
      throw Error(label + ": view " + std::to_string(i + 1) + " has no name");
  return views;
}

}  // namespace

std::vector<ViewSpec> parse_rig(std::string_view text) {
  const std::string t = trim(text);
  if (t.empty()) throw Error("rig: empty (expected cube, ring:n=8,fov=90,pitch=0 or @rig.yaml)");
  std::vector<ViewSpec> views;
  const bool file = t.front() == '@', yaml = file || t.front() == '-' || t.rfind("views:", 0) == 0;
  const std::string label = file ? "rig file '" + t.substr(1) + "'" : "rig";
  if (yaml) {
    views = yaml_views(file ? read_rig_file(t.substr(1)) : t, label);
  } else {
    size_t at = 0;
    while (at <= t.size()) {
      const size_t plus = std::min(t.find('+', at), t.size());
      const std::string part = trim(std::string_view(t).substr(at, plus - at));
      at = plus + 1;
      std::vector<ViewSpec> more;
      if (part == "cube")
        more = cube();
      else if (part == "ring")
        more = ring("");
      else if (part.rfind("ring:", 0) == 0)
        more = ring(part.substr(5));
      else
        throw Error(
            "rig: '" + shown(part) +
            "' (expected cube, ring:n=8,fov=90,pitch=0, a sum of them with '+', or @rig.yaml)");
      views.insert(views.end(), more.begin(), more.end());
      if (views.size() > kMaxViews)
        throw Error("rig: more than " + std::to_string(kMaxViews) + " views");
    }
  }
  std::set<std::string> names;
  for (const ViewSpec& v : views) {
    check_view(v, label + ": ");
    if (!names.insert(v.name).second)
      throw Error("rig: two views named " + v.name + " (names must differ: they name the files)");
  }
  return views;
}

namespace {

// tan(fov / 2), exactly 1 at 90 degrees (so a cube face's focal is exactly W / 2).
double tan_half(double fov_deg) {
  return fov_deg == 90 ? 1.0 : std::tan(fov_deg * kPi / 360);
}

}  // namespace

std::vector<ViewCamera> view_cameras(const std::vector<ViewSpec>& rig, std::optional<Size> size,
                                     double density) {
  std::vector<ViewCamera> cams;
  for (const ViewSpec& v : rig) {
    const double th = tan_half(v.hfov);
    int64_t w = v.width, h = v.height;
    if (w == 0 && size) {
      w = size->width, h = size->height;
      if (v.vfov > 0)
        throw Error("view " + v.name + ": vfov " + number_text(v.vfov, 10) + " and a size " +
                    size_text(*size) + " both given (the height follows from vfov: give one)");
    }
    double focal;
    if (w > 0) {
      focal = 0.5 * static_cast<double>(w) / th;
    } else {
      focal = density;
      const double wide = std::round(2 * focal * th);
      if (!(wide <= kMaxViewSide))
        throw Error("view " + v.name + ": " +
                    std::to_string(static_cast<int64_t>(std::min(wide, 1e15))) +
                    " px wide at the source's resolution (at most " + std::to_string(kMaxViewSide) +
                    "): give a size, or a smaller hfov");
      w = std::max<int64_t>(1, static_cast<int64_t>(wide));
      focal = 0.5 * static_cast<double>(w) / th;
    }
    if (h == 0) {
      const double tall = std::round(2 * focal * tan_half(v.vfov > 0 ? v.vfov : v.hfov));
      if (!(tall <= kMaxViewSide))
        throw Error("view " + v.name + ": " +
                    std::to_string(static_cast<int64_t>(std::min(tall, 1e15))) +
                    " px tall (at most " + std::to_string(kMaxViewSide) +
                    "): give a size, or a smaller vfov");
      h = std::max<int64_t>(1, static_cast<int64_t>(tall));
    }
    cams.push_back({v.name, Size{w, h}, focal, rotation_from_ypr(v.yaw, v.pitch, v.roll)});
  }
  return cams;
}

}  // namespace panoproj
