// Project lines to specs (pano_spec.hpp). Scalings from libpano13's SetMakeParams (adjust.c):
// the panorama's distance is W / hfov for the cylinders, fisheye and the world maps, W / (2 x)
// with x the format's half-width at hfov / 2 for the others: what each spec's hfov (or fov with
// radius W / 2) sets. The General Panini's compression (P's first value, 0..150) maps to d as
// unscaleParams_panini_general does: d = 1.5 / (t + 1e-4) - 1.5 / 3.0001, t = (150 - cmpr) / 50.
#include "jobs/stitch/pano_spec.hpp"

#include <cmath>
#include <sstream>

#include "panoproj/error.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {
namespace {

std::string num(double v) {
  std::ostringstream o;
  o.precision(17);
  o << v;
  return o.str();
}

[[noreturn]] void refuse(const PtoProject& p, int line, const std::string& what) {
  throw Error(p.path + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

std::string pano_spec(const PtoProject& project) {
  const PtoPanorama& p = project.pano;
  const std::string v = num(p.hfov);
  const double w = static_cast<double>(p.width), h = static_cast<double>(p.height);
  const std::string fisheye = ",fov=" + v + ",radius=" + num(0.5 * w) + ",clip=none";
  const auto bad = [&](const std::string& why) {
    return Error(project.path + ":" + std::to_string(p.line) + ": p line: token f" +
                 std::to_string(p.projection) + ": " + why);
  };
  switch (p.projection) {
    case 0:
      if (p.hfov >= 180) throw bad("a rectilinear panorama needs v below 180");
      return "pinhole:hfov=" + v;
    case 1:
      return "cylindrical:hfov=" + v +
             ",vfov=" + num(2 * rad2deg(std::atan(0.5 * h * deg2rad(p.hfov) / w)));
    case 2:
      if (p.hfov * h / w > 180 * (1 + 1e-12))
        throw bad("an equirect panorama of v" + v + " at " + std::to_string(p.width) + "x" +
                  std::to_string(p.height) + " spans more than 180 degrees of latitude");
      return "equirect:hfov=" + v + ",vfov=" + num(p.hfov * h / w);
    case 3:
      return "fisheye:model=equidistant" + fisheye;
    case 4:
      if (p.hfov >= 360) throw bad("a stereographic panorama needs v below 360");
      return "fisheye:model=stereographic" + fisheye;
    case 5:
      return "mercator:lat_max=89.999999,hfov=" + v;
    case 6:
      if (p.hfov >= 180) throw bad("a transverse Mercator panorama needs v below 180");
      return "transverse-mercator:x_max=89.999999,hfov=" + v;
    case 7:
      return "sinusoidal:hfov=" + v;
    case 8:
      return "cylindrical-equal-area:hfov=" + v;
    case 9:
    case 15:
      return "fisheye:model=equisolid" + fisheye;
    case 11:
      return "miller:hfov=" + v;
    case 12:
      // libpano13's erect_panini takes the latitude's arctangent twice (y = tan(tan phi) /
      // cos^2(lambda/2)): not the Panini projection, which f19 is.
      throw bad(
          "libpano13's Panini (f12) is not the Panini projection vertically: use f19 (General "
          "Panini)");
    case 14:
      if (p.hfov > 180) throw bad("an orthographic panorama needs v up to 180");
      return "fisheye:model=orthographic" + fisheye;
    case 19: {
      const double cmpr = p.params.size() > 0 ? p.params[0] : 100;
      const double tops = p.params.size() > 1 ? p.params[1] : 0,
                   bots = p.params.size() > 2 ? p.params[2] : 0;
      if (tops != 0 || bots != 0)
        throw bad("the General Panini's tops and bots (P's 2nd and 3rd values) must be 0");
      if (!(cmpr >= 0 && cmpr <= 150))
        throw bad("the General Panini's compression (P's 1st value) must be in [0, 150]");
      const double t = (150 - cmpr) / 50;
      return "panini:d=" + num(1.5 / (t + 0.0001) - 1.5 / 3.0001) + ",hfov=" + v;
    }
    case 20:
      return "fisheye:model=thoby" + fisheye;
    case 21:
      return "hammer:hfov=" + v;
    default:
      throw bad("this panorama projection is not supported (0-9, 11, 14, 15, 19, 20 and 21 are)");
  }
}

std::string image_spec(const PtoProject& project, const PtoImage& im, double sx, double sy) {
  const char* lens = nullptr;
  switch (im.lens_type) {
    case 0:
      lens = "rectilinear";
      break;
    case 1:
      lens = "cylindrical";
      break;
    case 2:
    case 3:
      lens = "equidistant";
      break;
    case 4:
      lens = "equirect";
      break;
    case 8:
      lens = "orthographic";
      break;
    case 10:
      lens = "stereographic";
      break;
    case 20:
      lens = "thoby";
      break;
    case 21:
      lens = "equisolid";
      break;
    default:
      refuse(project, im.line,
             "i line: token f" + std::to_string(im.lens_type) +
                 ": this lens type is not supported (0-4, 8, 10, 20 and 21 are)");
  }
  return std::string("panotools:lens=") + lens + ",hfov=" + num(im.hfov) + ",a=" + num(im.a) +
         ",b=" + num(im.b) + ",c=" + num(im.c) + ",d=" + num(im.d * sx) + ",e=" + num(im.e * sy) +
         ",g=" + num(im.g * sx) + ",t=" + num(im.t * sy);
}

Eigen::Matrix3d image_rotation(const PtoImage& im) {
  return rotation_from_ypr(im.yaw, im.pitch, im.roll).transpose();
}

}  // namespace panoproj
