#pragma once
// The stability report (`panoproj stability`; every case is an assertion in
// tests/stability_test.cpp): each projection's case table (its module's, in catalogue order:
// parameters at their extremes, fields of view from 0.001 degree to 360, Bonne's phi1 at 0, at
// its series switch and at the pole, ..., at sizes from 1x1 to over 32767 px), round-tripped
// pixel -> ray -> pixel -> ray over a grid of the closed frame plus its singular points
// (centre, edges, corners, seam, poles, rims, a hair inside and outside them), and fed
// degenerate rays (zero, NaN, infinite, 1e-300 and 1e300 components, the poles, straight back). Reported per case:
//   - the largest round-trip error as the angle between a pixel's ray and its round trip's,
//     and in pixels: that angle over the angle of one pixel there (so the identities, the seam
//     x = 0 = W, a pole row, a shared cube edge, count as no error);
//   - the most Newton iterations of an inverse (Aitoff's; -1 where there is none);
//   - non-finite values produced by a mapping that reported success (must be 0), and pixels
//     whose ray maps nowhere (must be 0).
#include <cstdint>
#include <string>
#include <vector>

#include "panoproj/projections/frame.hpp"

namespace panoproj {

struct StabilityCase {
  std::string spec;
  Size size;
  double bound_px;  // the round trip's stated bound
};

struct StabilityResult {
  StabilityCase c;
  int64_t points = 0;       // pixels round-tripped
  double max_px = 0, max_rad = 0;
  int max_newton = -1;
  int64_t non_finite = 0;   // NaN or inf out of a mapping that succeeded
  int64_t lost = 0;         // pixels with a ray that does not map back
  bool pass() const { return non_finite == 0 && lost == 0 && max_px <= c.bound_px; }
};

std::vector<StabilityCase> stability_cases();
StabilityResult run_stability_case(const StabilityCase& c);
std::string stability_table(const std::vector<StabilityResult>& results);

}  // namespace panoproj
