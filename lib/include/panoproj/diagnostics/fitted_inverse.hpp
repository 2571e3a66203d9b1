#pragma once
// The fitted inverse polynomials some calibrations carry (OCamCalib's invpol, F-theta's
// pixeldist_to_angle bw_poly) against the law's exact inverse, which panoproj uses: their largest
// difference over the lens's field, in pixels, and both inverses' time per point.
#include <optional>
#include <string>

#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"

namespace panoproj {

struct FittedInverse {
  std::string name;          // "invpol", "bw_poly"
  double max_px = 0;         // largest difference from the exact inverse, in pixels
  double at_deg = 0;         // the angle off axis where it is largest
  double fitted_ns = 0;      // time per point: the fitted polynomial
  double exact_ns = 0;       // the exact inverse (bracketed Newton)
  std::string text() const;  // one line for reports
};

// nullopt where the spec carries no fitted inverse; `lens` is the spec's projection (any frame).
std::optional<FittedInverse> fitted_inverse(const ProjectionSpec& spec, const Projection& lens);

}  // namespace panoproj
