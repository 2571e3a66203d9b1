#pragma once
// The undistort job's plan (internal): what each camera of a COLMAP model becomes and the model
// written beside the undistorted images.
//
// A camera whose field (twice the largest angle off its axis of any pixel that has a ray) is at
// most max_fov becomes one PINHOLE camera, chosen as COLMAP's image_undistorter chooses it (a
// SIMPLE_PINHOLE or PINHOLE camera is kept as it is unless max_image_size shrinks it): its
// focal lengths and principal point kept, then the frame scaled about the principal point so
// that blank_pixels = 1 keeps every source pixel and 0 leaves no pixel without a source
// (interpolated between), each scale clamped to [min_scale, max_scale], then the whole camera
// shrunk to max_image_size (0: none); of a region of interest (roi) and without border points
// past max_cam_point_norm where given. A wider camera (a fisheye, past 180 degrees too, or an
// EQUIRECTANGULAR one) becomes a rig of pinhole views around its axis (the views job's rigs,
// cube by default; views.hpp), those that see none of its pixels left out.
//
// The new model: pinhole cameras and their images keep their ids and names; a camera's views
// are new cameras, each image's views new images named "{view}/{name}": the first view keeps the
// camera's (image's) id, view v > 0 of the rig's n takes last + index x (n - 1) + v, where last
// is the model's largest id and index the camera's (image's) place in the model, so any image's
// outputs are known without planning the others (views a camera does not see leave theirs
// unused). Observations
// (points2D) move to where their ray falls in the new image (a view's: the first view that holds
// it; one that none holds is dropped, and tracks follow). Rigs: each camera's sensor becomes its
// pinhole camera or its views (sensor_from_rig turned by each view's rotation); when a rig's
// reference camera is split, its first view becomes the reference and the rig's frame turns with
// it (frames' rig_from_world). A model without rigs (COLMAP 3.x) stays so unless a camera is
// split: it then gets COLMAP's implicit rigs (one per camera, one frame per image).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/colmap/model.hpp"
#include "jobs/views/views.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

struct UndistortOptions {
  double max_fov = 120;     // degrees: the widest field undistorted to one pinhole
  double blank_pixels = 0;  // [0, 1]
  double min_scale = 0.2, max_scale = 2;
  int64_t max_image_size = 0;             // pixels a side; 0: none
  std::array<double, 4> roi{0, 0, 1, 1};  // the source's region: x0, y0, x1, y1 (fractions)
  double max_cam_point_norm = 0;          // border points past this tan(theta) skipped; 0: none
  std::vector<ViewSpec> rig;              // a wide camera's views
  std::optional<Size> size;  // each view's size (else the camera's resolution at its centre)
  std::string extension;     // the images' (".jpg", ".png"); "": each name's own
};

// One image written: its name in the new model, camera, and where it looks from the source
// camera.
struct OutputImage {
  std::string name;
  uint32_t id = 0, camera = 0;
  Size size;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // COLMAP's (pixel centres at i + 0.5)
  Eigen::Matrix3d camera_from_view = Eigen::Matrix3d::Identity();
  bool view = false;  // a wide camera's view (masked where it sees no source)
};

struct CameraPlan {
  colmap::Camera camera;                // the source camera
  std::string spec;                     // its spec (spec/colmap_cameras.hpp)
  double field = 0;                     // degrees
  bool pinhole = false;                 // else views
  std::vector<colmap::Camera> cameras;  // the new cameras: one pinhole (or the camera, kept), or
                                        // one per view
  std::vector<ViewCamera> views;        // the views (their rotation: camera from view)
  std::vector<size_t> rig_index;        // each view's place in the rig
};

// The largest camera and image ids of a model (the views' ids follow them).
struct LastIds {
  uint32_t camera = 0, image = 0;
};
LastIds last_ids(const colmap::Model& m);
// View v's id of a rig of `views` (v = 0: `own`), for the camera or image at `index`.
uint32_t view_id(uint32_t own, uint32_t last, size_t index, size_t views, size_t v,
                 const std::string& dir, const char* what);

struct UndistortPlan {
  std::vector<CameraPlan> cameras;               // the model's, in its order
  std::vector<std::vector<OutputImage>> images;  // each image's outputs, the model's order
  colmap::Model model;                           // the new model
};

// COLMAP's focal lengths and principal point of a camera of a model that has them (one focal
// length for the SIMPLE_ models, RADIAL and the radial fisheyes).
struct Intrinsics {
  double fx, fy, cx, cy;
};
Intrinsics intrinsics_of(const colmap::Camera& c);
// A source camera's projection on its frame.
Projection camera_projection(const CameraPlan& plan);
// Camera `index` of the model; throws Error naming `dir` where the views' ids pass 2^32 - 1.
CameraPlan plan_camera(const colmap::Camera& camera, const UndistortOptions& o, size_t index,
                       LastIds last, const std::string& dir);
// Image `index`'s outputs (its camera's plan `cp`).
std::vector<OutputImage> image_outputs(const colmap::Image& im, size_t index, const CameraPlan& cp,
                                       const UndistortOptions& o, LastIds last,
                                       const std::string& dir);
// Throws Error naming the model and what cannot be undistorted (an image name that leaves the
// folder, ids that overflow).
UndistortPlan plan_undistort(const colmap::Model& in, const UndistortOptions& o,
                             const std::string& model_dir);

}  // namespace panoproj
