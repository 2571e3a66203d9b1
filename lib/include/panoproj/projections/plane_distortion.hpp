#pragma once
// OpenCV's distortion of a point m = (x, y) of a lens's undistorted plane, r2 = x^2 + y^2:
//   m_d = m (1 + a1 r2 + a2 r2^2 + a3 r2^3 + a4 r2^4) / (1 + b1 r2 + b2 r2^2 + b3 r2^3)   radial
//         + (2 p1 x y + p2 (r2 + 2 x^2), p1 (r2 + 2 y^2) + 2 p2 x y)                    tangential
//         + (s1 r2 + s2 r2^2, s3 r2 + s4 r2^2)                                            thin
//         prism
// (Brown 1966, Conrady 1919; OpenCV's camera model documentation: rational k1..k6 as a1..a3 over
// b1..b3, thin prism s1..s4; COLMAP's THIN_PRISM_FISHEYE puts k1..k4 in a1..a4, on the
// equidistant plane). The inverse has no closed form: Newton in 2-D from the distorted point, a
// step halved while it does not reduce the residual; converged when a step is under 1e-15 (1 + r),
// at most 100 steps, accepted when the residual is under 1e-12 (1 + |m_d|).
#include <array>
#include <cmath>

namespace panoproj {

struct PlaneDistortion {
  std::array<double, 4> a{};  // radial numerator
  std::array<double, 3> b{};  // radial denominator
  double p1 = 0, p2 = 0;      // tangential
  std::array<double, 4> s{};  // thin prism

  bool identity() const {
    for (double v : a)
      if (v != 0) return false;
    for (double v : b)
      if (v != 0) return false;
    for (double v : s)
      if (v != 0) return false;
    return p1 == 0 && p2 == 0;
  }
  // The radial factor N / D at r2, and its derivative in r2.
  double numerator(double q) const { return 1.0 + q * (a[0] + q * (a[1] + q * (a[2] + q * a[3]))); }
  double denominator(double q) const { return 1.0 + q * (b[0] + q * (b[1] + q * b[2])); }
  double radial(double q) const { return numerator(q) / denominator(q); }
  double radial_slope(double q) const {
    const double n = numerator(q), d = denominator(q);
    const double dn = a[0] + q * (2.0 * a[1] + q * (3.0 * a[2] + q * 4.0 * a[3]));
    const double dd = b[0] + q * (2.0 * b[1] + q * 3.0 * b[2]);
    return (dn * d - n * dd) / (d * d);
  }
  // d/dr of r N(r^2) / D(r^2): where it stays positive the radial part does not fold.
  double radius_slope(double r) const { return radial(r * r) + 2.0 * r * r * radial_slope(r * r); }

  void apply(double x, double y, double& xd, double& yd) const {
    const double q = x * x + y * y, f = radial(q);
    xd = x * f + 2.0 * p1 * x * y + p2 * (q + 2.0 * x * x) + q * (s[0] + q * s[1]);
    yd = y * f + p1 * (q + 2.0 * y * y) + 2.0 * p2 * x * y + q * (s[2] + q * s[3]);
  }
  // d(xd, yd) / d(x, y), row-major.
  void jacobian(double x, double y, double j[4]) const {
    const double q = x * x + y * y, f = radial(q), df = 2.0 * radial_slope(q);
    const double px = 2.0 * (s[0] + 2.0 * q * s[1]),
                 py = 2.0 * (s[2] + 2.0 * q * s[3]);  // prism / d(r2), times 2
    j[0] = f + x * x * df + 2.0 * p1 * y + 6.0 * p2 * x + px * x;
    j[1] = x * y * df + 2.0 * p1 * x + 2.0 * p2 * y + px * y;
    j[2] = x * y * df + 2.0 * p1 * x + 2.0 * p2 * y + py * x;
    j[3] = f + y * y * df + 6.0 * p1 * y + 2.0 * p2 * x + py * y;
  }
  // (x, y) with apply(x, y) = (xd, yd), Newton from (xd, yd); false where it does not converge.
  bool invert(double xd, double yd, double& x, double& y) const {
    x = xd, y = yd;
    double fx, fy;
    apply(x, y, fx, fy);
    fx -= xd, fy -= yd;
    double res = std::hypot(fx, fy);
    for (int i = 0; i < 100 && res > 0.0; ++i) {
      double j[4];
      jacobian(x, y, j);
      const double det = j[0] * j[3] - j[1] * j[2];
      if (!(std::fabs(det) > 1e-300)) return false;
      double sx = (j[3] * fx - j[1] * fy) / det, sy = (j[0] * fy - j[2] * fx) / det;
      double nx = x, ny = y, nres = res, gx = fx, gy = fy;
      for (int h = 0; h < 40; ++h, sx *= 0.5, sy *= 0.5) {
        nx = x - sx, ny = y - sy;
        apply(nx, ny, gx, gy);
        gx -= xd, gy -= yd;
        nres = std::hypot(gx, gy);
        if (nres < res) break;
      }
      const double step = std::hypot(nx - x, ny - y);
      if (!(nres < res)) break;  // no step reduces it: converged to rounding
      x = nx, y = ny, fx = gx, fy = gy, res = nres;
      if (step < 1e-15 * (1.0 + std::hypot(x, y))) break;
    }
    return res <= 1e-12 * (1.0 + std::hypot(xd, yd));
  }
};

}  // namespace panoproj
