#include "panoproj/diagnostics/stability.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"
#include "projections/module.hpp"

namespace panoproj {
namespace {

bool finite(const Ray& d) { return std::isfinite(d.x()) && std::isfinite(d.y()) && std::isfinite(d.z()); }

double angle(const Ray& a, const Ray& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// Positions along one axis of extent n: a grid, the edges, the centre, and a hair around them.
std::vector<double> positions(double n) {
  std::vector<double> v;
  for (int i = 0; i <= 32; ++i) v.push_back(n * i / 32.0);
  for (double p : {0.0, 0.5 * n, n})
    for (double e : {1e-9, 1e-6, 1e-3, 0.5}) v.push_back(p + e), v.push_back(p - e);
  v.erase(std::remove_if(v.begin(), v.end(), [&](double p) { return p < 0 || p > n; }), v.end());
  return v;
}

}  // namespace

std::vector<StabilityCase> stability_cases() {
  std::vector<StabilityCase> c;
  for (const ProjectionCase& row : projection_cases())
    for (Size s : row.sizes) c.push_back({row.spec, s, row.bound_px});
  return c;
}

StabilityResult run_stability_case(const StabilityCase& c) {
  StabilityResult r;
  r.c = c;
  const Projection p = make_projection(parse_spec(c.spec), c.size);
  const auto W = static_cast<double>(c.size.width), H = static_cast<double>(c.size.height);
  const Aitoff* aitoff = std::get_if<Aitoff>(&p);
  const bool mollweide = std::holds_alternative<Mollweide>(p);  // its forward Newton, per ray
  for (double y : positions(H))
    for (double x : positions(W)) {
      Ray d;
      if (!to_ray(p, x, y, d)) continue;
      ++r.points;
      double px, py;
      Ray back;
      if (!finite(d)) {
        ++r.non_finite;
        continue;
      }
      if (!to_pixel(p, d.normalized(), px, py) || !to_ray(p, px, py, back)) {
        ++r.lost;
        continue;
      }
      if (!std::isfinite(px) || !std::isfinite(py) || !finite(back)) {
        ++r.non_finite;
        continue;
      }
      const double a = angle(d, back);
      // One pixel's angle here: half a pixel either way along x or y, whichever has a ray.
      double pixel = 0;
      for (auto [dx, dy] : {std::pair{0.5, 0.0}, {-0.5, 0.0}, {0.0, 0.5}, {0.0, -0.5}}) {
        Ray n;
        if (to_ray(p, x + dx, y + dy, n) && finite(n)) pixel = std::max(pixel, 2 * angle(d, n));
      }
      r.max_rad = std::max(r.max_rad, a);
      r.max_px = std::max(r.max_px, pixel > 0 ? a / pixel : (a > 0 ? HUGE_VAL : 0.0));
      if (aitoff) {
        double lam, phi;
        r.max_newton = std::max(r.max_newton, aitoff->newton_inverse(aitoff->frame().plane_x(x), aitoff->frame().plane_y(y), lam, phi));
      }
      if (mollweide) {
        int it = 0;
        Mollweide::delta_of(std::hypot(d.x(), d.z()) / d.norm(), std::fabs(d.y()) / d.norm(), &it);
        r.max_newton = std::max(r.max_newton, it);
      }
    }
  // Degenerate rays: to_pixel may refuse them, but what it accepts must be finite.
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const Ray& d : {Ray(0, 0, 0), Ray(nan, 0, 1), Ray(0, inf, 0), Ray(1e-300, 0, 1e-300), Ray(1e300, 1e300, 0),
                       Ray(0, 1, 0), Ray(0, -1, 0), Ray(0, 0, -1), Ray(0, 0, 1), Ray(-1e-17, 0, -1), Ray(1e-17, 0, -1)}) {
    double px, py;
    if (to_pixel(p, d, px, py) && (!std::isfinite(px) || !std::isfinite(py))) ++r.non_finite;
  }
  return r;
}

std::string stability_table(const std::vector<StabilityResult>& results) {
  std::string t = "| projection | size | points | max error px | max error rad | Newton iterations | non-finite | lost | bound px | pass |\n"
                  "|---|---|---|---|---|---|---|---|---|---|\n";
  char line[512];
  for (const auto& r : results) {
    std::snprintf(line, sizeof line, "| %s | %lldx%lld | %lld | %.2e | %.2e | %s | %lld | %lld | %.0e | %s |\n", r.c.spec.c_str(),
                  static_cast<long long>(r.c.size.width), static_cast<long long>(r.c.size.height),
                  static_cast<long long>(r.points), r.max_px, r.max_rad,
                  r.max_newton < 0 ? "-" : std::to_string(r.max_newton).c_str(), static_cast<long long>(r.non_finite),
                  static_cast<long long>(r.lost), r.c.bound_px, r.pass() ? "yes" : "NO");
    t += line;
  }
  return t;
}

}  // namespace panoproj
