#pragma once
// A fisheye's SIMD lanes (vector forms in fisheye-inl.h); fisheye.hpp gives the laws
// r = g(psi) / g(psi_max).
#include <algorithm>
#include <cmath>

#include "panoproj/projections/fisheye.hpp"
#include "simd/lanes.hpp"

namespace panoproj::simd {

// As a target: u = (x - cx) / rx, v = (y - cy) / ry, the law's value g_max r at radius r. clip:
// only inside the circle (r <= 1); else wherever the law has an inverse (g r <= law_max).
template <class T>
struct FisheyeRays {
  T cx, cy, inv_rx, inv_ry, g_max, law_max;
  bool clip;
  FisheyeModel law;
};

template <class T>
void describe(const Fisheye& f, FisheyeRays<T>& l) {
  // The laws' largest values: 2 asin(1/2 .) up to 2, asin up to 1; stereographic unbounded.
  double law_max = kPi;
  switch (f.model()) {
    case FisheyeModel::Equidistant: law_max = kPi; break;
    case FisheyeModel::Equisolid: law_max = 2.0; break;
    case FisheyeModel::Orthographic: law_max = 1.0; break;
    case FisheyeModel::Stereographic: law_max = 1e300; break;
    case FisheyeModel::Thoby: break;  // no vector form (geometry.cpp)
  }
  l = {lane<T>(f.cx()),
       lane<T>(f.cy()),
       lane<T>(1.0 / static_cast<double>(f.rx())),
       lane<T>(1.0 / static_cast<double>(f.ry())),
       lane<T>(f.g_max()),
       lane<T>(law_max),
       f.clip(),
       f.model()};
}

// As a source: position = centre + (rx_g, ry_g) law(psi) (x, y) / |(x, y)| with rx_g = rx / g_max;
// refused beyond psi_max (clipped; with the edge slack) and psi_limit (the law's limit). Float
// lanes are coarse near psi = pi: where (n + z) / n < coarse_npz or s / n < coarse_s (n = |ray|,
// s = |(x, y)|).
template <class T>
struct FisheyeSource {
  T width, height, cx, cy, rx_g, ry_g, psi_max, psi_limit, coarse_npz, coarse_s;
  FisheyeModel law;
};

// Returns whether float lanes serve.
template <class T>
bool describe(const Fisheye& f, FisheyeSource<T>& l) {
  const double w = static_cast<double>(f.size().width), h = static_cast<double>(f.size().height);
  // Pixels per radian (r / g) law'(psi) is rx / g at the centre; towards psi = pi the error grows
  // where a small quantity carries the result, so those lanes are coarse:
  //   equidistant: the azimuth (x, y) / s, error (rx/g) pi eps / sin(psi) -> coarse_s;
  //   equisolid: n + z, relative error eps / q with q = (n + z) / n: (rx/g) eps / q -> coarse_npz;
  //   stereographic: (rx/g) 2 sqrt(2) eps / q^1.5 -> coarse_npz; orthographic stays below 90 deg.
  const double scale = std::max(f.rx(), f.ry()) / f.g_max();
  const double room = kFloatTolerance - std::max(w, h) * kHalfUlp - scale * kFloatRayError;
  const double e = scale * kFloatRayError / std::max(room, 1e-300);
  double coarse_npz = 0.0, coarse_s = 0.0;
  switch (f.model()) {
    case FisheyeModel::Equidistant: coarse_s = kPi * e; break;
    case FisheyeModel::Equisolid: coarse_npz = e; break;
    case FisheyeModel::Stereographic: coarse_npz = std::pow(2.0 * std::sqrt(2.0) * e, 2.0 / 3.0); break;
    case FisheyeModel::Orthographic:
    case FisheyeModel::Thoby: break;
  }
  l = {lane<T>(w),
       lane<T>(h),
       lane<T>(f.cx()),
       lane<T>(f.cy()),
       lane<T>(f.rx() / f.g_max()),
       lane<T>(f.ry() / f.g_max()),
       lane<T>(f.clip() ? f.psi_max() * (1.0 + kEdgeSlack) : 1e300),
       lane<T>(f.psi_limit() * (1.0 + kEdgeSlack)),
       lane<T>(coarse_npz),
       lane<T>(coarse_s),
       f.model()};
  return room > 0;
}

}  // namespace panoproj::simd
