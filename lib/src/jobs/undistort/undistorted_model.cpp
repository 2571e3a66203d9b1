// The undistorted model (undistort.hpp): new cameras, images, observations, tracks, rigs and
// frames.
#include <algorithm>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "jobs/undistort/undistort.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

using colmap::Pose;

Pose rotation_pose(const Eigen::Matrix3d& r) {
  return colmap::pose_of(r, Eigen::Vector3d::Zero());
}

Pose inverse(const Pose& p) {
  const Eigen::Matrix3d r = colmap::rotation_of(p).transpose();
  return colmap::pose_of(r, -(r * colmap::translation_of(p)));
}

// A name kept inside the output's images/ folder: relative, no "." or ".." component.
void check_name(const std::string& name, const std::string& dir) {
  bool ok = !name.empty() && name[0] != '/' && name.find('\\') == std::string::npos;
  for (size_t at = 0; ok && at <= name.size();) {
    const size_t slash = std::min(name.find('/', at), name.size());
    const std::string part = name.substr(at, slash - at);
    ok = !part.empty() && part != "." && part != "..";
    at = slash + 1;
  }
  if (!ok)
    throw Error(dir + ": the image name '" + name.substr(0, 200) +
                "' leaves the images folder (expected a relative path without '.' or '..')");
}

std::string with_extension(const std::string& name, const std::string& ext) {
  if (ext.empty()) return name;
  const size_t slash = name.rfind('/');
  const size_t dot = name.rfind('.');
  return (dot != std::string::npos && (slash == std::string::npos || dot > slash)
              ? name.substr(0, dot)
              : name) +
         ext;
}

// COLMAP's implicit rigs of a model without them: one per camera, one frame per image.
void add_implicit_rigs(colmap::Model& m) {
  for (const colmap::Camera& c : m.cameras)
    m.rigs.push_back({c.id, {{colmap::SensorType::Camera, c.id, {}}}});
  for (const colmap::Image& im : m.images)
    m.frames.push_back(
        {im.id, im.camera, im.cam_from_world, {{colmap::SensorType::Camera, im.camera, im.id}}});
}

// Where an observation lands among an image's outputs: {output, x, y}; output -1: nowhere.
struct Landing {
  int output = -1;
  double x = 0, y = 0;
};
Landing land(const Projection& p, const std::vector<OutputImage>& outs, double x, double y) {
  Ray d;
  if (!to_ray(p, x, y, d)) return {};
  for (size_t k = 0; k < outs.size(); ++k) {
    const OutputImage& o = outs[k];
    const Ray v = o.camera_from_view.transpose() * d;
    if (!(v.z() > 0)) continue;
    const double u = o.fx * v.x() / v.z() + o.cx, w = o.fy * v.y() / v.z() + o.cy;
    const bool inside = u >= 0 && w >= 0 && u < static_cast<double>(o.size.width) &&
                        w < static_cast<double>(o.size.height);
    if (inside || !o.view) return {static_cast<int>(k), u, w};
  }
  return {};
}

// The plan as it is built: each camera's plan, where each observation went.
struct Builder {
  const colmap::Model& in;
  const UndistortOptions& o;
  const std::string& dir;
  UndistortPlan plan;
  std::unordered_map<uint32_t, size_t> plan_of;                       // camera id -> its plan
  std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> moved;  // (image << 32 | idx) -> new
  std::unordered_map<uint32_t, std::vector<uint32_t>> outputs_of;     // image id -> new image ids
  bool split = false;
  std::unordered_set<std::string> names;  // the outputs' (a view's folder may hold an image's)

  const CameraPlan& camera(uint32_t id) const { return plan.cameras[plan_of.at(id)]; }

  void cameras(LastIds last) {
    for (size_t i = 0; i < in.cameras.size(); ++i) {
      const colmap::Camera& c = in.cameras[i];
      CameraPlan p = plan_camera(c, o, i, last, dir);
      for (const colmap::Camera& n : p.cameras) plan.model.cameras.push_back(n);
      split = split || !p.pinhole;
      plan_of[c.id] = plan.cameras.size();
      plan.cameras.push_back(std::move(p));
    }
  }

  // Each image's outputs, their poses and the observations moved into them.
  void images(LastIds last) {
    for (size_t k = 0; k < in.images.size(); ++k) {
      const colmap::Image& im = in.images[k];
      const CameraPlan& cp = camera(im.camera);
      std::vector<OutputImage> outs = image_outputs(im, k, cp, o, last, dir);
      for (const OutputImage& oi : outs)
        if (!names.insert(oi.name).second)
          throw Error(dir + ": image " + std::to_string(im.id) + " would be written as " +
                      oi.name.substr(0, 200) +
                      ", another image's name (rename the rig's views, or the format)");
      std::vector<colmap::Image> news;
      for (const OutputImage& oi : outs) {
        news.push_back(
            {oi.id,
             colmap::compose(rotation_pose(oi.camera_from_view.transpose()), im.cam_from_world),
             oi.camera,
             oi.name,
             {}});
        outputs_of[im.id].push_back(oi.id);
      }
      const Projection p = camera_projection(cp);
      for (size_t k = 0; k < im.points.size(); ++k) {
        const colmap::Point2D& q = im.points[k];
        const Landing l = land(p, outs, q.x, q.y);
        if (l.output < 0) continue;
        colmap::Image& n = news[static_cast<size_t>(l.output)];
        moved[(uint64_t{im.id} << 32) | k] = {n.id, static_cast<uint32_t>(n.points.size())};
        n.points.push_back({l.x, l.y, q.point3d});
      }
      for (colmap::Image& n : news) plan.model.images.push_back(std::move(n));
      plan.images.push_back(std::move(outs));
    }
  }

  // Tracks follow their observations; a point seen by none is dropped (none of its observations
  // is left to name it).
  void points() {
    for (const colmap::Point3D& pt : in.points) {
      colmap::Point3D n = pt;
      n.track.clear();
      for (const colmap::TrackElement& e : pt.track)
        if (const auto at = moved.find((uint64_t{e.image} << 32) | e.point2d); at != moved.end())
          n.track.push_back({at->second.first, at->second.second});
      if (!n.track.empty()) plan.model.points.push_back(std::move(n));
    }
  }

  // A rig's sensors as new sensors; returns its new frame from its old.
  Pose rig(const colmap::Rig& r) {
    colmap::Rig n{r.id, {}};
    Pose turn = colmap::kIdentity;
    const colmap::Sensor& ref = r.sensors[0];
    if (ref.type == colmap::SensorType::Camera && !camera(ref.id).pinhole)
      turn = rotation_pose(camera(ref.id).views[0].world_from_camera.transpose());
    const Pose old_from_new = inverse(turn);
    for (size_t k = 0; k < r.sensors.size(); ++k) {
      const colmap::Sensor& s = r.sensors[k];
      const Pose from_old = k == 0 ? colmap::kIdentity : s.from_rig.value_or(colmap::kIdentity);
      const bool known = k == 0 || s.from_rig.has_value();
      if (s.type != colmap::SensorType::Camera) {
        n.sensors.push_back({s.type, s.id, colmap::compose(from_old, old_from_new)});
        continue;
      }
      const CameraPlan& cp = camera(s.id);
      for (size_t v = 0; v < cp.cameras.size(); ++v) {
        const Pose view_from_cam = cp.pinhole
                                       ? colmap::kIdentity
                                       : rotation_pose(cp.views[v].world_from_camera.transpose());
        const Pose p = colmap::compose(view_from_cam, colmap::compose(from_old, old_from_new));
        n.sensors.push_back({colmap::SensorType::Camera, cp.cameras[v].id,
                             n.sensors.empty() || !known ? std::nullopt : std::optional<Pose>(p)});
      }
    }
    plan.model.rigs.push_back(std::move(n));
    return turn;
  }

  void rigs_and_frames() {
    colmap::Model rigged = in;
    if (!in.rigs_and_frames) add_implicit_rigs(rigged);
    plan.model.rigs_and_frames = true;
    std::unordered_map<uint32_t, Pose> new_from_old;  // rig id -> its new frame from its old
    for (const colmap::Rig& r : rigged.rigs) new_from_old[r.id] = rig(r);
    for (const colmap::Frame& f : rigged.frames) {
      colmap::Frame n{f.id, f.rig, colmap::compose(new_from_old.at(f.rig), f.rig_from_world), {}};
      for (const colmap::Data& d : f.data) {
        if (d.type != colmap::SensorType::Camera) {
          n.data.push_back(d);
          continue;
        }
        const CameraPlan& cp = camera(d.sensor);
        const std::vector<uint32_t>& ids = outputs_of.at(static_cast<uint32_t>(d.id));
        for (size_t v = 0; v < ids.size(); ++v)
          n.data.push_back({colmap::SensorType::Camera, cp.cameras[v].id, ids[v]});
      }
      plan.model.frames.push_back(std::move(n));
    }
  }
};

}  // namespace

std::vector<OutputImage> image_outputs(const colmap::Image& im, size_t index, const CameraPlan& cp,
                                       const UndistortOptions& o, LastIds last,
                                       const std::string& dir) {
  check_name(im.name, dir);
  std::vector<OutputImage> outs;
  const size_t rig = cp.pinhole ? 1 : o.rig.size();
  for (size_t v = 0; v < cp.cameras.size(); ++v) {
    const colmap::Camera& c = cp.cameras[v];
    OutputImage oi;
    oi.view = !cp.pinhole;
    oi.name = with_extension(oi.view ? cp.views[v].name + "/" + im.name : im.name, o.extension);
    oi.id = view_id(im.id, last.image, index, rig, cp.pinhole ? 0 : cp.rig_index[v], dir, "image");
    oi.camera = c.id;
    oi.size = {static_cast<int64_t>(c.width), static_cast<int64_t>(c.height)};
    const Intrinsics in = intrinsics_of(c);
    oi.fx = in.fx, oi.fy = in.fy, oi.cx = in.cx, oi.cy = in.cy;
    if (oi.view) oi.camera_from_view = cp.views[v].world_from_camera;
    outs.push_back(oi);
  }
  return outs;
}

UndistortPlan plan_undistort(const colmap::Model& in, const UndistortOptions& o,
                             const std::string& dir) {
  const LastIds last = last_ids(in);
  Builder b{in, o, dir, {}, {}, {}, {}, false, {}};
  b.cameras(last);
  b.images(last);
  b.points();
  auto by_id = [](const auto& x, const auto& y) { return x.id < y.id; };  // (COLMAP's order)
  std::sort(b.plan.model.cameras.begin(), b.plan.model.cameras.end(), by_id);
  std::sort(b.plan.model.images.begin(), b.plan.model.images.end(), by_id);
  if (in.rigs_and_frames || b.split) b.rigs_and_frames();
  return std::move(b.plan);
}

}  // namespace panoproj
