#pragma once
// COLMAP's cameras (cameras.txt / cameras.bin of a sparse model) as specs: each COLMAP camera
// model by its name and parameter order (COLMAP's sensor/models.h) as the panoproj form that is
// its law, COLMAP's principal point (pixel centres at i + 0.5, as panoproj's) written as the
// specs' OpenCV-convention cx - 0.5. Throws panoproj::Error naming the file and what is wrong.
#include <string>

namespace panoproj {
namespace colmap {
struct Camera;
}

// Whether a spec file is COLMAP's cameras file: "cameras.txt" or "cameras.bin" by name, or text
// with COLMAP's header.
bool is_colmap_cameras(const std::string& text, const std::string& path);
// The spec of the camera with id `id` ("": the file's only camera) of such a file's contents.
std::string colmap_camera_spec(const std::string& text, const std::string& path,
                               const std::string& id);
// The spec of a camera read and checked (io/colmap/model.hpp).
std::string colmap_camera_spec(const colmap::Camera& camera);

}  // namespace panoproj
