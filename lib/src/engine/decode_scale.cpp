// The coarsest scale a source may be decoded at for a view (convert.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "panoproj/convert.hpp"
#include "geometry/source_taps.hpp"
#include "sampling/map_steps.hpp"

namespace panoproj {

double finest_source_step(const ConversionGeometry& g, double stop_below) {
  const Size out = size_of(g.target);
  const double wrap = SourceTaps(g.source).wrap_period();
  // Points every 16 output pixels, at most 257 per axis, the last row and column included.
  auto points = [](int64_t n) {
    const int64_t count = std::min<int64_t>(257, (n + 15) / 16 + 1);
    std::vector<double> p;
    for (int64_t i = 0; i < count; ++i)
      p.push_back(0.5 + (count == 1 ? 0.0 : static_cast<double>(i) * static_cast<double>(n - 1) / static_cast<double>(count - 1)));
    return p;
  };
  double finest = std::numeric_limits<double>::infinity();
  for (const double py : points(out.height))
    for (const double px : points(out.width)) {
      double x, y;
      if (!source_pixel(g.source, g.target, g.rotation, px, py, x, y)) continue;
      auto step = [&](double dx, double dy, float& sx, float& sy) {  // NaN: the neighbour has no source
        double nx, ny;
        const bool ok = source_pixel(g.source, g.target, g.rotation, px + dx, py + dy, nx, ny);
        sx = ok ? static_cast<float>(nx - x) : NAN, sy = ok ? static_cast<float>(ny - y) : 0.0f;
      };
      float bx, by, ax, ay, ux, uy, vx, vy;
      step(-1, 0, bx, by), step(1, 0, ax, ay);
      if (!shorter_step(bx, by, ax, ay, static_cast<float>(wrap), ux, uy)) continue;
      step(0, -1, bx, by), step(0, 1, ax, ay);
      if (!shorter_step(bx, by, ax, ay, static_cast<float>(wrap), vx, vy)) continue;
      // The least singular value of the Jacobian [u v]: sqrt((a - sqrt(a^2 - 4 det^2)) / 2).
      const double a = double{ux} * ux + double{uy} * uy + double{vx} * vx + double{vy} * vy;
      const double det = double{ux} * vy - double{uy} * vx;
      finest = std::min(finest, std::sqrt(std::max(0.0, 0.5 * (a - std::sqrt(std::max(0.0, a * a - 4 * det * det))))));
      if (finest < stop_below) return finest;
    }
  return finest;
}

int coarsest_decode_scale(const ConversionGeometry& g, double finest_step) {
  const Size s = size_of(g.source);
  for (int scale : {8, 4, 2})
    if (2.0 * scale <= finest_step && s.width % scale == 0 && s.height % scale == 0) return scale;
  return 1;
}

}  // namespace panoproj
