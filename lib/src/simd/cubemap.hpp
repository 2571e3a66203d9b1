#pragma once
// A cubemap's SIMD lanes (vector forms in cubemap-inl.h).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "panoproj/projections/cubemap.hpp"
#include "geometry/tile_map.hpp"
#include "simd/lanes.hpp"

namespace panoproj::simd {

// As a target, one face's cell: A = (x - ox) kx - mx, B = (y - oy) ky - my (the cell's
// coordinates, kx = 1 / half, mx = (centre - ox) / half: 2 / F and 1 without pad), the tangents
// a = A, b = B (eac: a = tan(pi/4 A)) and the ray fwd + a right + b down, the cell's basis rotated
// (the rays come rotated). Even cells only (FFmpeg's EAC frame: tile maps).
template <class T>
struct CubeFaceRays {
  bool angular;
  T ox, oy, kx, ky, mx, my;
  T fwd[3], right[3], down[3];
};

// Returns false unless the whole tile lies inside one face's cell.
template <class T>
bool describe(const Cubemap& c, const PixelRect& rect, const Eigen::Matrix3d& rotation,
              CubeFaceRays<T>& l) {
  if (!c.uniform()) return false;
  l.angular = c.format().angular;
  const int f = c.face_at(static_cast<double>(rect.x0) + 0.5, static_cast<double>(rect.y0) + 0.5);
  if (f < 0) return false;
  const auto box = c.cell_box(f);
  if (rect.x0 + rect.width() > box[2] || rect.y0 + rect.height() > box[3]) return false;
  const CubeFace& cf = c.cell_basis(f);
  const Eigen::Vector3d fwd = rotation * cf.fwd, right = rotation * cf.right, down = rotation * cf.down;
  const double ox = static_cast<double>(box[0]), oy = static_cast<double>(box[1]);
  const double hx = 0.5 * static_cast<double>(box[2] - box[0]), hy = 0.5 * static_cast<double>(box[3] - box[1]);
  const double sx = hx / c.x_axis().half[0], sy = hy / c.y_axis().half[0];  // 1 / (1 - pad)
  l.ox = lane<T>(ox);
  l.oy = lane<T>(oy);
  l.kx = lane<T>(sx / hx);
  l.ky = lane<T>(sy / hy);
  l.mx = lane<T>(sx);
  l.my = lane<T>(sy);
  for (int i = 0; i < 3; ++i) {
    l.fwd[i] = lane<T>(fwd[i]);
    l.right[i] = lane<T>(right[i]);
    l.down[i] = lane<T>(down[i]);
  }
  return true;
}

// As a source: the face of the ray's largest component and its tangents (a, b) (eac: the
// cell coordinates 4/pi atan a, 4/pi atan b). Plain cubes (unturned faces, no pad, tangent law):
// the cell's origin (ox, oy)[face] and position half_face (a + 1) within it, F = face. Others:
// x = kx[0] + kx[1] a + kx[2] b, y likewise, per face (its turn and pad), kept in its cell
// [x0, x1) x [y0, y1). Even cells only (FFmpeg's EAC frame: tile maps).
template <class T>
struct CubemapSource {
  bool plain, angular;
  T face, half_face;
  T ox[6], oy[6];
  T kx[3][6], ky[3][6], x1[6], y1[6];
};

// Returns whether float lanes serve: a = an / depth, both with the ray's error (depth >= |ray| /
// sqrt(3)), plus rounding; eac: atan's slope is at most 1, its polynomial within 3 ulp, times 4/pi.
template <class T>
bool describe(const Cubemap& c, CubemapSource<T>& l) {
  const double f = static_cast<double>(c.face_size());
  const CubeFormat& fm = c.format();
  l.angular = fm.angular;
  l.plain = fm.pad == 0 && fm.rot == std::array<int, 6>{} && !fm.angular;
  l.face = lane<T>(f);
  l.half_face = lane<T>(0.5 * f);
  for (int i = 0; i < 6; ++i) {
    const auto box = c.cell_box(i);
    const CubeFace& canon = cube_faces()[i];
    const CubeFace& cell = c.cell_basis(i);
    const int col = static_cast<int>(box[0] / c.face_size()), row = static_cast<int>(box[1] / c.face_size());
    const double hx = c.x_axis().half[col], hy = c.y_axis().half[row];
    l.ox[i] = lane<T>(box[0]);
    l.oy[i] = lane<T>(box[1]);
    l.kx[0][i] = lane<T>(c.x_axis().center[col]);
    l.kx[1][i] = lane<T>(hx * cell.right.dot(canon.right));
    l.kx[2][i] = lane<T>(hx * cell.right.dot(canon.down));
    l.ky[0][i] = lane<T>(c.y_axis().center[row]);
    l.ky[1][i] = lane<T>(hy * cell.down.dot(canon.right));
    l.ky[2][i] = lane<T>(hy * cell.down.dot(canon.down));
    l.x1[i] = lane<T>(box[2]);
    l.y1[i] = lane<T>(box[3]);
  }
  const Size frame = c.size();
  const double law = fm.angular ? 4 / kPi : 1, atan_error = fm.angular ? 6 * kHalfUlp : 0;
  return static_cast<double>(std::max(frame.width, frame.height)) * kHalfUlp +
             0.5 * f * law * (2 * std::sqrt(3.0) * kFloatRayError + atan_error) <=
         kFloatTolerance;
}

}  // namespace panoproj::simd
