#include "geometry/source_taps.hpp"

#include <algorithm>
#include <cmath>

namespace panoproj {

SourceTaps::SourceTaps(const Projection& source) {
  const Size s = size_of(source);
  w_ = s.width;
  h_ = s.height;
  if (const auto* e = std::get_if<Equirect>(&source)) {
    mode_ = Mode::Equirect;
    wrap_x_ = e->full_longitude();
    north_ = e->reaches_north_pole();
    south_ = e->reaches_south_pole();
  } else if (const auto* y = std::get_if<Cylindrical>(&source)) {
    mode_ = Mode::Equirect;  // same seam; its poles are at infinity, so no pole crossing
    wrap_x_ = y->full_longitude();
  } else if (const auto* c = std::get_if<Cubemap>(&source)) {
    mode_ = Mode::Cube;
    cube_ = c;
  } else if (const auto* d = std::get_if<DualFisheye>(&source)) {
    mode_ = Mode::Cells;
    dual_ = d;
  }
}

int SourceTaps::resolve(int64_t ix, int64_t iy, int face, Part* parts) const {
  switch (mode_) {
    case Mode::Equirect:
      // Crossing a pole: row -1 - j (or 2H - 1 - j), half a turn of longitude away.
      if (iy < 0 && north_) {
        iy = -1 - iy;
        ix += w_ / 2;
      } else if (iy >= h_ && south_) {
        iy = 2 * h_ - 1 - iy;
        ix += w_ / 2;
      }
      if (wrap_x_) {
        ix %= w_;
        if (ix < 0) ix += w_;
      }
      break;
    case Mode::Cube: {
      if (face < 0) break;
      const auto b = cube_->cell_box(face);
      if (ix >= b[0] && iy >= b[1] && ix < b[2] && iy < b[3]) break;
      // The tap's centre on the face's cell continued past its edges, re-projected onto the cube:
      // a continuous position on the cell holding that ray, pixel centres at integers.
      double x = 0, y = 0;  // (every ray has a cube pixel)
      cube_->to_pixel(cube_->cell_ray(face, static_cast<double>(ix) + 0.5, static_cast<double>(iy) + 0.5), x, y);
      const auto nb = cube_->cell_box(cube_->face_at(x, y));
      const double u = x - 0.5, v = y - 0.5, u0 = std::floor(u), v0 = std::floor(v);
      const double fu = u - u0, fv = v - v0;
      auto cx = [&](double t) { return std::clamp<int64_t>(static_cast<int64_t>(t), nb[0], nb[2] - 1); };
      auto cy = [&](double t) { return std::clamp<int64_t>(static_cast<int64_t>(t), nb[1], nb[3] - 1); };
      parts[0] = {cx(u0), cy(v0), (1 - fu) * (1 - fv)};
      parts[1] = {cx(u0 + 1), cy(v0), fu * (1 - fv)};
      parts[2] = {cx(u0), cy(v0 + 1), (1 - fu) * fv};
      parts[3] = {cx(u0 + 1), cy(v0 + 1), fu * fv};
      return 4;
    }
    case Mode::Cells: {
      // Within the lens's half.
      const int64_t cw = dual_->cell_width(), ch = dual_->cell_height();
      const int64_t ox = dual_->top_bottom() ? 0 : face * cw, oy = dual_->top_bottom() ? face * ch : 0;
      parts[0] = {std::clamp<int64_t>(ix, ox, ox + cw - 1), std::clamp<int64_t>(iy, oy, oy + ch - 1), 1.0};
      return 1;
    }
    case Mode::Clamp: break;
  }
  parts[0] = {std::clamp<int64_t>(ix, 0, w_ - 1), std::clamp<int64_t>(iy, 0, h_ - 1), 1.0};
  return 1;
}

}  // namespace panoproj
