#include "panoproj/diagnostics/stability.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "panoproj/projection.hpp"
#include "panoproj/spec.hpp"

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
  const Size tiny{1, 1}, photo{4096, 2048}, huge{40000, 20000};
  auto add = [&](const std::string& spec, std::initializer_list<Size> sizes, double bound) {
    for (Size s : sizes) c.push_back({spec, s, bound});
  };
  for (const char* f : {"0.01", "1", "90", "179", "179.99"}) add(std::string("pinhole:hfov=") + f, {tiny, {1920, 1080}, huge}, 1e-6);
  for (const char* m : {"equidistant", "equisolid", "orthographic", "stereographic"})
    for (const char* f : {"0.01", "1", "90", "180", "270", "359.99"}) {
      const double fov = std::stod(f);
      if ((std::string(m) == "orthographic" && fov > 180) || (std::string(m) == "stereographic" && fov > 359)) continue;
      // Orthographic r = sin(psi): its inverse's condition 1 / cos(psi) grows towards 90 degrees
      // (1.5e-6 px at the rim of a 40000-px 180-degree image).
      add(std::string("fisheye:fov=") + f + ",model=" + m, {tiny, {2048, 2048}, {40000, 40000}},
          std::string(m) == "orthographic" ? 1e-5 : 1e-6);
    }
  add("fisheye:fov=200,clip=none", {{2048, 2048}}, 1e-6);
  // Kannala-Brandt: the equidistant law, a tiny field, a 360-degree circle, and a field ending
  // 0.01 degree before the law folds back (theta (1 - 0.1 theta^2): the Newton inverse's slope
  // tends to 0 at the rim).
  for (const char* f : {"0.01", "180", "360"}) add(std::string("kannala-brandt:fov=") + f + ",k1=-0.01,k2=0.0005", {tiny, {2048, 2048}, {40000, 40000}}, 1e-6);
  add("kannala-brandt:fov=209.2,k1=-0.1", {{2048, 2048}, {40000, 40000}}, 1e-6);
  // Brown-Conrady: a pinhole to 160 degrees, barrel distortion up to its fold, and tangential
  // terms (focal lengths scaled with the frame).
  add("brown-conrady", {tiny, {1920, 1080}, {40000, 22500}}, 1e-6);
  add("brown-conrady:k1=-0.3", {{1920, 1080}, {40000, 22500}}, 1e-6);
  add("brown-conrady:fx=1000,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0.01", {{1920, 1080}}, 1e-6);
  add("brown-conrady:fx=20833,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0005,k3=-0.01", {{40000, 22500}}, 1e-6);
  // PTLens: a plain rectilinear lens to 160 degrees, and one whose polynomial folds (the field
  // ends there).
  add("ptlens", {tiny, {1920, 1080}, {40000, 22500}}, 1e-6);
  add("ptlens:hfov=100,a=-0.2,b=0.05,c=-0.01", {{1920, 1080}, {40000, 22500}}, 1e-6);
  // The closed-form lens laws over their whole domain, and unbounded ones at their default 180
  // degrees. Where R stays bounded (unified xi > 1, extended unified alpha > 1/2) its slope
  // reaches 0 at the domain's edge, so theta(R) has the conditioning of sqrt there, as the
  // orthographic fisheye's: 1.1e-6 px at the rim of a 40000-px image.
  for (const char* s : {"double-sphere:xi=-0.18,alpha=0.59", "double-sphere:xi=0.3,alpha=0.4", "unified:xi=2.5", "unified:xi=0.8",
                        "extended-unified:alpha=0.63,beta=1.04", "extended-unified:alpha=0.3,beta=2"})
    add(s, {tiny, {2048, 2048}, {40000, 40000}}, 1e-5);
  // Dual fisheye: each ray back through the lens it lies deeper inside (in the overlap, the other
  // half of the frame), lenses to 360 degrees and to 0.01, a turned top/bottom pair.
  add("dual-fisheye:fov=200", {{2, 1}, photo, huge}, 1e-6);
  add("dual-fisheye:fov=359.99,model=equisolid", {photo}, 1e-6);
  add("dual-fisheye:fov=0.01", {photo}, 1e-6);
  add("dual-fisheye:fov=190,fov2=220,layout=top-bottom,yaw2=175,pitch2=5,roll2=90", {{2048, 4096}}, 1e-6);
  add("equirect", {tiny, {2, 1}, photo, huge}, 1e-6);
  add("equirect:hfov=0.01,vfov=0.01", {tiny, photo}, 1e-6);
  add("equirect:hfov=120,vfov=60,lat0=59.99", {photo}, 1e-6);
  add("cylindrical", {tiny, photo, huge}, 1e-6);
  add("cylindrical:vfov=179.99", {photo}, 1e-6);
  add("cylindrical:vfov=0.01", {photo}, 1e-6);
  for (int f : {1, 2, 1024, 40000}) add("cubemap", {{6 * f, f}}, 1e-6);
  add("cubemap:layout=cross", {{4 * 1024, 3 * 1024}}, 1e-6);
  add("aitoff", {tiny, photo, huge}, 1e-6);
  add("hammer", {tiny, photo, huge}, 1e-6);
  add("eckert-greifendorff", {photo}, 1e-6);
  for (const char* p : {"0", "1e-9", "5.7", "5.73", "5.8", "45", "-45", "89.99", "90", "-90"})
    add(std::string("bonne:phi1=") + p, {photo, huge}, 1e-6);
  return c;
}

StabilityResult run_stability_case(const StabilityCase& c) {
  StabilityResult r;
  r.c = c;
  const Projection p = make_projection(parse_spec(c.spec), c.size);
  const auto W = static_cast<double>(c.size.width), H = static_cast<double>(c.size.height);
  const Aitoff* aitoff = std::get_if<Aitoff>(&p);
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
