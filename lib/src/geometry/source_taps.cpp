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
      const int64_t f = cube_->face_size();
      const auto o = cube_->face_origin(face);
      const int64_t lx = ix - o[0], ly = iy - o[1];
      if (lx >= 0 && ly >= 0 && lx < f && ly < f) break;
      // The tap's centre on the extended face plane, re-projected onto the cube.
      const double fd = static_cast<double>(f);
      const Ray d = Cubemap::face_ray(face, 2.0 * (static_cast<double>(lx) + 0.5) / fd - 1.0,
                                      2.0 * (static_cast<double>(ly) + 0.5) / fd - 1.0);
      const int nf = cube_face_of(d);
      const CubeFace& c = cube_faces()[nf];
      const double depth = d.dot(c.fwd);
      // Continuous position on the neighbour face, pixel centres at integers.
      const double u = 0.5 * (d.dot(c.right) / depth + 1.0) * fd - 0.5;
      const double v = 0.5 * (d.dot(c.down) / depth + 1.0) * fd - 0.5;
      const double u0 = std::floor(u), v0 = std::floor(v);
      const double fu = u - u0, fv = v - v0;
      const auto no = cube_->face_origin(nf);
      auto clampf = [f](double t) {
        return std::clamp<int64_t>(static_cast<int64_t>(t), 0, f - 1);
      };
      const int64_t x0 = no[0] + clampf(u0), x1 = no[0] + clampf(u0 + 1);
      const int64_t y0 = no[1] + clampf(v0), y1 = no[1] + clampf(v0 + 1);
      parts[0] = {x0, y0, (1 - fu) * (1 - fv)};
      parts[1] = {x1, y0, fu * (1 - fv)};
      parts[2] = {x0, y1, (1 - fu) * fv};
      parts[3] = {x1, y1, fu * fv};
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
