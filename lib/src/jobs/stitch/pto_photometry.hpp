#pragma once
// A project's photometry in panoproj's terms (photometry/photometric.hpp): each image's response
// (Rt, Ra..Re), exposure (Eev), white balance (Er Eb) and vignetting (Va..Vd Vx Vy, as Hugin
// reads them: pto_project.hpp), and the output's (the p line's E and R; R_out: image 0's EMoR
// curve, as nona's LDR output).
#include <string>

#include "jobs/stitch/pto_project.hpp"
#include "photometry/photometric.hpp"

namespace panoproj {

// Throws Error naming the image's line for a response that is not one.
Photometry image_photometry(const PtoProject& project, const PtoImage& image);
PhotometricOutput pano_output(const PtoProject& project);
// Why a value the project gives is not used, as nona does not use it ("" if none).
std::string unused_photometry(const PtoProject& project, const PtoImage& image);

}  // namespace panoproj
