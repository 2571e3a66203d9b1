#include "geometry/source_taps.hpp"

#include <algorithm>
#include <cmath>

namespace panoproj {

SourceTaps::SourceTaps(const Projection& source) : facts_(sampling_facts(source)) {
  const Size s = size_of(source);
  // Pixels whose centres lie in the box, at least one.
  auto first = [](double edge, int64_t n) {
    return std::clamp<int64_t>(static_cast<int64_t>(std::ceil(edge - 0.5)), 0, n - 1);
  };
  col0_ = first(facts_.x0, s.width), row0_ = first(facts_.y0, s.height);
  col1_ = std::clamp<int64_t>(static_cast<int64_t>(std::ceil(facts_.x1 - 0.5)), col0_ + 1, s.width);
  row1_ =
      std::clamp<int64_t>(static_cast<int64_t>(std::ceil(facts_.y1 - 0.5)), row0_ + 1, s.height);
}

int SourceTaps::resolve(int64_t ix, int64_t iy, int face, Part* parts) const {
  if (facts_.cube) {
    if (face >= 0) return cube_neighbour(*facts_.cube, ix, iy, face, parts);
  } else if (facts_.max) {
    if (face >= 0) return cube_neighbour(facts_.max->lens(face / 8), ix, iy, face % 8, parts);
  } else if (facts_.dual) {
    // Within the lens's half.
    const DualFisheye& d = *facts_.dual;
    const int64_t cw = d.cell_width(), ch = d.cell_height();
    const int64_t ox = d.top_bottom() ? 0 : face * cw, oy = d.top_bottom() ? face * ch : 0;
    parts[0] = {std::clamp<int64_t>(ix, ox, ox + cw - 1), std::clamp<int64_t>(iy, oy, oy + ch - 1),
                1.0};
    return 1;
  } else if (ix < col0_ || ix >= col1_ || iy < row0_ || iy >= row1_) {
    return wrapped(ix, iy, parts);
  }
  parts[0] = {std::clamp(ix, col0_, col1_ - 1), std::clamp(iy, row0_, row1_ - 1), 1.0};
  return 1;
}

int SourceTaps::wrapped(int64_t ix, int64_t iy, Part* parts) const {
  const SamplingFacts& f = facts_;
  const double x = static_cast<double>(ix) + 0.5,
               y = static_cast<double>(iy) + 0.5;  // the tap's centre
  const double turn = f.x1 - f.x0;
  // Rows: linear between the two row centres around a position (clamped into the box's rows);
  // past a pole line the position mirrored about it, on the far side (half a turn away). Between
  // the pole line and the first row's centre, the neighbours are that row on both sides of the
  // pole.
  struct Row {
    int64_t r;
    double w;
    bool far;
  } rows[2];
  auto between = [&](double at, bool far) {
    const double v0 = std::floor(at - 0.5), fv = at - 0.5 - v0;
    rows[0] = {std::clamp(static_cast<int64_t>(v0), row0_, row1_ - 1), 1 - fv, far};
    rows[1] = {std::clamp(static_cast<int64_t>(v0) + 1, row0_, row1_ - 1), fv, far};
  };
  auto over_pole = [&](double mirrored, int64_t edge_row, double near, double first) {
    if ((mirrored - first) * (first - near) >= 0)
      return between(mirrored, true);  // past the first centre
    const double w_far = (mirrored - near) / (first - near);
    rows[0] = {edge_row, 1 - w_far, false};
    rows[1] = {edge_row, w_far, true};
  };
  if (y < f.y0 && f.north_pole) {
    const double first = static_cast<double>(row0_) + 0.5;
    over_pole(2 * f.y0 - y, row0_, 2 * f.y0 - first, first);
  } else if (y >= f.y1 && f.south_pole) {
    const double last = static_cast<double>(row1_) - 0.5;
    over_pole(2 * f.y1 - y, row1_ - 1, 2 * f.y1 - last, last);
  } else {
    between(y, false);
  }
  // Columns: where x wraps, the centres of the box continue periodically (across the seam the
  // gap is under a pixel where the box's edges are fractional); else clamped into the box.
  int n = 0;
  for (const Row& row : rows) {
    if (row.w == 0) continue;
    double at = row.far ? x + 0.5 * turn : x;
    int64_t xs[2];
    double wx[2];
    if (f.wraps_x) {
      at -= turn * std::floor((at - f.x0) / turn);
      const double first = static_cast<double>(col0_) + 0.5,
                   last = static_cast<double>(col1_) - 0.5;
      double left = std::floor(at - 0.5) + 0.5, right = left + 1;  // centres
      xs[0] = static_cast<int64_t>(left - 0.5), xs[1] = xs[0] + 1;
      if (at < first)
        left = last - turn, xs[0] = col1_ - 1, right = first, xs[1] = col0_;
      else if (right > last)
        right = first + turn, xs[1] = col0_;
      wx[1] = (at - left) / (right - left), wx[0] = 1 - wx[1];
    } else {
      const double u0 = std::floor(at - 0.5);
      xs[0] = std::clamp(static_cast<int64_t>(u0), col0_, col1_ - 1);
      xs[1] = std::clamp(static_cast<int64_t>(u0) + 1, col0_, col1_ - 1);
      wx[1] = at - 0.5 - u0, wx[0] = 1 - wx[1];
    }
    for (int i = 0; i < 2; ++i)
      if (wx[i] != 0) parts[n++] = {xs[i], row.r, wx[i] * row.w};
  }
  return n;
}

int SourceTaps::cube_neighbour(const Cubemap& cube, int64_t ix, int64_t iy, int face,
                               Part* parts) const {
  const auto b = cube.cell_box(face);
  if (ix >= b[0] && iy >= b[1] && ix < b[2] && iy < b[3]) {
    parts[0] = {ix, iy, 1.0};
    return 1;
  }
  // The tap's centre on the face's cell continued past its edges, re-projected onto the cube:
  // a continuous position on the cell holding that ray, pixel centres at integers. (Every ray
  // has a pixel of a whole cube; one a partial cube does not see stays in the cell.)
  double x = 0, y = 0;
  if (!cube.to_pixel(
          cube.cell_ray(face, static_cast<double>(ix) + 0.5, static_cast<double>(iy) + 0.5), x,
          y)) {
    parts[0] = {std::clamp(ix, b[0], b[2] - 1), std::clamp(iy, b[1], b[3] - 1), 1.0};
    return 1;
  }
  const auto nb = cube.cell_box(cube.face_at(x, y));
  const double u = x - 0.5, v = y - 0.5, u0 = std::floor(u), v0 = std::floor(v);
  const double fu = u - u0, fv = v - v0;
  auto cx = [&](double t) {
    return std::clamp<int64_t>(static_cast<int64_t>(t), nb[0], nb[2] - 1);
  };
  auto cy = [&](double t) {
    return std::clamp<int64_t>(static_cast<int64_t>(t), nb[1], nb[3] - 1);
  };
  parts[0] = {cx(u0), cy(v0), (1 - fu) * (1 - fv)};
  parts[1] = {cx(u0 + 1), cy(v0), fu * (1 - fv)};
  parts[2] = {cx(u0), cy(v0 + 1), (1 - fu) * fv};
  parts[3] = {cx(u0 + 1), cy(v0 + 1), fu * fv};
  return 4;
}

}  // namespace panoproj
