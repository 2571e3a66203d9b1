// What one camera becomes (undistort.hpp): its field, the pinhole chosen as COLMAP's
// image_undistorter chooses it (colmap/image/undistortion.cc, UndistortCamera), or its views.
#include <algorithm>
#include <cmath>
#include <limits>

#include "jobs/undistort/undistort.hpp"
#include "panoproj/conventions.hpp"
#include "panoproj/error.hpp"
#include "panoproj/spec.hpp"
#include "spec/colmap_cameras.hpp"

namespace panoproj {
namespace {

// Positions along a side of n pixels: every centre, or 4096 spread evenly on a longer side.
std::vector<double> centres(uint64_t n) {
  const uint64_t k = std::min<uint64_t>(n, 4096);
  std::vector<double> v(k);
  for (uint64_t i = 0; i < k; ++i)
    v[i] = k == n ? static_cast<double>(i) + 0.5
                  : 0.5 + static_cast<double>(i) * static_cast<double>(n - 1) /
                              static_cast<double>(k - 1);
  return v;
}

// Twice the largest angle off the axis (degrees) of the frame's border pixels and a 65 x 65
// grid inside (a circular fisheye's edge lies inside its frame).
double field_of(const Projection& p, Size size) {
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  double most = 0;
  auto look = [&](double x, double y) {
    Ray d;
    if (to_ray(p, x, y, d)) most = std::max(most, std::atan2(std::hypot(d.x(), d.y()), d.z()));
  };
  for (double x : centres(static_cast<uint64_t>(size.width))) look(x, 0.5), look(x, h - 0.5);
  for (double y : centres(static_cast<uint64_t>(size.height))) look(0.5, y), look(w - 0.5, y);
  for (int j = 0; j <= 64; ++j)
    for (int i = 0; i <= 64; ++i) look(w * i / 64.0, h * j / 64.0);
  return 2 * most * 180 / kPi;
}

// COLMAP's focal lengths and principal point of a camera (one focal length for the SIMPLE_
// models, RADIAL and the radial fisheyes).
struct Intrinsics {
  double fx, fy, cx, cy;
};
Intrinsics intrinsics_of(const colmap::Camera& c) {
  const std::string& m = c.model;
  const bool one = m.rfind("SIMPLE_", 0) == 0 || m == "RADIAL" || m == "RADIAL_FISHEYE";
  const auto& p = c.params;
  return one ? Intrinsics{p[0], p[0], p[1], p[2]} : Intrinsics{p[0], p[1], p[2], p[3]};
}

// The pinhole that keeps every source pixel (blank_pixels 1) or leaves none blank (0).
colmap::Camera pinhole_of(const colmap::Camera& c, const Projection& p, const UndistortOptions& o) {
  const Intrinsics in = intrinsics_of(c);
  const double w = static_cast<double>(c.width), h = static_cast<double>(c.height);
  constexpr double kBig = std::numeric_limits<double>::max();
  double left_min = kBig, left_max = -kBig, right_min = kBig, right_max = -kBig;
  double top_min = kBig, top_max = -kBig, bottom_min = kBig, bottom_max = -kBig;
  // Where a source pixel lands on the pinhole (false: no ray, or behind it).
  auto land = [&](double x, double y, double& u, double& v) {
    Ray d;
    if (!to_ray(p, x, y, d) || !(d.z() > 0)) return false;
    u = in.fx * d.x() / d.z() + in.cx, v = in.fy * d.y() / d.z() + in.cy;
    return true;
  };
  double u, v;
  for (double y : centres(c.height)) {
    if (land(0.5, y, u, v)) left_min = std::min(left_min, u), left_max = std::max(left_max, u);
    if (land(w - 0.5, y, u, v))
      right_min = std::min(right_min, u), right_max = std::max(right_max, u);
  }
  for (double x : centres(c.width)) {
    if (land(x, 0.5, u, v)) top_min = std::min(top_min, v), top_max = std::max(top_max, v);
    if (land(x, h - 0.5, u, v))
      bottom_min = std::min(bottom_min, v), bottom_max = std::max(bottom_max, v);
  }
  const double cx = in.cx, cy = in.cy;
  double sx = 1, sy = 1;
  if (c.model != "SIMPLE_PINHOLE" && c.model != "PINHOLE") {
    const double keep_x = std::min(cx / (cx - left_min), (w - 0.5 - cx) / (right_max - cx));
    const double keep_y = std::min(cy / (cy - top_min), (h - 0.5 - cy) / (bottom_max - cy));
    const double fill_x = std::max(cx / (cx - left_max), (w - 0.5 - cx) / (right_min - cx));
    const double fill_y = std::max(cy / (cy - top_max), (h - 0.5 - cy) / (bottom_min - cy));
    sx = 1 / (keep_x * o.blank_pixels + fill_x * (1 - o.blank_pixels));
    sy = 1 / (keep_y * o.blank_pixels + fill_y * (1 - o.blank_pixels));
    if (!std::isfinite(sx) || !std::isfinite(sy))
      throw Error(
          "camera " + std::to_string(c.id) + " (" + c.model +
          "): its frame's edge has no ray on the pinhole (give a smaller max_fov to undistort "
          "it into views)");
    sx = std::clamp(sx, o.min_scale, o.max_scale);
    sy = std::clamp(sy, o.min_scale, o.max_scale);
  }
  colmap::Camera out{c.id, "PINHOLE", 0, 0, {}};
  out.width = static_cast<uint64_t>(std::max(1.0, sx * w));
  out.height = static_cast<uint64_t>(std::max(1.0, sy * h));
  out.params = {in.fx, in.fy, cx * static_cast<double>(out.width) / w,
                cy * static_cast<double>(out.height) / h};
  if (o.max_image_size > 0) {
    const double m = static_cast<double>(o.max_image_size);
    const double scale =
        std::min(m / static_cast<double>(out.width), m / static_cast<double>(out.height));
    if (scale < 1) {  // (COLMAP's Camera::Rescale)
      const double ow = static_cast<double>(out.width), oh = static_cast<double>(out.height);
      const double kx = std::round(scale * ow) / ow, ky = std::round(scale * oh) / oh;
      out.width = static_cast<uint64_t>(std::round(scale * ow));
      out.height = static_cast<uint64_t>(std::round(scale * oh));
      out.params = {out.params[0] * kx, out.params[1] * ky, out.params[2] * kx, out.params[3] * ky};
    }
  }
  constexpr uint64_t kMaxSide = 65536;
  if (out.width > kMaxSide || out.height > kMaxSide)
    throw Error("camera " + std::to_string(c.id) + " undistorts to " + std::to_string(out.width) +
                "x" + std::to_string(out.height) + " px (at most " + std::to_string(kMaxSide) +
                " a side: give max_image_size, or a smaller max_scale)");
  return out;
}

// Whether a view sees any of the source camera's pixels (a 33 x 33 grid of its pixels).
bool sees(const Projection& p, const ViewCamera& v) {
  const double w = static_cast<double>(v.size.width), h = static_cast<double>(v.size.height);
  for (int j = 0; j <= 32; ++j)
    for (int i = 0; i <= 32; ++i) {
      const Ray d = v.world_from_camera *
                    Ray((w * i / 32.0 - 0.5 * w) / v.focal, (h * j / 32.0 - 0.5 * h) / v.focal, 1)
                        .normalized();
      double x, y;
      if (to_pixel(p, d, x, y)) return true;
    }
  return false;
}

}  // namespace

Projection camera_projection(const CameraPlan& plan) {
  return make_projection(parse_spec(plan.spec), {static_cast<int64_t>(plan.camera.width),
                                                 static_cast<int64_t>(plan.camera.height)});
}

CameraPlan plan_camera(const colmap::Camera& camera, const UndistortOptions& o) {
  CameraPlan plan;
  plan.camera = camera;
  plan.spec = colmap_camera_spec(camera);
  const Projection p = camera_projection(plan);
  const Size size{static_cast<int64_t>(camera.width), static_cast<int64_t>(camera.height)};
  plan.field = field_of(p, size);
  plan.pinhole = camera.model != "EQUIRECTANGULAR" && plan.field <= o.max_fov;
  if (plan.pinhole) {
    plan.cameras.push_back(pinhole_of(camera, p, o));
    return plan;
  }
  for (const ViewCamera& v : view_cameras(o.rig, o.size, center_density(p)))
    if (sees(p, v)) plan.views.push_back(v);
  if (plan.views.empty())
    throw Error("camera " + std::to_string(camera.id) + ": no view of the rig sees its pixels");
  for (const ViewCamera& v : plan.views)
    plan.cameras.push_back({0,
                            "PINHOLE",
                            static_cast<uint64_t>(v.size.width),
                            static_cast<uint64_t>(v.size.height),
                            {v.focal, v.focal, 0.5 * static_cast<double>(v.size.width),
                             0.5 * static_cast<double>(v.size.height)}});
  return plan;
}

}  // namespace panoproj
