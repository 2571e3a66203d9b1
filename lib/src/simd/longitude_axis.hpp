#pragma once
// The SIMD lanes of the longitude-axis forms, equirect and cylindrical (vector forms in
// longitude_axis-inl.h): x is linear in longitude; y in latitude (equirect) or in the height
// t = tan(latitude) on the unit cylinder (cylindrical).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "panoproj/projections/cylindrical.hpp"
#include "panoproj/projections/equirect.hpp"
#include "simd/lanes.hpp"

namespace panoproj::simd {

// As a target: longitude lon_first + px lon_per_px; latitude (or t) top - py fall.
// (span: the frame's vertical extent in latitude or t.)
template <class T>
struct AxisRays {
  T lon_per_px, lon_first, top, fall;
  bool cylinder;
};

// Returns whether the rotation is folded into the rays: a turn about the vertical only shifts
// the longitudes.
template <class T>
bool describe(const LongitudeAxis& axis, Size size, double top, double span, bool cylinder,
              const Eigen::Matrix3d& r, AxisRays<T>& l) {
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  double first = axis.lon0 - 0.5 * axis.hfov;
  const bool folded = r(1, 1) > 0 && r(0, 1) == 0 && r(1, 0) == 0 && r(1, 2) == 0 && r(2, 1) == 0;
  if (folded) first += std::atan2(r(0, 2), r(0, 0));
  l = {lane<T>(axis.hfov / w), lane<T>(first), lane<T>(top), lane<T>(span / h),
       cylinder};
  return folded;
}

template <class T>
bool describe(const Equirect& e, const Eigen::Matrix3d& r, AxisRays<T>& l) {
  return describe(e.axis(), e.size(), e.lat_top(), e.vfov(), false, r, l);
}

template <class T>
bool describe(const Cylindrical& c, const Eigen::Matrix3d& r, AxisRays<T>& l) {
  return describe(c.axis(), c.size(), c.t_top(), c.t_top() - c.t_bottom(), true, r, l);
}

// As a source: x = half_width + px_per_lon (longitude - lon0), wrapped into [0, width) on a
// full circle (else refused beyond half_span, with Fisheye's edge slack); y = px_per_unit (top -
// latitude or t) (px_per_unit negative on a cylinder: t falls downwards). Float lanes are coarse
// where cos^2(latitude) < coarse_cos2.
template <class T>
struct AxisSource {
  T width, height, lon0, px_per_lon, half_width, half_span, top, px_per_unit, coarse_cos2;
  bool full;         // a full circle of longitude
  bool full_sphere;  // every latitude in the frame (a full equirect)
  bool cylinder;
};

// y_gain: the latitude's error is the ray's over cos^y_gain(latitude) (0 equirect, 2 cylinder:
// dt / dlat = 1 / cos^2). Returns whether float lanes serve.
template <class T>
bool describe(const LongitudeAxis& axis, Size size, double top, double per_unit, double y_gain, bool full_sphere,
              bool cylinder, AxisSource<T>& l) {
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  // x: longitude error (W / hfov) eps / cos(lat); y: (H per unit) eps / cos^y_gain(lat).
  const double room = kFloatTolerance - w * kHalfUlp, room_y = kFloatTolerance - h * kHalfUlp;
  const double y_error = std::fabs(per_unit) * kFloatRayError;
  bool use_float = room > 0 && room_y > 0 && (y_gain > 0 || y_error <= room_y);
  const double cos_x = w / axis.hfov * kFloatRayError / std::max(room, 1e-300);
  const double cos_y = y_gain > 0 ? std::pow(y_error / std::max(room_y, 1e-300), 1.0 / y_gain) : 0.0;
  const double cos_min = use_float ? std::min(1.0, std::max(cos_x, cos_y)) : 1.0;
  l = {lane<T>(w),
       lane<T>(h),
       lane<T>(axis.lon0),
       lane<T>(w / axis.hfov),
       lane<T>(0.5 * w),
       lane<T>(0.5 * axis.hfov * (1.0 + kEdgeSlack)),
       lane<T>(top),
       lane<T>(per_unit),
       lane<T>(cos_min * cos_min),
       axis.full,
       full_sphere,
       cylinder};
  // A latitude band whose lanes all need double is no use for float (the check is per lane).
  return use_float && cos_min * cos_min < 1.0;
}

template <class T>
bool describe(const Equirect& e, AxisSource<T>& l) {
  const bool full_sphere = e.vfov() == kPi && e.lat_top() == kHalfPi;
  return describe(e.axis(), e.size(), e.lat_top(), static_cast<double>(e.size().height) / e.vfov(), 0.0, full_sphere,
                  false, l);
}

template <class T>
bool describe(const Cylindrical& c, AxisSource<T>& l) {
  return describe(c.axis(), c.size(), c.t_top(),
                  static_cast<double>(c.size().height) / (c.t_bottom() - c.t_top()), 2.0, false, true, l);
}

}  // namespace panoproj::simd
