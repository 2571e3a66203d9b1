#pragma once
// Helpers the projection modules share: catalogue entries' keys, errors naming the spec, and the
// default size's rounding and limit.
#include <array>
#include <cmath>
#include <string>

#include "panoproj/conventions.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"

namespace panoproj::spec_support {

inline constexpr double kInf = HUGE_VAL;

// Catalogue keys.
ParamDef number(const char* key, const char* def, double lo, double hi, bool lo_open, bool hi_open, const char* help);
ParamDef choice(const char* key, const char* def, const char* choices, const char* help);
ParamDef coefficient(const char* key);  // a distortion coefficient, any finite value
ParamDef lon0();
ParamDef lat0();
ParamDef center(const char* key);  // cx or cy, OpenCV's convention
ParamDef angle(const char* key, const char* def, const char* help);
ParamDef map_aspect();  // a world map's aspect=keep|stretch
ParamDef map_hfov();    // a world map's hfov: the longitudes its width spans at the equator

// Throws Error("<name>: <what>").
[[noreturn]] void fail(const ProjectionSpec& s, const std::string& what);
// The key's value in radians.
double rad(const ProjectionSpec& s, const char* key);
// A centre key in pixels (pixel centres at +0.5), else the middle of `extent`.
double center_of(const ProjectionSpec& s, const char* key, double extent);
// The error for a lens law that `coefficients` make fold back at `fold` (radians off axis) inside
// the field's half angle: it names the largest field that works.
[[noreturn]] void fail_fold(const ProjectionSpec& s, const char* coefficients, double fold, double half_field);
// A calibrated camera's focal lengths (fx, fy): as given (one alone serves both), else f0.
std::array<double, 2> focal_lengths(const ProjectionSpec& s, double f0);
// lat0 +- vfov/2 within [-90, 90] (open: (-90, 90)).
void check_latitude_span(const ProjectionSpec& s, bool open);
// The default size of an unrounded w x h frame: whole pixels, refused over kMaxDefaultPixels.
Size framed_size(const ProjectionSpec& s, double w, double h);
// A world map's default size: its plane frame (unit scale at the centre) at `density`.
Size map_size(const ProjectionSpec& s, const MapFrame& frame, double density);
// A world map as its keys say: with hfov, the width spanning hfov at the equator about the
// centre, square pixels; else square pixels (aspect=keep) or its outline filling the frame.
template <class Map>
Map map_framed(const ProjectionSpec& s, Map m) {
  if (const auto hfov = s.number("hfov")) {
    double X, Y;
    m.forward(0.5 * deg2rad(*hfov), 0.0, X, Y);
    if (!(std::isfinite(X) && X > 0))
      fail(s, "hfov=" + std::to_string(*hfov) + " is past the map's width");
    return m.spanned(X);
  }
  if (s.choice("aspect") == "keep") m.keep_square();
  return m;
}

// A world map's window (module.hpp).
template <class Map>
Projection map_window(const Projection& p, const PixelRect& r) {
  return std::get<Map>(p).windowed(r);
}

// Shared by the fisheye and dual-fisheye modules (defined in fisheye.cpp).
FisheyeModel fisheye_model(const std::string& name);
void check_fisheye_fov(const ProjectionSpec& s, const char* key, double fov);  // against the law's domain
Fisheye fisheye_scaled(const Fisheye& q, Size size, double sx, double sy);    // positions scaled by (sx, sy)

}  // namespace panoproj::spec_support
