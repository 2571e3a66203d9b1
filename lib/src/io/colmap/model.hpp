#pragma once
// COLMAP's sparse models (a folder of cameras, images, points3D and, since COLMAP 3.12, rigs and
// frames; .txt or .bin, COLMAP's reconstruction_io_text / _binary layouts): read, checked, and
// written back with every value as read (text numbers to 17 digits, so binary <-> text is
// exact). A model without rigs and frames (COLMAP 3.x) is kept so and written so. Throws
// panoproj::Error naming the file and what is wrong (ErrorKind::File for files that cannot be
// read).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

namespace panoproj::colmap {

// COLMAP's camera models: name (its id is the index), parameter count.
struct CameraModel {
  const char* name;
  size_t params;
};
const std::vector<CameraModel>& camera_models();
const CameraModel* camera_model(std::string_view name);  // nullptr: not COLMAP's
std::string camera_model_names();                        // "SIMPLE_PINHOLE, PINHOLE, ..."

// A rigid transform as COLMAP stores it: QW QX QY QZ TX TY TZ (b_from_a maps a's points to b).
using Pose = std::array<double, 7>;
inline constexpr Pose kIdentity{1, 0, 0, 0, 0, 0, 0};
Eigen::Matrix3d rotation_of(const Pose& p);
Eigen::Vector3d translation_of(const Pose& p);
Pose pose_of(const Eigen::Matrix3d& r, const Eigen::Vector3d& t);  // qw >= 0
// b_from_world (either side the identity: the other as it is)
Pose compose(const Pose& b_from_a, const Pose& a_from_world);

inline constexpr uint64_t kNoPoint3D = ~uint64_t{0};  // -1 in text

struct Camera {
  uint32_t id = 0;
  std::string model;  // a camera_models() name
  uint64_t width = 0, height = 0;
  std::vector<double> params;
};
struct Point2D {
  double x = 0, y = 0;
  uint64_t point3d = kNoPoint3D;
};
struct Image {
  uint32_t id = 0;
  Pose cam_from_world = kIdentity;
  uint32_t camera = 0;
  std::string name;
  std::vector<Point2D> points;
};
// Sensor types as COLMAP numbers them.
enum class SensorType : int32_t { Invalid = -1, Camera = 0, Imu = 1 };
struct Sensor {
  SensorType type = SensorType::Camera;
  uint32_t id = 0;
  std::optional<Pose> from_rig;  // none for the reference sensor, or a pose not known
};
struct Rig {
  uint32_t id = 0;
  std::vector<Sensor> sensors;  // the first is the reference sensor
};
struct Data {
  SensorType type = SensorType::Camera;
  uint32_t sensor = 0;
  uint64_t id = 0;  // an image id for cameras
};
struct Frame {
  uint32_t id = 0, rig = 0;
  Pose rig_from_world = kIdentity;
  std::vector<Data> data;
};
struct TrackElement {
  uint32_t image = 0, point2d = 0;
};
struct Point3D {
  uint64_t id = 0;
  std::array<double, 3> xyz{};
  std::array<uint8_t, 3> rgb{};
  double error = 0;
  std::vector<TrackElement> track;
};

struct Model {
  std::vector<Camera> cameras;
  std::vector<Image> images;
  std::vector<Point3D> points;
  bool rigs_and_frames = false;  // COLMAP 3.12 and later; else none (3.x)
  std::vector<Rig> rigs;
  std::vector<Frame> frames;

  const Camera* camera(uint32_t id) const;
};

// The files of a model folder, as read.
struct ModelFiles {
  bool binary = false;
  std::string cameras, images, points, rigs, frames;  // rigs, frames: "" when absent
  bool rigs_and_frames = false;
};

// The model in folder `dir` (the .bin files if cameras.bin is there, else the .txt ones; rigs and
// frames both or neither), each file at most `max_bytes`. Checked: every id unique, every
// reference (an image's camera, a frame's rig and data, a rig's cameras, a track's image and
// point, an observation's point) to something in the model, every camera's parameter count and
// a finite, non-zero size, finite numbers.
Model read_model(const std::string& dir, int64_t max_bytes);
// The same from files' contents (`dir` names them in messages).
Model parse_model(const ModelFiles& files, const std::string& dir);
// One file's cameras (cameras.txt or cameras.bin's contents), each checked.
std::vector<Camera> parse_cameras(std::string_view bytes, bool binary, const std::string& path);
void check_model(const Model& m, const std::string& dir, const std::string& ext);  // ext: ".txt"

struct File {
  std::string path, bytes;
};
// The model's files, named "<prefix>cameras.txt" ... or ".bin", in COLMAP's order and layout
// (rigs and frames only if the model has them).
std::vector<File> model_files(const Model& m, bool binary, const std::string& prefix);

// The text and binary layouts (model_text.cpp, model_binary.cpp).
std::vector<Camera> cameras_text(std::string_view s, const std::string& path);
std::vector<Image> images_text(std::string_view s, const std::string& path);
std::vector<Point3D> points_text(std::string_view s, const std::string& path);
std::vector<Rig> rigs_text(std::string_view s, const std::string& path);
std::vector<Frame> frames_text(std::string_view s, const std::string& path);
std::vector<Camera> cameras_binary(std::string_view s, const std::string& path);
std::vector<Image> images_binary(std::string_view s, const std::string& path);
std::vector<Point3D> points_binary(std::string_view s, const std::string& path);
std::vector<Rig> rigs_binary(std::string_view s, const std::string& path);
std::vector<Frame> frames_binary(std::string_view s, const std::string& path);
std::string write_text(const std::vector<Camera>& v);
std::string write_text(const std::vector<Image>& v);
std::string write_text(const std::vector<Point3D>& v);
std::string write_text(const std::vector<Rig>& v);
std::string write_text(const std::vector<Frame>& v);
std::string write_binary(const std::vector<Camera>& v);
std::string write_binary(const std::vector<Image>& v);
std::string write_binary(const std::vector<Point3D>& v);
std::string write_binary(const std::vector<Rig>& v);
std::string write_binary(const std::vector<Frame>& v);

}  // namespace panoproj::colmap
