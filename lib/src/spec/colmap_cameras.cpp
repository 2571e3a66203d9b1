// COLMAP's cameras as specs (colmap_cameras.hpp).
#include "spec/colmap_cameras.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

#include "base/text.hpp"
#include "io/colmap/model.hpp"
#include "panoproj/conventions.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// "name:fx=..,fy=..,cx=..,cy=..": one focal length or two first, then the principal point.
std::string intrinsics(const char* name, const std::vector<double>& p, bool one_focal) {
  const size_t c = one_focal ? 1 : 2;
  return std::string(name) + ":fx=" + number_text(p[0]) +
         ",fy=" + number_text(one_focal ? p[0] : p[1]) + ",cx=" + number_text(p[c] - 0.5) +
         ",cy=" + number_text(p[c + 1] - 0.5);
}

std::string keys(const std::vector<double>& p, size_t from,
                 std::initializer_list<const char*> names) {
  std::string s;
  size_t i = from;
  for (const char* n : names) s += std::string(",") + n + "=" + number_text(p[i++]);
  return s;
}

std::string lens_spec(const colmap::Camera& c) {
  const auto& p = c.params;
  const std::string& m = c.model;
  if (m == "SIMPLE_PINHOLE") return intrinsics("brown-conrady", p, true);
  if (m == "PINHOLE") return intrinsics("brown-conrady", p, false);
  if (m == "SIMPLE_RADIAL") return intrinsics("brown-conrady", p, true) + keys(p, 3, {"k1"});
  if (m == "RADIAL") return intrinsics("brown-conrady", p, true) + keys(p, 3, {"k1", "k2"});
  if (m == "OPENCV")
    return intrinsics("brown-conrady", p, false) + keys(p, 4, {"k1", "k2", "p1", "p2"});
  if (m == "FULL_OPENCV")
    return intrinsics("brown-conrady", p, false) +
           keys(p, 4, {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"});
  if (m == "OPENCV_FISHEYE")
    return intrinsics("kannala-brandt", p, false) + keys(p, 4, {"k1", "k2", "k3", "k4"});
  if (m == "SIMPLE_RADIAL_FISHEYE")
    return intrinsics("kannala-brandt", p, true) + keys(p, 3, {"k1"});
  if (m == "RADIAL_FISHEYE")
    return intrinsics("kannala-brandt", p, true) + keys(p, 3, {"k1", "k2"});
  if (m == "SIMPLE_FISHEYE") return intrinsics("kannala-brandt", p, true);
  if (m == "FISHEYE") return intrinsics("kannala-brandt", p, false);
  if (m == "THIN_PRISM_FISHEYE")
    return intrinsics("thin-prism-fisheye", p, false) +
           keys(p, 4, {"k1", "k2", "p1", "p2", "k3", "k4", "sx1", "sy1"});
  if (m == "RAD_TAN_THIN_PRISM_FISHEYE")
    return intrinsics("rad-tan-thin-prism-fisheye", p, false) +
           keys(p, 4, {"k0", "k1", "k2", "k3", "k4", "k5", "p0", "p1", "s0", "s1", "s2", "s3"});
  // FOV at omega = 0 is COLMAP's pinhole limit.
  if (m == "FOV")
    return p[4] == 0 ? intrinsics("brown-conrady", p, false)
                     : intrinsics("devernay-faugeras", p, false) + keys(p, 4, {"omega"});
  if (m == "SIMPLE_DIVISION") return intrinsics("division", p, true) + keys(p, 3, {"k"});
  if (m == "DIVISION") return intrinsics("division", p, false) + keys(p, 4, {"k"});
  if (m == "EUCM") return intrinsics("extended-unified", p, false) + keys(p, 4, {"alpha", "beta"});
  return "";
}

// The Kannala-Brandt family's radial coefficients (theta_d = theta (1 + k1 theta^2 + ...)), its
// focal lengths and principal point; false for other models.
bool fisheye_law(const colmap::Camera& c, std::vector<double>& k, double f[4]) {
  const auto& p = c.params;
  const bool one = c.model == "SIMPLE_RADIAL_FISHEYE" || c.model == "RADIAL_FISHEYE" ||
                   c.model == "SIMPLE_FISHEYE";
  if (c.model == "OPENCV_FISHEYE")
    k = {p[4], p[5], p[6], p[7]};
  else if (c.model == "SIMPLE_RADIAL_FISHEYE")
    k = {p[3]};
  else if (c.model == "RADIAL_FISHEYE")
    k = {p[3], p[4]};
  else if (c.model == "THIN_PRISM_FISHEYE")
    k = {p[4], p[5], p[8], p[9]};
  else if (c.model == "RAD_TAN_THIN_PRISM_FISHEYE")
    k = {p[4], p[5], p[6], p[7], p[8], p[9]};
  else if (c.model != "SIMPLE_FISHEYE" && c.model != "FISHEYE")
    return false;
  const size_t at = one ? 1 : 2;
  f[0] = p[0], f[1] = one ? p[0] : p[1], f[2] = p[at], f[3] = p[at + 1];
  return true;
}

// A fisheye's field wider than the spec's default 180 degrees: to its frame's corners (2% past
// their radius) or short of its law's first fold, whichever is nearer; "" within 180 degrees.
// (COLMAP's cameras hold no field: their frame is the field.)
std::string fisheye_fov(const colmap::Camera& c) {
  std::vector<double> k;
  double f[4];
  if (!fisheye_law(c, k, f)) return "";
  double r = 0;
  for (double x : {0.0, static_cast<double>(c.width)})
    for (double y : {0.0, static_cast<double>(c.height)})
      r = std::max(r, std::hypot((x - f[2]) / f[0], (y - f[3]) / f[1]));
  auto g = [&](double t) {  // theta_d and its slope
    double s = 1, d = 1, t2 = t * t, pw = t2;
    for (size_t i = 0; i < k.size(); ++i, pw *= t2)
      s += k[i] * pw, d += static_cast<double>(2 * i + 3) * k[i] * pw;
    return std::pair{t * s, d};
  };
  constexpr double kStep = 1e-3;
  double t = 0;
  for (; t + kStep < kPi; t += kStep) {
    const auto [rd, slope] = g(t + kStep);
    if (!(slope > 0) || !std::isfinite(rd)) break;  // (the fold: stop a step short of it)
    if (rd > 1.02 * r) {
      t += kStep;
      break;
    }
  }
  if (t <= kPi / 2) return "";
  return ",fov=" + number_text(2 * t * 180 / kPi);
}

// EQUIRECTANGULAR: its params are the full panorama's w, h (COLMAP sets them to the frame's
// size): the frame is the whole sphere, or the top-left part of one from longitude -180 and
// latitude 90 (COLMAP's x / w and y / h).
std::string equirect_spec(const colmap::Camera& c) {
  const double w = static_cast<double>(c.width), h = static_cast<double>(c.height);
  const double pw = c.params[0], ph = c.params[1];
  if (pw == w && ph == h) return "equirect";
  if (!(pw >= w && ph >= h))
    throw Error("camera " + std::to_string(c.id) +
                " (EQUIRECTANGULAR) has w, h = " + number_text(pw) + ", " + number_text(ph) +
                " for a frame of " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                " (expected the panorama's size: at least the frame's)");
  const double hfov = 360 * w / pw, vfov = 180 * h / ph;
  return "equirect:hfov=" + number_text(hfov) + ",vfov=" + number_text(vfov) +
         ",lon0=" + number_text(-180 + hfov / 2) + ",lat0=" + number_text(90 - vfov / 2);
}

// The lens's spec with the camera's size (a frame of another size is refused), or equirect for
// EQUIRECTANGULAR (COLMAP's axes: tested).
std::string spec_of(const colmap::Camera& c) {
  if (c.model == "EQUIRECTANGULAR") return equirect_spec(c);
  return lens_spec(c) + fisheye_fov(c) + ",width=" + std::to_string(c.width) +
         ",height=" + std::to_string(c.height);
}

}  // namespace

bool is_colmap_cameras(const std::string& text, const std::string& path) {
  const std::string name = base_name(path);
  return name == "cameras.txt" || name == "cameras.bin" ||
         text.find("# Camera list with one line of data per camera:") != std::string::npos;
}

std::string colmap_camera_spec(const std::string& text, const std::string& path,
                               const std::string& id) {
  const std::vector<colmap::Camera> cams =
      colmap::parse_cameras(text, base_name(path) == "cameras.bin", path);
  std::string ids;
  for (size_t i = 0; i < cams.size() && i < 8; ++i)
    ids += (ids.empty() ? "" : ", ") + std::to_string(cams[i].id);
  if (cams.size() > 8) ids += ", ...";
  if (cams.empty()) throw Error(path + ": no cameras (expected COLMAP's cameras file)");
  const colmap::Camera* cam = nullptr;
  for (const colmap::Camera& c : cams)
    if (std::to_string(c.id) == id || (id.empty() && cams.size() == 1)) cam = &c;
  if (!cam)
    throw Error(path + (id.empty() ? ": holds cameras " + ids + " (name one: @" + path + "#" +
                                         std::to_string(cams[0].id) + ")"
                                   : ": no camera " + id + " (it holds " + ids + ")"));
  return spec_of(*cam);
}

std::string colmap_camera_spec(const colmap::Camera& camera) {
  return spec_of(camera);
}

}  // namespace panoproj
