// Rig files of lenses (lens_rig.hpp).
#include "jobs/stitch/lens_rig.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "base/input_check.hpp"
#include "base/mapping_list.hpp"
#include "base/text.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

constexpr size_t kMaxRigFile = size_t{1} << 20;

double angle(const std::string& text, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v) ||
      std::abs(v) > 360)
    throw Error(what + " '" + shown(text) + "' (expected -360 to 360 degrees)");
  return v;
}

// WxH+X+Y, integers: W, H positive, X, Y at least 0, the whole inside kMaxSide.
PixelRect rectangle(const std::string& text, const std::string& what) {
  long long v[4] = {0, 0, 0, 0};
  const char seps[4] = {'x', '+', '+', '\0'};
  size_t at = 0;
  bool ok = true;
  for (int k = 0; k < 4 && ok; ++k) {
    const size_t start = at;
    while (at < text.size() && std::isdigit(static_cast<unsigned char>(text[at])) &&
           at - start < 10)
      ++at;
    ok = at > start && (at - start) < 10;
    if (ok) v[k] = std::stoll(text.substr(start, at - start));
    if (ok && k < 3) ok = at < text.size() && text[at++] == seps[k];
  }
  ok = ok && at == text.size() && v[0] > 0 && v[1] > 0 && v[0] + v[2] <= kMaxSide &&
       v[1] + v[3] <= kMaxSide;
  if (!ok)
    throw Error(
        what + " '" + shown(text) +
        "' (expected WxH+X+Y: a rectangle W x H pixels whose top-left pixel is (X, Y), e.g. "
        "1920x1920+1920+0)");
  return {v[2], v[3], v[2] + v[0], v[3] + v[1]};
}

// CX CY R: three finite numbers, R over 0.
std::array<double, 3> circle(const std::string& text, const std::string& what) {
  std::array<double, 3> v{};
  const char* at = text.c_str();
  bool ok = true;
  for (double& x : v) {
    char* end = nullptr;
    errno = 0;
    x = std::strtod(at, &end);
    ok = ok && end != at && errno != ERANGE && std::isfinite(x) && std::abs(x) <= 1e9;
    at = end;
  }
  while (ok && *at == ' ') ++at;
  if (!ok || *at != '\0' || !(v[2] > 0))
    throw Error(what + " '" + shown(text) +
                "' (expected CX CY R: the circle's centre and radius over 0, in pixels, e.g. 960 "
                "960 950)");
  return v;
}

}  // namespace

bool is_rig_path(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e == ".yaml" || e == ".yml" || e == ".json";
}

LensRig parse_lens_rig(const std::string& text, const std::string& path) {
  LensRig rig{path, {}};
  const std::string label = "rig " + path;
  const std::vector<Mapping> items = parse_mapping_list(
      text, label,
      {"lens", "lenses", "lenses", "{spec: 'fisheye:fov=200', input: front.jpg, yaw: 0}"},
      kMaxRigLenses);
  for (const Mapping& m : items) {
    RigLens lens;
    lens.line = m.line;
    lens.name = "lens " + std::to_string(rig.lenses.size() + 1);
    for (size_t k = 0; k < m.entries.size(); ++k) {
      const auto& [key, value] = m.entries[k];
      const std::string what = label + " line " + std::to_string(m.lines[k]) + ": " + key;
      if (key == "name")
        lens.name = value;
      else if (key == "spec")
        lens.spec = value;
      else if (key == "input")
        lens.input = value;
      else if (key == "rect")
        lens.rect = rectangle(value, what);
      else if (key == "crop")
        lens.crop = rectangle(value, what);
      else if (key == "flat_field")
        lens.flat_field = value;
      else if (key == "circle")
        lens.circle = circle(value, what);
      else if (key == "yaw")
        lens.yaw = angle(value, what);
      else if (key == "pitch")
        lens.pitch = angle(value, what);
      else if (key == "roll")
        lens.roll = angle(value, what);
      else
        throw Error(
            label + " line " + std::to_string(m.lines[k]) + ": unknown key '" + key +
            "' (expected spec, input, rect, crop, circle, yaw, pitch, roll, name, flat_field)");
    }
    const std::string of = label + " line " + std::to_string(m.line) + ": " + lens.name;
    if (lens.name.empty() || lens.name.size() > 64)
      throw Error(label + " line " + std::to_string(m.line) +
                  ": name (expected 1 to 64 characters)");
    if (lens.spec.empty())
      throw Error(of +
                  " has no spec (expected spec: its projection, e.g. 'fisheye:fov=200', or "
                  "@calibration.yaml)");
    if (lens.crop && lens.circle)
      throw Error(of + " has a crop and a circle (give one: the part of its image it keeps)");
    if (lens.input.empty())
      throw Error(of + " has no input (expected input: its image file, or the frame it shares)");
    rig.lenses.push_back(std::move(lens));
  }
  return rig;
}

LensRig read_lens_rig(const std::string& path) {
  const std::string text = read_head(path, kMaxRigFile + 1, "the rig file", "a YAML or JSON rig");
  if (text.size() > kMaxRigFile)
    throw Error("rig " + path + ": over 1 MiB (expected a list of lenses)");
  return parse_lens_rig(text, path);
}

}  // namespace panoproj
