#include "jobs/views/camera_files.hpp"

#include <cstdio>

#include <Eigen/Geometry>

#include "base/json_text.hpp"

namespace panoproj {
namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v + 0.0);
  return b;
}

// A rotation's unit quaternion as "w<sep>x<sep>y<sep>z", w >= 0 (COLMAP's order).
std::string wxyz(const Eigen::Matrix3d& r, const char* sep) {
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return num(q.w()) + sep + num(q.x()) + sep + num(q.y()) + sep + num(q.z());
}

// "QW QX QY QZ TX TY TZ" of a rotation without translation (COLMAP's Rigid3d as text).
std::string pose(const Eigen::Matrix3d& r) {
  return wxyz(r, " ") + " 0 0 0";
}

std::string colmap_cameras(const std::vector<ViewCamera>& views) {
  std::string s =
      "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, "
      "PARAMS[]\n"
      "# Number of cameras: " +
      std::to_string(views.size()) + "\n";
  for (size_t v = 0; v < views.size(); ++v) {
    const ViewCamera& c = views[v];
    // PINHOLE: fx fy cx cy; COLMAP's top-left pixel centre is (0.5, 0.5), so the centre is W/2,
    // H/2.
    s += std::to_string(v + 1) + " PINHOLE " + std::to_string(c.size.width) + " " +
         std::to_string(c.size.height) + " " + num(c.focal) + " " + num(c.focal) + " " +
         num(0.5 * static_cast<double>(c.size.width)) + " " +
         num(0.5 * static_cast<double>(c.size.height)) + "\n";
  }
  return s;
}

// One rig: sensor v (camera v + 1) at cam_v_from_rig = R_v^T R_0, the first view the reference.
std::string colmap_rigs(const std::vector<ViewCamera>& views) {
  std::string s =
      "# Rig calib list with one line of data per calib:\n"
      "#   RIG_ID, NUM_SENSORS, REF_SENSOR_TYPE, REF_SENSOR_ID, SENSORS[] as (SENSOR_TYPE, "
      "SENSOR_ID, HAS_POSE, "
      "[QW, QX, QY, QZ, TX, TY, TZ])\n# Number of rigs: 1\n";
  s += "1 " + std::to_string(views.size()) + " CAMERA 1";
  for (size_t v = 1; v < views.size(); ++v)
    s += " CAMERA " + std::to_string(v + 1) + " 1 " +
         pose(views[v].world_from_camera.transpose() * views[0].world_from_camera);
  return s + "\n";
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
         num(c.focal) + ", " + num(c.focal) + ", " + num(0.5 * static_cast<double>(c.size.width)) +
         ", " + num(0.5 * static_cast<double>(c.size.height)) + "]\n      }";
  }
  return s + "\n    ]\n  }\n]\n";
}

// One frame per panorama: rig_from_world = R_0^T (every panorama at the origin, levelled alike).
std::string colmap_frames(const std::vector<ViewCamera>& views, size_t frames) {
  std::string s =
      "# Frame list with one line of data per frame:\n"
      "#   FRAME_ID, RIG_ID, RIG_FROM_WORLD[QW, QX, QY, QZ, TX, TY, TZ], NUM_DATA_IDS, DATA_IDS[] "
      "as "
      "(SENSOR_TYPE, SENSOR_ID, DATA_ID)\n# Number of frames: " +
      std::to_string(frames) + "\n";
  const std::string rig_from_world = pose(views[0].world_from_camera.transpose());
  for (size_t f = 0; f < frames; ++f) {
    s += std::to_string(f + 1) + " 1 " + rig_from_world + " " + std::to_string(views.size());
    for (size_t v = 0; v < views.size(); ++v)
      s += " CAMERA " + std::to_string(v + 1) + " " + std::to_string(f * views.size() + v + 1);
    s += "\n";
  }
  return s;
}

std::string colmap_images(const std::vector<ViewCamera>& views,
                          const std::vector<std::string>& stems, const ViewFiles& files) {
  const size_t n = stems.size() * views.size();
  std::string s =
      "# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, "
      "CAMERA_ID, NAME\n"
      "#   POINTS2D[] as (X, Y, POINT3D_ID)\n# Number of images: " +
      std::to_string(n) + ", mean observations per image: 0\n";
  for (size_t f = 0; f < stems.size(); ++f)
    for (size_t v = 0; v < views.size(); ++v)
      s += std::to_string(f * views.size() + v + 1) + " " +
           pose(views[v].world_from_camera.transpose()) + " " + std::to_string(v + 1) + " " +
           files.image_name(stems[f], views[v].name) + "\n\n";
  return s;
}

const char* kPoints =
    "# 3D point list with one line of data per point:\n"
    "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
    "# Number of points: 0, mean track length: 0\n";

// The intrinsics nerfstudio reads (camera_angle_x/_y too, for readers of Blender's format).
std::string intrinsics(const ViewCamera& c, const std::string& indent) {
  const double w = static_cast<double>(c.size.width), h = static_cast<double>(c.size.height);
  return indent + "\"w\": " + std::to_string(c.size.width) + ",\n" + indent +
         "\"h\": " + std::to_string(c.size.height) + ",\n" + indent + "\"fl_x\": " + num(c.focal) +
         ",\n" + indent + "\"fl_y\": " + num(c.focal) + ",\n" + indent + "\"cx\": " + num(0.5 * w) +
         ",\n" + indent + "\"cy\": " + num(0.5 * h) + ",\n" + indent +
         "\"camera_angle_x\": " + num(2 * std::atan(0.5 * w / c.focal)) + ",\n" + indent +
         "\"camera_angle_y\": " + num(2 * std::atan(0.5 * h / c.focal)) + ",\n" + indent +
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
          s += (c ? ", " : "") + num(r < 3 && c < 3 ? c2w(r, c) : (r == 3 && c == 3 ? 1.0 : 0.0));
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
  std::vector<TextFile> out{{"sparse/0/cameras.txt", colmap_cameras(views)},
                            {"sparse/0/images.txt", colmap_images(views, stems, files)},
                            {"sparse/0/points3D.txt", kPoints},
                            {"sparse/0/rigs.txt", colmap_rigs(views)},
                            {"sparse/0/frames.txt", colmap_frames(views, stems.size())},
                            {"transforms.json", transforms(views, stems, files)}};
  if (files.folders) out.push_back({"rig_config.json", rig_config(views)});
  return out;
}

}  // namespace panoproj
