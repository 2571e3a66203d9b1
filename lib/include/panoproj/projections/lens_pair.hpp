#pragma once
// The shares of two lenses whose fields overlap (a dual fisheye, dual_fisheye.hpp; a GoPro MAX's
// strips, gopro_max.hpp), from a ray's margins m_k: how far inside lens k's field it lies
// (radians, or the form's own angle; negative outside).
#include <algorithm>

namespace panoproj {

// Lens 0's weight: 1 or 0 where only one lens sees the ray; where both do,
//   w0 = clamp(1/2 + (m0 - m1) / (2 min(f, m0 + m1)), 0, 1),
// a linear ramp f wide centred on the midline m0 = m1 (f = 0: the hard cut). m0 + m1 is the
// overlap's local width: where it is narrower than f the ramp narrows to it, so w0 still reaches
// 0 on lens 0's edge and 1 on lens 1's (no seam). f = the overlap gives w0 = m0 / (m0 + m1).
inline double lens_weight0(double m0, double m1, double feather) {
  if (m1 < 0) return 1.0;
  if (m0 < 0) return 0.0;
  const double f = std::min(feather, m0 + m1);
  if (f <= 0) return m0 >= m1 ? 1.0 : 0.0;
  return std::clamp(0.5 + (m0 - m1) / (2.0 * f), 0.0, 1.0);
}

}  // namespace panoproj
