// Fitted inverse polynomials against the exact law (fitted_inverse.hpp).
#include "panoproj/diagnostics/fitted_inverse.hpp"

#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

#include "panoproj/conventions.hpp"

namespace panoproj {
namespace {

double horner(const std::vector<double>& c, double x) {
  double v = 0.0;
  for (size_t i = c.size(); i-- > 0;) v = v * x + c[i];
  return v;
}

// Nanoseconds per call of f over `xs` (the best of three passes).
template <class F>
double ns_per(const std::vector<double>& xs, F&& f) {
  double best = HUGE_VAL, sink = 0.0;
  for (int pass = 0; pass < 3; ++pass) {
    const auto t0 = std::chrono::steady_clock::now();
    for (double x : xs) sink += f(x);
    const std::chrono::duration<double, std::nano> dt = std::chrono::steady_clock::now() - t0;
    best = std::fmin(best, dt.count() / static_cast<double>(xs.size()));
  }
  volatile double keep = sink;
  (void)keep;
  return best;
}

}  // namespace

std::string FittedInverse::text() const {
  std::ostringstream o;
  o.precision(3);
  o << "the calibration's fitted " << name << " is up to " << max_px
    << " px from the exact inverse (at " << at_deg
    << " deg off axis); panoproj inverts the law (bracketed Newton, " << exact_ns
    << " ns a point; the fitted polynomial " << fitted_ns << " ns)";
  return o.str();
}

std::optional<FittedInverse> fitted_inverse(const ProjectionSpec& spec, const Projection& lens) {
  const auto* p = std::get_if<CalibratedLens>(&lens);
  const bool ocam = spec.name() == "ocamcalib", ftheta = spec.name() == "f-theta";
  const char* key = ocam ? "invpol" : "bw_poly";
  if (!p || !(ocam || ftheta) || !spec.given(key)) return std::nullopt;
  const std::vector<double> c = spec.numbers(key, 1, 64, "its coefficients");
  FittedInverse f;
  f.name = key;
  constexpr int kSamples = 4096;
  std::vector<double> thetas, radii;
  for (int i = 0; i <= kSamples; ++i) {
    const double t = p->theta_max() * i / kSamples;
    thetas.push_back(t);
    radii.push_back(p->radius(t));
  }
  for (int i = 0; i <= kSamples; ++i) {
    double px;
    if (ocam) {  // world2cam: rho = invpol(theta - pi/2), theta from the optical axis
      px = std::fabs(horner(c, thetas[i] - kHalfPi) - radii[i]);
    } else {  // theta = bw_poly(r): an angle error, in pixels at the law's local slope
      const double t = thetas[i], dt = 1e-6 * (1.0 + t);
      const double slope = (p->radius(t + dt) - p->radius(std::fmax(0.0, t - dt))) /
                           (t + dt - std::fmax(0.0, t - dt));
      px = std::fabs(horner(c, radii[i]) - t) * slope;
    }
    if (!(px <= f.max_px)) f.max_px = px, f.at_deg = rad2deg(thetas[i]);
  }
  if (ocam) {
    f.fitted_ns = ns_per(thetas, [&](double t) { return horner(c, t - kHalfPi); });
    f.exact_ns = ns_per(thetas, [&](double t) { return p->radius(t); });
  } else {
    f.fitted_ns = ns_per(radii, [&](double r) { return horner(c, r); });
    f.exact_ns = ns_per(radii, [&](double r) { return p->angle(r); });
  }
  return f;
}

}  // namespace panoproj
