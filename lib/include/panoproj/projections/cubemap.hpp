#pragma once
// Cubemap: six 90-degree pinhole faces of F x F pixels, placed in a layout image.
//
// Faces, in index order, with the ray through face coordinates (a, b) in [-1, 1]^2
// (a to the right of the face image, b down it):  ray = normalize(fwd + a * right + b * down)
//   0 front  fwd +z  right +x  down +y
//   1 right  fwd +x  right -z  down +y   (yaw +90)
//   2 back   fwd -z  right -x  down +y   (yaw 180)
//   3 left   fwd -x  right +z  down +y   (yaw -90)
//   4 up     fwd -y  right +x  down +z   (pitch +90: the top of the face is toward the back)
//   5 down   fwd +y  right +x  down -z   (pitch -90: the top of the face is toward the front)
// Side faces are seen as from the centre with up at the top. This matches Pannellum's cubemap
// order and orientation (verified against the real Jordan Pond pair: tests/cubemap_real_test.cpp).
//
// Layouts (cells of F x F, column, row), face indices as above, "." unused:
//   6x1   0 1 2 3 4 5          1x6  one column, 0 at the top
//   3x2   0 1 2 / 3 4 5        cross (4 wide, 3 high):  . 4 . . / 3 0 1 2 / . 5 . .
//   files six images; in memory they are held as the 6x1 strip.
#include <array>
#include <cmath>
#include <cstdint>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

enum class CubeLayout { Files, Row6x1, Column1x6, Grid3x2, Cross4x3 };

struct CubeFace {
  Ray fwd, right, down;
};

inline const std::array<CubeFace, 6>& cube_faces() {
  static const std::array<CubeFace, 6> faces = {{
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},    // front
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},   // right
      {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},  // back
      {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},   // left
      {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},   // up
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},   // down
  }};
  return faces;
}

// The face whose forward axis is closest to d (largest |component|; ties: x, then y, then z).
inline int cube_face_of(const Ray& d) {
  const double ax = std::fabs(d.x()), ay = std::fabs(d.y()), az = std::fabs(d.z());
  if (ax >= ay && ax >= az) return d.x() > 0 ? 1 : 3;
  if (ay >= az) return d.y() > 0 ? 5 : 4;
  return d.z() > 0 ? 0 : 2;
}

class Cubemap {
 public:
  Cubemap(int64_t face_size, CubeLayout layout);

  // Layout grid size in cells and the cell of each face.
  static std::array<int, 2> grid(CubeLayout layout);
  std::array<int64_t, 2> face_origin(int face) const { return origin_[face]; }
  int64_t face_size() const { return f_; }
  CubeLayout layout() const { return layout_; }
  // Face at a layout pixel position, or -1 outside every face.
  int face_at(double x, double y) const {
    const auto cx = static_cast<int64_t>(std::floor(x / fd_));
    const auto cy = static_cast<int64_t>(std::floor(y / fd_));
    // The closed frame's far edges (x == W, y == H) belong to the last cell.
    const int64_t col = cx == cols_ ? cols_ - 1 : cx, row = cy == rows_ ? rows_ - 1 : cy;
    if (col < 0 || row < 0 || col >= cols_ || row >= rows_) return -1;
    return cell_face_[row * cols_ + col];
  }

  // Ray through face coordinates (a, b); a, b may go past [-1, 1] (used for guard taps).
  static Ray face_ray(int face, double a, double b) {
    const CubeFace& c = cube_faces()[face];
    return (c.fwd + a * c.right + b * c.down).normalized();
  }

  bool to_ray(double x, double y, Ray& d) const {
    const int face = face_at(x, y);
    if (face < 0) return false;
    const double a = 2.0 * (x - static_cast<double>(origin_[face][0])) / fd_ - 1.0;
    const double b = 2.0 * (y - static_cast<double>(origin_[face][1])) / fd_ - 1.0;
    d = face_ray(face, a, b);
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    if (!d.allFinite() || d.isZero()) return false;
    const int face = cube_face_of(d);
    const CubeFace& c = cube_faces()[face];
    const double depth = d.dot(c.fwd);
    const double a = d.dot(c.right) / depth, b = d.dot(c.down) / depth;
    // Kept inside the face's own cell (a = 1 would land in the next cell of the layout); the
    // clamp is applied after adding the origin, where the spacing of doubles is coarser.
    const double ox = static_cast<double>(origin_[face][0]), oy = static_cast<double>(origin_[face][1]);
    x = std::fmin(std::fmax(ox + 0.5 * (a + 1.0) * fd_, ox), std::nextafter(ox + fd_, 0.0));
    y = std::fmin(std::fmax(oy + 0.5 * (b + 1.0) * fd_, oy), std::nextafter(oy + fd_, 0.0));
    return true;
  }

  // Whether pixel position (x, y) has a ray (inside a face).
  bool contains(double x, double y) const { return in_frame(x, y, size_) && face_at(x, y) >= 0; }

  // True only if every position in [x0, x1] x [y0, y1] has a ray: both corners in one face's cell.
  bool covers(double x0, double y0, double x1, double y1) const {
    const int f = face_at(x0, y0);
    if (f < 0 || !in_frame(x0, y0, size_) || !in_frame(x1, y1, size_)) return false;
    const double ox = static_cast<double>(origin_[f][0]), oy = static_cast<double>(origin_[f][1]);
    return x1 < ox + fd_ && y1 < oy + fd_;
  }
  Size size() const { return size_; }
  double center_density() const { return 0.5 * fd_; }  // face focal length F/2

 private:
  int64_t f_;
  double fd_;
  CubeLayout layout_;
  int64_t cols_, rows_;
  Size size_;
  std::array<std::array<int64_t, 2>, 6> origin_{};
  std::array<int, 12> cell_face_{};
};

}  // namespace panoproj
