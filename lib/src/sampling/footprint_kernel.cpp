#include "sampling/footprint_kernel.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "geometry/sampling_facts.hpp"
#include "sampling/map_steps.hpp"

namespace panoproj {

void footprint_weights(double s, double e, double* w) {
  const double f = (s - 0.5) - std::floor(s - 0.5);  // offset from the left centre, [0, 1)
  const double h = 0.5 * (e + 1.0);
  double sum = 0.0;
  for (int i = 0; i < kFootprintTaps; ++i) {
    const double d = f - (i - kFootprintTaps / 2 + 1);  // the sample's distance from tap i
    sum += (w[i] = std::min(1.0, std::max(0.0, h - std::fabs(d))));
  }
  for (int i = 0; i < kFootprintTaps; ++i) w[i] /= sum;
}

void FootprintField::at(int64_t i, int64_t j, float& wx, float& wy) const {
  const float u = std::clamp(u0 + static_cast<float>(i) * du, 0.0f, 2.0f);
  const float v = std::clamp(v0 + static_cast<float>(j) * dv, 0.0f, 2.0f);
  // The row's blend of the points' rows, then of its three columns (as the SIMD sampler).
  float cx[3] = {}, cy[3] = {};
  for (int r = 0; r < 3; ++r) {
    const float hv = std::max(0.0f, 1.0f - std::fabs(v - static_cast<float>(r)));
    for (int c = 0; c < 3; ++c) cx[c] += hv * ex[3 * r + c], cy[c] += hv * ey[3 * r + c];
  }
  wx = wy = 0.0f;
  for (int c = 0; c < 3; ++c) {
    const float hu = std::max(0.0f, 1.0f - std::fabs(u - static_cast<float>(c)));
    wx += hu * cx[c], wy += hu * cy[c];
  }
  constexpr auto kReach = static_cast<float>(kFootprintReach);
  wx = std::clamp(wx * scale, 1.0f, kReach), wy = std::clamp(wy * scale, 1.0f, kReach);
}

namespace {

// The share of a source row's samples per angle at (x, y) that a row at the equator holds: cos(phi)
// on an equirect (its rows all hold the full circle of longitude), else 1.
double x_density(const Projection& source, double x, double y) {
  Ray d;
  if (!sampling_facts(source).rows_hold_turn || !to_ray(source, x, y, d)) return 1.0;
  return std::sqrt(std::max(0.0, 1.0 - d.y() * d.y() / d.squaredNorm()));  // latitude: asin(-y) (conventions.hpp)
}

}  // namespace

FootprintField FootprintField::for_rect(const PixelRect& tile, const PixelRect& rect, int n) const {
  // Sub-pixel X of the n-times target lies at output position (X + 0.5) / n - 0.5.
  FootprintField f = *this;
  const auto per_u = tile.width() > 1 ? 2.0 / static_cast<double>(tile.width() - 1) : 0.0;
  const auto per_v = tile.height() > 1 ? 2.0 / static_cast<double>(tile.height() - 1) : 0.0;
  f.u0 = static_cast<float>(((static_cast<double>(rect.x0) + 0.5) / n - 0.5 - static_cast<double>(tile.x0)) * per_u);
  f.v0 = static_cast<float>(((static_cast<double>(rect.y0) + 0.5) / n - 0.5 - static_cast<double>(tile.y0)) * per_v);
  f.du = static_cast<float>(per_u / n), f.dv = static_cast<float>(per_v / n);
  f.scale = 1.0f / static_cast<float>(n);
  return f;
}

FootprintSides footprint_field(const Projection& source, const Projection& target,
                               const Eigen::Matrix3d& rotation, const PixelRect& rect,
                               double wrap_width, FootprintField& field) {
  const auto wrap = static_cast<float>(wrap_width);
  std::array<float, 9> sides{}, split_sides{};
  std::array<bool, 9> has{};
  int count = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int q = 3 * r + c;
      const double px =
          static_cast<double>(rect.x0) + 0.5 + 0.5 * c * static_cast<double>(rect.width() - 1);
      const double py =
          static_cast<double>(rect.y0) + 0.5 + 0.5 * r * static_cast<double>(rect.height() - 1);
      double x, y;
      if (!source_pixel(source, target, rotation, px, py, x, y)) continue;
      auto step = [&](double dx, double dy, float& sx, float& sy) {  // to the neighbour (px + dx, py + dy); NaN: none
        double nx, ny;
        const bool ok = source_pixel(source, target, rotation, px + dx, py + dy, nx, ny);
        sx = ok ? static_cast<float>(nx - x) : NAN, sy = ok ? static_cast<float>(ny - y) : 0.0f;
      };
      float bx, by, ax, ay, ux, uy, vx, vy;
      step(-1, 0, bx, by), step(1, 0, ax, ay);
      if (!shorter_step(bx, by, ax, ay, wrap, ux, uy)) continue;
      step(0, -1, bx, by), step(0, 1, ax, ay);
      if (!shorter_step(bx, by, ax, ay, wrap, vx, vy)) continue;
      // The footprint's side: the geometric mean of its steps' lengths.
      auto side = [&] { return std::sqrt(std::sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy))); };
      field.ex[q] = std::sqrt(ux * ux + vx * vx), field.ey[q] = std::sqrt(uy * uy + vy * vy);
      sides[static_cast<size_t>(count)] = side();
      // An equirect row at latitude phi holds 1 / cos(phi) times the samples per angle of one at
      // the equator: x steps there count cos(phi) for the split.
      const auto density = static_cast<float>(x_density(source, x, y));
      ux *= density, vx *= density;
      split_sides[static_cast<size_t>(count++)] = side();
      has[static_cast<size_t>(q)] = true;
    }
  if (count == 0) return {0.0, 0.0};
  float mx = 0.0f, my = 0.0f;
  for (int q = 0; q < 9; ++q)
    if (has[static_cast<size_t>(q)]) mx += field.ex[q], my += field.ey[q];
  for (int q = 0; q < 9; ++q)
    if (!has[static_cast<size_t>(q)]) field.ex[q] = mx / static_cast<float>(count), field.ey[q] = my / static_cast<float>(count);
  field = field.for_rect(rect, rect, 1);
  auto median = [&](std::array<float, 9>& v) {
    std::nth_element(v.begin(), v.begin() + count / 2, v.begin() + count);
    return static_cast<double>(v[static_cast<size_t>(count / 2)]);
  };
  return {median(sides), median(split_sides)};
}

}  // namespace panoproj
