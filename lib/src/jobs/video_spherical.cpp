#include "jobs/video_spherical.hpp"

#include <cmath>
#include <cstdio>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/projections/cubemap.hpp"
#include "panoproj/projections/equirect.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {
namespace {

constexpr std::array<int, 6> kLayout0Order = {1, 3, 4, 5, 0, 2};  // r l u d f b

const char* stereo_key(SphericalVideo::Stereo s) {
  return s == SphericalVideo::Stereo::TopBottom   ? "stereo=tb"
         : s == SphericalVideo::Stereo::LeftRight ? "stereo=sbs"
                                                  : "";
}

Error refusal(const std::string& input, const std::string& what) {
  return Error("cannot tell the projection of " + input + ": its spherical metadata says " + what +
               ": give " + option_text("from") + " SPEC");
}

std::string spec_text(const SphericalVideo& v, Size size, const std::string& input) {
  if (v.stereo == SphericalVideo::Stereo::Other)
    throw refusal(
        input,
        "stereo layout '" + v.stereo_name +
            "', which panoproj does not read (top-bottom and left-right, left eye first, it does)");
  const std::string stereo = stereo_key(v.stereo), more = stereo.empty() ? "" : "," + stereo;
  const std::string full = stereo.empty() ? "equirect" : "equirect:" + stereo;
  switch (v.kind) {
    case SphericalVideo::Kind::None: {
      const Size eye =
          stereo_eye(size,
                     v.stereo == SphericalVideo::Stereo::TopBottom ? StereoLayout::TopBottom
                                                                   : StereoLayout::SideBySide,
                     "the frame");
      if (eye.width != 2 * eye.height)
        throw refusal(input, "stereo but no projection, and its eyes of " + size_text(eye) +
                                 " are not 2:1 equirects");
      return full;
    }
    case SphericalVideo::Kind::Other:
      throw refusal(input, "projection '" + v.name + "', which panoproj does not read");
    case SphericalVideo::Kind::Cubemap:
      return "cubemap:layout=3x2,order=rludfb" +
             (v.padding > 0 ? ",pad_px=" + std::to_string(v.padding) : std::string()) + more;
    case SphericalVideo::Kind::Equirect:
      break;
  }
  double wide = 1 - v.left - v.right, high = 1 - v.top - v.bottom, left = v.left, top = v.top;
  if (!(wide > 0 && high > 0 && v.left >= 0 && v.right >= 0 && v.top >= 0 && v.bottom >= 0))
    throw refusal(input, "an equirect cropped past its whole (bounds left " +
                             std::to_string(v.left) + ", right " + std::to_string(v.right) +
                             ", top " + std::to_string(v.top) + ", bottom " +
                             std::to_string(v.bottom) + ")");
  if (wide == 1 && high == 1) return full;
  // Bounds within 1e-3 px of whole pixels of the whole panorama are those pixels (the 0.32
  // fixed point leaves 1e-7 degrees of rounding).
  const Size eye =
      stereo_eye(size,
                 v.stereo == SphericalVideo::Stereo::TopBottom   ? StereoLayout::TopBottom
                 : v.stereo == SphericalVideo::Stereo::LeftRight ? StereoLayout::SideBySide
                                                                 : StereoLayout::Mono,
                 "the frame");
  const auto snap = [](double& part, double& start, int64_t pixels) {
    const double whole = static_cast<double>(pixels) / part, n = std::round(whole);
    if (n < 1 || std::fabs(whole - n) >= 1e-3) return;
    part = static_cast<double>(pixels) / n;
    if (const double at = start * n; std::fabs(at - std::round(at)) < 1e-3)
      start = std::round(at) / n;
  };
  snap(wide, left, eye.width);
  snap(high, top, eye.height);
  char text[200];
  std::snprintf(text, sizeof text, "equirect:hfov=%.17g,vfov=%.17g,lon0=%.17g,lat0=%.17g%s",
                360 * wide, 180 * high, 360 * (left + wide / 2 - 0.5), 180 * (0.5 - top - high / 2),
                more.c_str());
  return text;
}

}  // namespace

bool same_spec(const ProjectionSpec& a, const ProjectionSpec& b) {
  if (a.kind() != b.kind()) return false;
  for (const ParamDef& d : a.def().params) {
    if (d.type == ParamType::Number || d.type == ParamType::Integer) {
      const auto x = a.number(d.key), y = b.number(d.key);
      if (x.has_value() != y.has_value() || (x && std::fabs(*x - *y) > 1e-6)) return false;
    } else if (a.choice(d.key) != b.choice(d.key)) {
      return false;
    }
  }
  return true;
}

std::string spherical_source_spec(const SphericalVideo& v, Size size, const std::string& input) {
  const std::string text = spec_text(v, size, input);
  try {  // (the frames' geometry: a padding past the cell, eyes that do not fit)
    ConvertOptions o;
    o.size = Size{1, 1};
    (void)make_geometry(size, parse_spec(text), parse_spec("pinhole:hfov=90"), o);
  } catch (const Error& e) {
    throw refusal(input, spherical_text(v) + ", which its frames of " + size_text(size) +
                             " do not hold (" + e.what() + ")");
  }
  return text;
}

Eigen::Matrix3d spherical_pose(const SphericalVideo& v) {
  return rotation_from_ypr(v.yaw, v.pitch, v.roll);
}

SphericalVideo spherical_of_target(const ConversionGeometry& g, std::string& why) {
  SphericalVideo v;
  v.stereo = g.stereo.target == StereoLayout::TopBottom    ? SphericalVideo::Stereo::TopBottom
             : g.stereo.target == StereoLayout::SideBySide ? SphericalVideo::Stereo::LeftRight
                                                           : SphericalVideo::Stereo::Mono;
  if (const auto* e = std::get_if<Equirect>(&g.target)) {
    const double h = e->axis().hfov / kTwoPi, w = e->vfov() / kPi;
    const double left = std::remainder(e->axis().lon0 / kTwoPi - h / 2 + 0.5, 1.0);
    v.left = h >= 1 ? 0 : left < 0 ? left + 1 : left;
    v.right = h >= 1 ? 0 : 1 - v.left - h;
    v.top = 0.5 - e->lat_top() / kPi;
    v.bottom = 1 - v.top - w;
    const double tiny = 1e-9;
    if (v.right < -tiny || v.top < -tiny || v.bottom < -tiny) {
      why =
          "its equirect crosses the back seam (180 degrees), which bounds cannot say: turn "
          "its centre with --yaw";
      return {};
    }
    v.right = std::max(0.0, v.right), v.top = std::max(0.0, v.top);
    v.bottom = std::max(0.0, v.bottom);
    v.kind = SphericalVideo::Kind::Equirect;
    v.name = "equirectangular";
    return v;
  }
  if (const auto* c = std::get_if<Cubemap>(&g.target)) {
    const CubeFormat& f = c->format();
    if (c->layout() == CubeLayout::Grid3x2 && f.order == kLayout0Order &&
        f.rot == std::array<int, 6>{} && f.pad == 0 && !f.angular) {
      v.kind = SphericalVideo::Kind::Cubemap;
      v.name = "cubemap";
      return v;
    }
    why = c->layout() == CubeLayout::Eac
              ? "YouTube signals an EAC with a mesh (mshp), which libavformat 5.1 cannot write"
              : "only a 3x2 cube in layout 0's order has a box (cubemap:layout=3x2,order=rludfb, "
                "unturned and unpadded)";
    return {};
  }
  why = "Spherical Video V2 describes equirects and cubes only";
  return {};
}

std::string spherical_text(const SphericalVideo& v) {
  std::string t = v.kind == SphericalVideo::Kind::None ? "no projection" : v.name;
  char b[160];
  if (v.top > 0 || v.bottom > 0 || v.left > 0 || v.right > 0) {
    std::snprintf(b, sizeof b, ", bounds left %.4g right %.4g top %.4g bottom %.4g", v.left,
                  v.right, v.top, v.bottom);
    t += b;
  }
  if (v.padding > 0) t += ", padding " + std::to_string(v.padding);
  if (v.stereo != SphericalVideo::Stereo::Mono)
    t += ", stereo " + (v.stereo == SphericalVideo::Stereo::TopBottom   ? std::string("top-bottom")
                        : v.stereo == SphericalVideo::Stereo::LeftRight ? std::string("left-right")
                                                                        : v.stereo_name);
  if (v.yaw != 0 || v.pitch != 0 || v.roll != 0) {
    std::snprintf(b, sizeof b, ", pose yaw %g pitch %g roll %g", v.yaw, v.pitch, v.roll);
    t += b;
  }
  return t;
}

}  // namespace panoproj
