#pragma once
// The views job's camera files (views.hpp): COLMAP 4.x's text model and nerfstudio's
// transforms.json, and the paths of the images and masks they name. Internal to the views job.
#include <string>
#include <vector>

#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "jobs/views/views.hpp"

namespace panoproj {

// How the views' files are named.
struct ViewFiles {
  std::string ext;  // jpg | png
  bool folders =
      false;  // images/{view}/{stem}.{ext} (COLMAP's rig layout), else images/{stem}_{view}.{ext}
  bool masks = false;  // masks/<the image's name>.png
  // As COLMAP's images.txt holds it (relative to images/).
  std::string image_name(const std::string& stem, const std::string& view) const;
  // Within the output folder.
  std::string image_path(const std::string& stem, const std::string& view) const {
    return "images/" + image_name(stem, view);
  }
  std::string mask_path(const std::string& stem, const std::string& view) const {
    return "masks/" + image_name(stem, view) + std::string(kPngFormat.extensions[0]);
  }
};

// sparse/0/{cameras,images,points3D,rigs,frames}.txt, transforms.json and, with folders,
// rig_config.json (COLMAP's rig_configurator: image_prefix "{view}/").
std::vector<TextFile> camera_files(const std::vector<ViewCamera>& views,
                                   const std::vector<std::string>& stems, const ViewFiles& files);

}  // namespace panoproj
