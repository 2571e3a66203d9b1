// COLMAP's models: the camera models, poses, reading a folder and checking it (model.hpp).
#include "io/colmap/model.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unordered_map>
#include <unordered_set>

#include "base/input_check.hpp"
#include "base/text.hpp"
#include "panoproj/error.hpp"

namespace panoproj::colmap {
namespace {

bool finite(const Pose& p) {
  for (double v : p)
    if (!std::isfinite(v)) return false;
  return p[0] != 0 || p[1] != 0 || p[2] != 0 || p[3] != 0;
}

void check_pose(const Pose& p, const std::string& where) {
  if (!finite(p))
    throw Error(where + " has the pose " + number_text(p[0]) + " " + number_text(p[1]) + " " +
                number_text(p[2]) + " " + number_text(p[3]) + " " + number_text(p[4]) + " " +
                number_text(p[5]) + " " + number_text(p[6]) +
                " (expected finite numbers, a non-zero quaternion)");
}

// Ids listed once each; returns id -> index.
template <typename T, typename Id>
std::unordered_map<Id, size_t> index_of(const std::vector<T>& v, const char* what,
                                        const std::string& file) {
  std::unordered_map<Id, size_t> at;
  for (size_t i = 0; i < v.size(); ++i)
    if (!at.emplace(static_cast<Id>(v[i].id), i).second)
      throw Error(file + ": " + what + " " + std::to_string(v[i].id) + " is listed twice");
  return at;
}

constexpr uint64_t kMaxSide = uint64_t{1} << 20;

}  // namespace

const std::vector<CameraModel>& camera_models() {
  // COLMAP's sensor/models.h, in the order of its ids.
  static const std::vector<CameraModel> models{{"SIMPLE_PINHOLE", 3},
                                               {"PINHOLE", 4},
                                               {"SIMPLE_RADIAL", 4},
                                               {"RADIAL", 5},
                                               {"OPENCV", 8},
                                               {"OPENCV_FISHEYE", 8},
                                               {"FULL_OPENCV", 12},
                                               {"FOV", 5},
                                               {"SIMPLE_RADIAL_FISHEYE", 4},
                                               {"RADIAL_FISHEYE", 5},
                                               {"THIN_PRISM_FISHEYE", 12},
                                               {"RAD_TAN_THIN_PRISM_FISHEYE", 16},
                                               {"SIMPLE_DIVISION", 4},
                                               {"DIVISION", 5},
                                               {"SIMPLE_FISHEYE", 3},
                                               {"FISHEYE", 4},
                                               {"EUCM", 6},
                                               {"EQUIRECTANGULAR", 2}};
  return models;
}

const CameraModel* camera_model(std::string_view name) {
  for (const CameraModel& m : camera_models())
    if (name == m.name) return &m;
  return nullptr;
}

std::string camera_model_names() {
  std::string s;
  for (const CameraModel& m : camera_models()) s += std::string(s.empty() ? "" : ", ") + m.name;
  return s;
}

Eigen::Matrix3d rotation_of(const Pose& p) {
  return Eigen::Quaterniond(p[0], p[1], p[2], p[3]).normalized().toRotationMatrix();
}

Eigen::Vector3d translation_of(const Pose& p) {
  return {p[4], p[5], p[6]};
}

Pose pose_of(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return {q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z()};
}

Pose compose(const Pose& b_from_a, const Pose& a_from_world) {
  if (b_from_a == kIdentity) return a_from_world;  // (bit for bit)
  if (a_from_world == kIdentity) return b_from_a;
  const Eigen::Matrix3d r = rotation_of(b_from_a);
  return pose_of(r * rotation_of(a_from_world),
                 r * translation_of(a_from_world) + translation_of(b_from_a));
}

const Camera* Model::camera(uint32_t id) const {
  for (const Camera& c : cameras)
    if (c.id == id) return &c;
  return nullptr;
}

std::vector<Camera> parse_cameras(std::string_view bytes, bool binary, const std::string& path) {
  std::vector<Camera> cams = binary ? cameras_binary(bytes, path) : cameras_text(bytes, path);
  index_of<Camera, uint32_t>(cams, "camera", path);
  for (const Camera& c : cams) {
    const CameraModel* m = camera_model(c.model);
    const std::string where = path + ": camera " + std::to_string(c.id) + " ";
    if (!m)
      throw Error(where + "has the model " + c.model.substr(0, 40) +
                  " (expected one of COLMAP's: " + camera_model_names() + ")");
    if (c.params.size() != m->params)
      throw Error(where + "(" + c.model + ") has " + std::to_string(c.params.size()) +
                  " parameters (expected " + std::to_string(m->params) + ")");
    for (double v : c.params)
      if (!std::isfinite(v))
        throw Error(where + "has a parameter " + number_text(v) + " (expected finite numbers)");
    if (c.width < 1 || c.height < 1 || c.width > kMaxSide || c.height > kMaxSide)
      throw Error(where + "is " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                  " pixels (expected 1 to " + std::to_string(kMaxSide) + " each way)");
  }
  return cams;
}

void check_model(const Model& m, const std::string& dir, const std::string& ext) {
  const std::string f = dir + "/";
  const auto cams = index_of<Camera, uint32_t>(m.cameras, "camera", f + "cameras" + ext);
  const auto images = index_of<Image, uint32_t>(m.images, "image", f + "images" + ext);
  const auto points = index_of<Point3D, uint64_t>(m.points, "point3D", f + "points3D" + ext);
  std::unordered_set<std::string> names;
  for (const Image& im : m.images) {
    const std::string where = f + "images" + ext + ": image " + std::to_string(im.id);
    if (!cams.count(im.camera))
      throw Error(where + " has the camera " + std::to_string(im.camera) +
                  ", which cameras does not list");
    check_pose(im.cam_from_world, where);
    if (im.name.empty() || im.name.find_first_of(" \t\r\n") != std::string::npos)
      throw Error(where + " has the name '" + im.name.substr(0, 80) +
                  "' (expected a name without spaces)");
    if (!names.insert(im.name).second)
      throw Error(where + ": the name " + im.name.substr(0, 80) + " is another image's too");
    for (size_t k = 0; k < im.points.size(); ++k) {
      const Point2D& p = im.points[k];
      if (!std::isfinite(p.x) || !std::isfinite(p.y))
        throw Error(where + ": point2D " + std::to_string(k) + " is at " + number_text(p.x) + ", " +
                    number_text(p.y) + " (expected finite numbers)");
      if (p.point3d != kNoPoint3D && !points.count(p.point3d))
        throw Error(where + ": point2D " + std::to_string(k) + " sees the point3D " +
                    std::to_string(p.point3d) + ", which points3D does not list");
    }
  }
  for (const Point3D& p : m.points) {
    const std::string where = f + "points3D" + ext + ": point3D " + std::to_string(p.id);
    if (p.id == kNoPoint3D) throw Error(where + " has an id kept for none");
    for (double v : p.xyz)
      if (!std::isfinite(v))
        throw Error(where + " is at " + number_text(v) + " (expected finite numbers)");
    for (const TrackElement& e : p.track) {
      const auto at = images.find(e.image);
      if (at == images.end())
        throw Error(where + " is seen by the image " + std::to_string(e.image) +
                    ", which images does not list");
      if (e.point2d >= m.images[at->second].points.size())
        throw Error(where + " is seen by point2D " + std::to_string(e.point2d) + " of image " +
                    std::to_string(e.image) + ", which has " +
                    std::to_string(m.images[at->second].points.size()));
    }
  }
  if (!m.rigs_and_frames) return;
  const auto rigs = index_of<Rig, uint32_t>(m.rigs, "rig", f + "rigs" + ext);
  index_of<Frame, uint32_t>(m.frames, "frame", f + "frames" + ext);
  std::unordered_map<uint32_t, uint32_t> rig_of_camera;
  for (const Rig& r : m.rigs) {
    const std::string where = f + "rigs" + ext + ": rig " + std::to_string(r.id);
    if (r.sensors.empty()) throw Error(where + " has no sensors");
    for (const Sensor& s : r.sensors) {
      if (s.type != SensorType::Camera && s.type != SensorType::Imu)
        throw Error(where + " has a sensor of type " + std::to_string(static_cast<int>(s.type)) +
                    " (expected CAMERA or IMU)");
      if (s.from_rig) check_pose(*s.from_rig, where);
      if (s.type != SensorType::Camera) continue;
      if (!cams.count(s.id))
        throw Error(where + " has the camera " + std::to_string(s.id) +
                    ", which cameras does not list");
      if (!rig_of_camera.emplace(s.id, r.id).second)
        throw Error(where + ": camera " + std::to_string(s.id) + " is a sensor of two rigs");
    }
  }
  std::unordered_map<uint32_t, uint32_t> frame_of_image;
  for (const Frame& fr : m.frames) {
    const std::string where = f + "frames" + ext + ": frame " + std::to_string(fr.id);
    const auto r = rigs.find(fr.rig);
    if (r == rigs.end())
      throw Error(where + " has the rig " + std::to_string(fr.rig) + ", which rigs does not list");
    check_pose(fr.rig_from_world, where);
    for (const Data& d : fr.data) {
      if (d.type != SensorType::Camera) continue;
      const auto im = images.find(static_cast<uint32_t>(d.id));
      if (d.id > UINT32_MAX || im == images.end())
        throw Error(where + " has the image " + std::to_string(d.id) +
                    ", which images does not list");
      const auto rc = rig_of_camera.find(d.sensor);
      if (rc == rig_of_camera.end() || rc->second != fr.rig ||
          m.images[im->second].camera != d.sensor)
        throw Error(where + ": image " + std::to_string(d.id) + " is named as camera " +
                    std::to_string(d.sensor) + "'s (its camera is " +
                    std::to_string(m.images[im->second].camera) + "; rig " +
                    std::to_string(fr.rig) + "'s cameras must take it)");
      if (!frame_of_image.emplace(static_cast<uint32_t>(d.id), fr.id).second)
        throw Error(where + ": image " + std::to_string(d.id) + " is in two frames");
    }
  }
  for (const Image& im : m.images)
    if (!frame_of_image.count(im.id))
      throw Error(f + "frames" + ext + ": no frame holds the image " + std::to_string(im.id));
}

Model parse_model(const ModelFiles& files, const std::string& dir) {
  const std::string ext = files.binary ? ".bin" : ".txt";
  const std::string p = dir + "/";
  Model m;
  m.cameras = parse_cameras(files.cameras, files.binary, p + "cameras" + ext);
  m.images = files.binary ? images_binary(files.images, p + "images" + ext)
                          : images_text(files.images, p + "images" + ext);
  m.points = files.binary ? points_binary(files.points, p + "points3D" + ext)
                          : points_text(files.points, p + "points3D" + ext);
  m.rigs_and_frames = files.rigs_and_frames;
  if (m.rigs_and_frames) {
    m.rigs = files.binary ? rigs_binary(files.rigs, p + "rigs" + ext)
                          : rigs_text(files.rigs, p + "rigs" + ext);
    m.frames = files.binary ? frames_binary(files.frames, p + "frames" + ext)
                            : frames_text(files.frames, p + "frames" + ext);
  }
  check_model(m, dir, ext);
  return m;
}

Model read_model(const std::string& dir, int64_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error("cannot read the model " + dir + ": " +
                    (fs::exists(dir, ec) ? "not a folder" : "no such folder") +
                    " (expected a COLMAP model folder such as sparse/0)",
                ErrorKind::Missing);
  ModelFiles files;
  files.binary = fs::exists(dir + "/cameras.bin", ec);
  if (!files.binary && !fs::exists(dir + "/cameras.txt", ec))
    throw Error("cannot read the model " + dir +
                    ": it has no cameras.bin or cameras.txt (expected a COLMAP model folder such "
                    "as sparse/0)",
                ErrorKind::Missing);
  const std::string ext = files.binary ? ".bin" : ".txt";
  const size_t most = static_cast<size_t>(max_bytes);
  auto read = [&](const char* name) {
    const std::string path = dir + "/" + name + ext;
    std::string s = read_head(path, most + 1, "the model file", "a COLMAP model file");
    if (s.size() > most)
      throw Error(path + " is over " + std::to_string(most >> 20) +
                  " MiB (raise --memory-limit to read it)");
    return s;
  };
  files.cameras = read("cameras");
  files.images = read("images");
  // (A model without points3D, as some tools write for known poses, has none.)
  if (fs::exists(dir + "/points3D" + ext, ec))
    files.points = read("points3D");
  else if (files.binary)
    files.points = std::string(8, '\0');
  const bool rigs = fs::exists(dir + "/rigs" + ext, ec),
             frames = fs::exists(dir + "/frames" + ext, ec);
  if (rigs != frames)
    throw Error("cannot read the model " + dir + ": it has " + (rigs ? "rigs" : "frames") + ext +
                " but no " + (rigs ? "frames" : "rigs") + ext +
                " (expected both, COLMAP 3.12 and later, or neither)");
  if (rigs) {
    files.rigs_and_frames = true;
    files.rigs = read("rigs");
    files.frames = read("frames");
  }
  return parse_model(files, dir);
}

std::vector<File> model_files(const Model& m, bool binary, const std::string& prefix) {
  auto file = [&](const char* name, const auto& v) {
    return File{prefix + name + (binary ? ".bin" : ".txt"),
                binary ? write_binary(v) : write_text(v)};
  };
  std::vector<File> out{file("cameras", m.cameras), file("images", m.images),
                        file("points3D", m.points)};
  if (m.rigs_and_frames) {
    out.push_back(file("rigs", m.rigs));
    out.push_back(file("frames", m.frames));
  }
  return out;
}

}  // namespace panoproj::colmap
