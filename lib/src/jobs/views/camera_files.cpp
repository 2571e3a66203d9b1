#include "jobs/views/camera_files.hpp"

#include <cstdio>

#include <Eigen/Geometry>

#include "base/json_text.hpp"
#include "base/text.hpp"
#include "io/colmap/model.hpp"

namespace panoproj {
namespace {

// A rotation's unit quaternion as "w<sep>x<sep>y<sep>z", w >= 0 (COLMAP's order).
std::string wxyz(const Eigen::Matrix3d& r, const char* sep) {
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return number_text(q.w()) + sep + number_text(q.x()) + sep + number_text(q.y()) + sep +
         number_text(q.z());
}

// COLMAP's rig_configurator input: sensor v's images under "{view}/", its cam_from_rig (the
// rotation [w, x, y, z]) and intrinsics, the first view the reference.
std::string rig_config(const std::vector<ViewCamera>& views) {
  std::string s = "[\n  {\n    \"cameras\": [";
  for (size_t v = 0; v < views.size(); ++v) {
    const ViewCamera& c = views[v];
    s += v ? ",\n" : "\n";
    s += "      {\n        \"image_prefix\": " + json_string(c.name + "/") + ",\n";
    if (v == 0) {
      s += "        \"ref_sensor\": true,\n";
    } else {
      s += "        \"cam_from_rig_rotation\": [" +
           wxyz(c.world_from_camera.transpose() * views[0].world_from_camera, ", ") +
           "],\n        \"cam_from_rig_translation\": [0, 0, 0],\n";
    }
    s += "        \"camera_model_name\": \"PINHOLE\",\n        \"camera_params\": [" +
         number_text(c.focal) + ", " + number_text(c.focal) + ", " +
         number_text(0.5 * static_cast<double>(c.size.width)) + ", " +
         number_text(0.5 * static_cast<double>(c.size.height)) + "]\n      }";
  }
  return s + "\n    ]\n  }\n]\n";
}

// COLMAP's model of the views (io/colmap/model.hpp writes it): a PINHOLE camera per view (COLMAP's
// top-left pixel centre is (0.5, 0.5), so the principal point is W/2, H/2); one rig, the first
// view its reference and each other's sensor_from_rig = R_v^T R_0; one frame per panorama,
// rig_from_world = R_0^T (every panorama at the origin, levelled alike); each image's
// cam_from_world = R_v^T; no points.
colmap::Model colmap_model(const std::vector<ViewCamera>& views,
                           const std::vector<std::string>& stems, const ViewFiles& files) {
  colmap::Model m;
  m.rigs_and_frames = true;
  auto rotation = [](const Eigen::Matrix3d& r) {
    return colmap::pose_of(r, Eigen::Vector3d::Zero());
  };
  colmap::Rig rig{1, {}};
  for (size_t v = 0; v < views.size(); ++v) {
    const ViewCamera& c = views[v];
    const auto id = static_cast<uint32_t>(v + 1);
    const double w = static_cast<double>(c.size.width), h = static_cast<double>(c.size.height);
    m.cameras.push_back({id,
                         "PINHOLE",
                         static_cast<uint64_t>(c.size.width),
                         static_cast<uint64_t>(c.size.height),
                         {c.focal, c.focal, 0.5 * w, 0.5 * h}});
    rig.sensors.push_back(
        {colmap::SensorType::Camera, id,
         v == 0 ? std::nullopt
                : std::optional<colmap::Pose>(
                      rotation(c.world_from_camera.transpose() * views[0].world_from_camera))});
  }
  m.rigs.push_back(std::move(rig));
  for (size_t f = 0; f < stems.size(); ++f) {
    colmap::Frame frame{
        static_cast<uint32_t>(f + 1), 1, rotation(views[0].world_from_camera.transpose()), {}};
    for (size_t v = 0; v < views.size(); ++v) {
      const auto id = static_cast<uint32_t>(f * views.size() + v + 1);
      frame.data.push_back({colmap::SensorType::Camera, static_cast<uint32_t>(v + 1), id});
      m.images.push_back({id,
                          rotation(views[v].world_from_camera.transpose()),
                          static_cast<uint32_t>(v + 1),
                          files.image_name(stems[f], views[v].name),
                          {}});
    }
    m.frames.push_back(std::move(frame));
  }
  return m;
}

// The intrinsics nerfstudio reads (camera_angle_x/_y too, for readers of Blender's format).
std::string intrinsics(const ViewCamera& c, const std::string& indent) {
  const double w = static_cast<double>(c.size.width), h = static_cast<double>(c.size.height);
  return indent + "\"w\": " + std::to_string(c.size.width) + ",\n" + indent +
         "\"h\": " + std::to_string(c.size.height) + ",\n" + indent +
         "\"fl_x\": " + number_text(c.focal) + ",\n" + indent +
         "\"fl_y\": " + number_text(c.focal) + ",\n" + indent + "\"cx\": " + number_text(0.5 * w) +
         ",\n" + indent + "\"cy\": " + number_text(0.5 * h) + ",\n" + indent +
         "\"camera_angle_x\": " + number_text(2 * std::atan(0.5 * w / c.focal)) + ",\n" + indent +
         "\"camera_angle_y\": " + number_text(2 * std::atan(0.5 * h / c.focal)) + ",\n" + indent +
         "\"k1\": 0,\n" + indent + "\"k2\": 0,\n" + indent + "\"p1\": 0,\n" + indent +
         "\"p2\": 0,\n";
}

// nerfstudio: camera-to-world with OpenGL's camera axes (x right, y up, z back), the world turned
// z up: (x, y, z)_panoproj -> (x, z, -y).
std::string transforms(const std::vector<ViewCamera>& views, const std::vector<std::string>& stems,
                       const ViewFiles& files) {
  bool shared = true;
  for (const ViewCamera& c : views)
    shared = shared && c.size == views[0].size && c.focal == views[0].focal;
  Eigen::Matrix3d to_z_up;
  to_z_up << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  const Eigen::Matrix3d gl = Eigen::Vector3d(1, -1, -1).asDiagonal();
  std::string s = "{\n  \"camera_model\": \"OPENCV\",\n";
  if (shared) s += intrinsics(views[0], "  ");
  s += "  \"frames\": [";
  for (size_t f = 0; f < stems.size(); ++f)
    for (size_t v = 0; v < views.size(); ++v) {
      s += f + v == 0 ? "\n" : ",\n";
      s += "    {\n      \"file_path\": " + json_string(files.image_path(stems[f], views[v].name)) +
           ",\n";
      if (files.masks)
        s +=
            "      \"mask_path\": " + json_string(files.mask_path(stems[f], views[v].name)) + ",\n";
      if (!shared) s += intrinsics(views[v], "      ");
      const Eigen::Matrix3d c2w = to_z_up * views[v].world_from_camera * gl;
      s += "      \"transform_matrix\": [";
      for (int r = 0; r < 4; ++r) {
        s += r ? ", [" : "[";
        for (int c = 0; c < 4; ++c)
          s += (c ? ", " : "") +
               number_text(r < 3 && c < 3 ? c2w(r, c) : (r == 3 && c == 3 ? 1.0 : 0.0));
        s += "]";
      }
      s += "]\n    }";
    }
  return s + "\n  ]\n}\n";
}

}  // namespace

std::string ViewFiles::image_name(const std::string& stem, const std::string& view) const {
  return folders ? view + "/" + stem + "." + ext : stem + "_" + view + "." + ext;
}

std::vector<TextFile> camera_files(const std::vector<ViewCamera>& views,
                                   const std::vector<std::string>& stems, const ViewFiles& files) {
  std::vector<TextFile> out;
  for (colmap::File& f : colmap::model_files(colmap_model(views, stems, files), false, "sparse/0/"))
    out.push_back({std::move(f.path), std::move(f.bytes)});
  out.push_back({"transforms.json", transforms(views, stems, files)});
  if (files.folders) out.push_back({"rig_config.json", rig_config(views)});
  return out;
}

}  // namespace panoproj
