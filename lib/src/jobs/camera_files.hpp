#pragma once
// The views job's camera files (views.hpp): COLMAP 4.x's text model and nerfstudio's
// transforms.json, and the paths of the images and masks they name. Internal to the views job.
#include <string>
#include <vector>

#include "panoproj/views.hpp"
#include "io/atomic_output.hpp"

namespace panoproj {

// A view image's name as COLMAP's images.txt holds it (relative to images/).
std::string view_image_name(const std::string& stem, const std::string& view, const std::string& ext);
// Within the output folder.
std::string view_image_path(const std::string& stem, const std::string& view, const std::string& ext);
std::string view_mask_path(const std::string& stem, const std::string& view, const std::string& ext);

// sparse/0/{cameras,images,points3D,rigs,frames}.txt and transforms.json.
std::vector<TextFile> camera_files(const std::vector<ViewCamera>& views, const std::vector<std::string>& stems,
                                   const std::string& ext, bool masks);

}  // namespace panoproj
