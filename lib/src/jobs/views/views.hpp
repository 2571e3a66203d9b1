#pragma once
// Panoramas split into perspective views with their cameras, for SfM, NeRF and Gaussian splatting
// (COLMAP 4.x, nerfstudio). Each view is a pinhole (square pixels, principal point at the centre)
// turned by yaw, pitch, roll (rotation.hpp) in the panorama's frame: x right, y down, z forward at
// the panorama's centre, levelled by a Photo Sphere pose when the file has one.
//
// Rigs (text):
//   cube                           front right back left up down: 90-degree views (up: pitched up
//                                  from front, so its lower edge meets front's upper edge)
//   ring:n=8,fov=90,pitch=0        n views around, first at yaw= (default 0); fov is horizontal,
//                                  vfov= (default fov); names y000, y045 ... (pitch p: y000_p30)
//   A+B                            the views of both (names must differ)
//   @rig.yaml                      a list of views, one mapping each: name, yaw, pitch, roll,
//                                  hfov (or fov), vfov, size (WxH) or width/height; block or flow
//                                  style, optionally under a top key "views:"; the same YAML
//                                  inline (text starting "- " or "views:")
// A video instead of panoramas: each frame taken (jobs/frame_selection.hpp) is a panorama named
// {stem}_NNNNNN (its number among those taken, from 0), decoded as RGB one at a time; not staged
// (its frames are read in order by one process).
// Sizes: a view's own size, else the job's size, else the source's resolution at its centre
// (focal = pixels per radian there). The focal follows from the width and hfov; the height from
// vfov unless given.
//
// Output folder (lands whole, as tiles.hpp's):
//   images/{stem}_{view}.{jpg|png}      one per panorama and view (layout folders:
//                                       images/{view}/{stem}.{ext}, COLMAP's rig layout)
//   masks/<image's name>.png            partial panoramas: 255 where the view is fully covered,
//                                       else 0 (COLMAP's ImageReader.mask_path naming; nerfstudio's
//                                       mask_path)
//   sparse/0/cameras.txt                one PINHOLE camera per view (a rig's sensors are cameras);
//                                       COLMAP's pixels: the top-left pixel's centre is (0.5, 0.5),
//                                       so cx = W / 2, cy = H / 2
//   sparse/0/rigs.txt                   one rig: the first view is its reference sensor, each other
//                                       view's sensor_from_rig its rotation from the first
//   sparse/0/frames.txt                 one frame per panorama: rig_from_world = the first view's
//                                       rotation, no translation
//   sparse/0/images.txt                 cam_from_world = each view's rotation (world: the
//   panorama's
//                                       frame, translation 0). With several panoramas every one is
//                                       put at the origin, levelled the same: the rig is known,
//                                       the frames' poses are what SfM solves
//   sparse/0/points3D.txt               empty
//   panoproj-output.json                the marker of a folder panoproj made (overwrite replaces
//                                       only such a folder)
//   rig_config.json                     layout folders: COLMAP's rig_configurator input (each
//                                       view's image_prefix "{view}/", cam_from_rig, PINHOLE
//                                       intrinsics), for SfM from a feature database
//   transforms.json                     nerfstudio: camera-to-world in OpenGL's camera axes (x
//   right,
//                                       y up, looking down -z), world x right, y forward (the
//                                       panorama's centre), z up; intrinsics as OPENCV without
//                                       distortion (shared at the top when all views share them);
//                                       every camera at the origin (nerfstudio: --auto-scale-poses
//                                       False, it divides by the largest translation)
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "panoproj/image.hpp"

namespace panoproj {

struct ViewSpec {
  std::string name;                     // [A-Za-z0-9_-], 1 to 64 characters
  double yaw = 0, pitch = 0, roll = 0;  // degrees
  double hfov = 90;                     // degrees, (0, 179]
  double vfov = 0;                      // degrees; 0: from the height, else hfov
  int64_t width = 0, height = 0;        // 0: from the job's size or the source's resolution
};

// The views a rig's text names (throws panoproj::Error naming the value and what was expected).
std::vector<ViewSpec> parse_rig(std::string_view text);

// A view as written: size, focal (pixels) and its rotation (world from camera; OpenCV's camera
// axes: x right, y down, z forward).
struct ViewCamera {
  std::string name;
  Size size;
  double focal = 0;
  Eigen::Matrix3d world_from_camera = Eigen::Matrix3d::Identity();
};

// The views' sizes and focals: a view's own size, else `size`, else the source's resolution at
// its centre (`density`, pixels per radian); the focal follows from the width and hfov, the
// height from vfov unless given. Throws Error for a view over 65536 px a side.
std::vector<ViewCamera> view_cameras(const std::vector<ViewSpec>& rig, std::optional<Size> size,
                                     double density);

}  // namespace panoproj
