#pragma once
// Hammer's (and Eckert-Greifendorff's) SIMD lanes (vector forms in hammer-inl.h): hammer.hpp's
// equations with the longitude scaled by w.
#include "panoproj/projections/hammer.hpp"
#include "simd/map_frame.hpp"

namespace panoproj::simd {

// As a target: the closed-form inverse, valid for |lambda| <= lam_max (pi with the edge slack).
template <class T>
struct HammerRays {
  MapPlane<T> plane;
  T w, inv_w, lam_max;
};

template <class T>
void describe(const Hammer& m, HammerRays<T>& l) {
  describe(m.frame(), m.lon0(), l.plane);
  l.w = lane<T>(m.w());
  l.inv_w = lane<T>(1.0 / m.w());
  l.lam_max = lane<T>(kPi * (1.0 + kEdgeSlack));
}

// As a source (the frame in MapPixels).
template <class T>
struct HammerSource {
  T w, inv_w;
};

// Returns whether float lanes serve: the plane position's error is the ray's times the largest
// scale times the pixels per plane unit, plus rounding. The largest scale is the Lambert
// azimuthal's 1 / cos(c / 2) at the outline's equator, c = w pi: sqrt(2) for Hammer (w = 1/2),
// 6.4 for w = 0.9 (the factor 2 below covers it up to w = 1/2).
template <class T>
bool describe(const Hammer& m, HammerSource<T>& l) {
  l.w = lane<T>(m.w());
  l.inv_w = lane<T>(1.0 / m.w());
  const double scale = std::max(1.0, 1.0 / (std::sqrt(2.0) * std::cos(m.w() * kHalfPi)));
  return rounding(m.frame()) + pixels_per_unit(m.frame()) * 2 * scale * kFloatRayError <= kFloatTolerance;
}

}  // namespace panoproj::simd
