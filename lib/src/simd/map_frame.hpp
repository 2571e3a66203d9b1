#pragma once
// The SIMD lanes the map forms share (Hammer, Aitoff, Bonne; vector forms in map_frame-inl.h):
// the frame between pixels and the plane of the map's equations (MapFrame), and lon0.
#include <algorithm>

#include "panoproj/projections/map_frame.hpp"
#include "simd/lanes.hpp"

namespace panoproj::simd {

// As a target: plane X = xmin + px x_per_px, Y = ymax - py y_per_px.
template <class T>
struct MapPlane {
  T xmin, x_per_px, ymax, y_per_px, lon0;
};

template <class T>
void describe(const MapFrame& f, double lon0, MapPlane<T>& l) {
  l = {lane<T>(f.xmin), lane<T>((f.xmax - f.xmin) / static_cast<double>(f.size.width)),
       lane<T>(f.ymax), lane<T>((f.ymax - f.ymin) / static_cast<double>(f.size.height)),
       lane<T>(lon0)};
}

// As a source: pixel x = (X - xmin) px_per_x, y = (ymax - Y) px_per_y, in the closed frame.
template <class T>
struct MapPixels {
  T width, height, xmin, px_per_x, ymax, px_per_y, lon0;
};

template <class T>
void describe(const MapFrame& f, double lon0, MapPixels<T>& l) {
  const double w = static_cast<double>(f.size.width), h = static_cast<double>(f.size.height);
  l = {lane<T>(w),  lane<T>(h),    lane<T>(f.xmin),         lane<T>(w / (f.xmax - f.xmin)),
       lane<T>(f.ymax), lane<T>(h / (f.ymax - f.ymin)), lane<T>(lon0)};
}

// The larger of the frame's pixels per plane unit in x and y.
inline double pixels_per_unit(const MapFrame& f) {
  return std::max(static_cast<double>(f.size.width) / (f.xmax - f.xmin),
                  static_cast<double>(f.size.height) / (f.ymax - f.ymin));
}

// The rounding of a float position in the frame, in pixels.
inline double rounding(const MapFrame& f) {
  return static_cast<double>(std::max(f.size.width, f.size.height)) * kHalfUlp;
}

}  // namespace panoproj::simd
