// A project's photometry (pto_photometry.hpp).
#include "jobs/stitch/pto_photometry.hpp"

namespace panoproj {
namespace {

std::string where(const PtoProject& project, const PtoImage& image) {
  return project.path + ":" + std::to_string(image.line) + ": i line";
}

}  // namespace

Photometry image_photometry(const PtoProject& project, const PtoImage& image) {
  Photometry p;
  if (image.response_type == 0) p.response = Response::emor(image.emor, where(project, image));
  p.exposure = image.exposure;
  p.red = image.red;
  p.blue = image.blue;
  p.vignetting.coefficients = image.vignetting;
  p.vignetting.shift_x = image.vignetting_x;
  p.vignetting.shift_y = image.vignetting_y;
  return p;
}

PhotometricOutput pano_output(const PtoProject& project) {
  PhotometricOutput o;
  o.hdr = project.pano.hdr;
  o.exposure = project.pano.exposure;
  // nona's LDR output: the codes of image 0's EMoR curve (Stitcher.cpp), whatever its Rt.
  o.response = Response::emor(project.images.at(0).emor, where(project, project.images.at(0)));
  return o;
}

std::string unused_photometry(const PtoProject& project, const PtoImage& image) {
  std::string why;
  if (!image.flat_field.empty())
    why = "Vf\"" + image.flat_field + "\" (a flat field)";
  else if (image.vignetting_mode != 5 && image.vignetting_mode != 0)
    why = "Vm" + std::to_string(image.vignetting_mode) + " and its Va..Vd";
  if (why.empty()) return "";
  return where(project, image) + ": " + why +
         " not applied: Hugin 2022 reads every vignetting mode but Vm5 as none, and nona renders "
         "it so";
}

}  // namespace panoproj
