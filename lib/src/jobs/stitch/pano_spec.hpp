#pragma once
// A project's projections as panoproj specs: the panorama's (the p line's f, v and size) and each
// image's (panotools.hpp: the i line's lens type, v, a b c d e g t), each matched to libpano13's
// scaling (adjust.c's distance per format); a format panoproj lacks is refused naming the line.
#include <string>

#include "jobs/stitch/pto_project.hpp"
#include "panoproj/conventions.hpp"

namespace panoproj {

// The panorama's spec ("equirect:hfov=360,vfov=180"); throws Error naming the p line's f.
std::string pano_spec(const PtoProject& project);
// An image's spec, its shift and shear scaled by (sx, sy) (a file of another size than the
// project says: its pixels per the project's).
std::string image_spec(const PtoProject& project, const PtoImage& image, double sx = 1,
                       double sy = 1);
// Hugin's image orientation (y, p, r): the rotation that takes the panorama's rays to the image's.
Eigen::Matrix3d image_rotation(const PtoImage& image);

}  // namespace panoproj
