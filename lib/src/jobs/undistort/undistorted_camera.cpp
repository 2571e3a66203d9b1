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

// Pixel centres from..to - 1 along a side: every one, or 65536 spread evenly over a longer run.
std::vector<double> centres(uint64_t from, uint64_t to) {
  const uint64_t n = to - from, k = std::min<uint64_t>(n, 65536);
  std::vector<double> v(k);
  for (uint64_t i = 0; i < k; ++i)
    v[i] =
        static_cast<double>(from) + 0.5 +
        (k == n ? static_cast<double>(i)
                : static_cast<double>(i) * static_cast<double>(n - 1) / static_cast<double>(k - 1));
  return v;
}
std::vector<double> centres(uint64_t n) {
  return centres(0, n);
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

// The region of interest in whole pixels (COLMAP's rounding and clamps).
struct Roi {
  uint64_t x0, y0, x1, y1;
  bool on;
};
Roi roi_of(const colmap::Camera& c, const UndistortOptions& o) {
  const auto& r = o.roi;
  Roi roi{0, 0, c.width, c.height, r[0] > 0 || r[1] > 0 || r[2] < 1 || r[3] < 1};
  if (!roi.on) return roi;
  const double w = static_cast<double>(c.width), h = static_cast<double>(c.height);
  roi.x0 = std::min(static_cast<uint64_t>(std::round(r[0] * w)), c.width - 1);
  roi.y0 = std::min(static_cast<uint64_t>(std::round(r[1] * h)), c.height - 1);
  roi.x1 = std::max(static_cast<uint64_t>(std::round(r[2] * w)), roi.x0 + 1);
  roi.y1 = std::max(static_cast<uint64_t>(std::round(r[3] * h)), roi.y0 + 1);
  return roi;
}

// Where the frame's border pixels land on the pinhole: the least and largest x of its left and
// right edges, y of its top and bottom edges (the ROI's rows and columns of the whole frame's
// edges, as COLMAP samples them).
struct Border {
  static constexpr double kBig = std::numeric_limits<double>::max();
  double left_min = kBig, left_max = -kBig, right_min = kBig, right_max = -kBig;
  double top_min = kBig, top_max = -kBig, bottom_min = kBig, bottom_max = -kBig;
};
Border border_of(const colmap::Camera& c, const Projection& p, const Intrinsics& in, const Roi& roi,
                 double max_norm) {
  const double w = static_cast<double>(c.width), h = static_cast<double>(c.height);
  // Where a source pixel lands on the pinhole (false: no ray, behind it, or past max_norm).
  auto land = [&](double x, double y, double& u, double& v) {
    Ray d;
    if (!to_ray(p, x, y, d) || !(d.z() > 0)) return false;
    const double a = d.x() / d.z(), b = d.y() / d.z();
    if (max_norm > 0 && !(a * a + b * b < max_norm * max_norm)) return false;
    u = in.fx * a + in.cx, v = in.fy * b + in.cy;
    return true;
  };
  Border e;
  double u, v;
  for (double y : centres(roi.y0, roi.y1)) {
    if (land(0.5, y, u, v))
      e.left_min = std::min(e.left_min, u), e.left_max = std::max(e.left_max, u);
    if (land(w - 0.5, y, u, v))
      e.right_min = std::min(e.right_min, u), e.right_max = std::max(e.right_max, u);
  }
  for (double x : centres(roi.x0, roi.x1)) {
    if (land(x, 0.5, u, v)) e.top_min = std::min(e.top_min, v), e.top_max = std::max(e.top_max, v);
    if (land(x, h - 0.5, u, v))
      e.bottom_min = std::min(e.bottom_min, v), e.bottom_max = std::max(e.bottom_max, v);
  }
  return e;
}

// The pinhole that keeps every source pixel (blank_pixels 1) or leaves none blank (0), of the
// region of interest.
colmap::Camera pinhole_of(const colmap::Camera& c, const Projection& p, const UndistortOptions& o) {
  const Intrinsics in = intrinsics_of(c);
  const Roi roi = roi_of(c, o);
  const double w = static_cast<double>(roi.x1 - roi.x0), h = static_cast<double>(roi.y1 - roi.y0);
  const double cx = in.cx - static_cast<double>(roi.x0), cy = in.cy - static_cast<double>(roi.y0);
  double sx = 1, sy = 1;
  if (roi.on || (c.model != "SIMPLE_PINHOLE" && c.model != "PINHOLE")) {
    const Intrinsics shifted{in.fx, in.fy, cx, cy};
    const Border e = border_of(c, p, shifted, roi, o.max_cam_point_norm);
    const double keep_x = std::min(cx / (cx - e.left_min), (w - 0.5 - cx) / (e.right_max - cx));
    const double keep_y = std::min(cy / (cy - e.top_min), (h - 0.5 - cy) / (e.bottom_max - cy));
    const double fill_x = std::max(cx / (cx - e.left_max), (w - 0.5 - cx) / (e.right_min - cx));
    const double fill_y = std::max(cy / (cy - e.top_max), (h - 0.5 - cy) / (e.bottom_min - cy));
    sx = 1 / (keep_x * o.blank_pixels + fill_x * (1 - o.blank_pixels));
    sy = 1 / (keep_y * o.blank_pixels + fill_y * (1 - o.blank_pixels));
    if (!std::isfinite(sx) || !std::isfinite(sy))
      throw Error("camera " + std::to_string(c.id) + " (" + c.model +
                  "): its frame's edge has no ray on the pinhole (give a smaller max_fov to "
                  "undistort it into views)");
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

Intrinsics intrinsics_of(const colmap::Camera& c) {
  const std::string& m = c.model;
  const bool one = m.rfind("SIMPLE_", 0) == 0 || m == "RADIAL" || m == "RADIAL_FISHEYE";
  const auto& p = c.params;
  return one ? Intrinsics{p[0], p[0], p[1], p[2]} : Intrinsics{p[0], p[1], p[2], p[3]};
}

Projection camera_projection(const CameraPlan& plan) {
  return make_projection(parse_spec(plan.spec), {static_cast<int64_t>(plan.camera.width),
                                                 static_cast<int64_t>(plan.camera.height)});
}

uint32_t view_id(uint32_t own, uint32_t last, size_t index, size_t views, size_t v,
                 const std::string& dir, const char* what) {
  if (v == 0) return own;
  const uint64_t id = uint64_t{last} + uint64_t{index} * (views - 1) + v;
  if (id > std::numeric_limits<uint32_t>::max())
    throw Error(dir + ": the undistorted model's " + what + " ids pass 2^32 - 1 (" +
                std::to_string(views) + " views each)");
  return static_cast<uint32_t>(id);
}

LastIds last_ids(const colmap::Model& m) {
  LastIds last;
  for (const colmap::Camera& c : m.cameras) last.camera = std::max(last.camera, c.id);
  for (const colmap::Image& im : m.images) last.image = std::max(last.image, im.id);
  return last;
}

CameraPlan plan_camera(const colmap::Camera& camera, const UndistortOptions& o, size_t index,
                       LastIds last, const std::string& dir) {
  CameraPlan plan;
  plan.camera = camera;
  plan.spec = colmap_camera_spec(camera);
  const Projection p = camera_projection(plan);
  const Size size{static_cast<int64_t>(camera.width), static_cast<int64_t>(camera.height)};
  plan.field = field_of(p, size);
  plan.pinhole = camera.model != "EQUIRECTANGULAR" && plan.field <= o.max_fov;
  if (plan.pinhole) {
    // (COLMAP keeps an undistorted camera as it is unless max_image_size shrinks it.)
    const bool undistorted = camera.model == "SIMPLE_PINHOLE" || camera.model == "PINHOLE";
    plan.cameras.push_back(undistorted && o.max_image_size == 0 ? camera
                                                                : pinhole_of(camera, p, o));
    return plan;
  }
  const std::vector<ViewCamera> rig = view_cameras(o.rig, o.size, center_density(p));
  for (size_t k = 0; k < rig.size(); ++k)
    if (sees(p, rig[k])) plan.views.push_back(rig[k]), plan.rig_index.push_back(k);
  if (plan.views.empty())
    throw Error("camera " + std::to_string(camera.id) + ": no view of the rig sees its pixels");
  for (size_t v = 0; v < plan.views.size(); ++v) {
    const ViewCamera& view = plan.views[v];
    const double w = static_cast<double>(view.size.width),
                 h = static_cast<double>(view.size.height);
    plan.cameras.push_back(
        {view_id(camera.id, last.camera, index, rig.size(), plan.rig_index[v], dir, "camera"),
         "PINHOLE",
         static_cast<uint64_t>(view.size.width),
         static_cast<uint64_t>(view.size.height),
         {view.focal, view.focal, 0.5 * w, 0.5 * h}});
  }
  return plan;
}

}  // namespace panoproj
