#pragma once
// Cubemap: six 90-degree faces placed in the cells of a layout image.
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
// order and orientation (verified against the real Jordan Pond pair: tests/cubemap_real_test.cpp)
// and FFmpeg v360's faces (vf_v360.c cube_to_xyz: the same six bases).
//
// A layout has six slots, each a cell (column, row) of its grid, "." unused:
//   6x1   slots 0..5 left to right       1x6  top to bottom
//   3x2   0 1 2 / 3 4 5                  cross (4 x 3): . 4 . . / 3 0 1 2 / . 5 . .
//   eac   3x2 (YouTube's equi-angular cubemap)
//   files six images, slot k the k-th file; in memory they are held as the 6x1 strip.
// Slot k holds face order[k], turned rot[k] quarter turns clockwise in its cell (v360's
// forder/frot). Default orders: f r b l u d (0..5), unturned; eac: l f r / d b u with the bottom
// row turned 3, 1, 3 (vf_v360.c prepare_eac_out). Presets put the slots in the cube-map targets'
// order +X -X +Y -Y +Z -Z, each target's image as the engine shows it (see cube_preset).
//
// Within a cell the position p maps to the cell coordinate s = (p - centre) / half, +-1 at the
// face's 90-degree edges, and s to the tangent a on the face:
//   cube  a = s                      eac  a = tan(pi/4 s)  (equal angles per pixel)
// pad widens every face's field (v360 in_pad): a cell spans |s| <= 1 / (1 - pad), its middle
// 1 - pad the face's 90 degrees. FFmpeg's EAC frame (border=ffmpeg, vf_v360.c eac_to_xyz) puts a
// 2-px border around each row of three faces, where a = s (tangents
// continued linearly); its faces are (W - 4) / 3 by H / 2 - 4 pixels, not whole pixels, so a
// cell's pixels are those whose centres fall in it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

enum class CubeLayout { Files, Row6x1, Column1x6, Grid3x2, Cross4x3, Eac, Cells };

// Where a face sits in a grid: its cell (column, row; -1: no cell) and its quarter turns
// clockwise there.
struct FaceCell {
  int col = -1, row = -1, rot = 0;
  bool operator==(const FaceCell&) const = default;
};

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

// What a layout's slots hold and how its cells lay the faces out (the spec keys order, rot, pad,
// layout=eac and border).
struct CubeFormat {
  std::array<int, 6> order{0, 1, 2, 3, 4, 5};
  std::array<int, 6> rot{};
  double pad = 0;
  bool angular = false;        // eac: a = tan(pi/4 s)
  bool ffmpeg_border = false;  // eac frames as FFmpeg writes them
  static CubeFormat eac();     // YouTube's order and turns
  bool operator==(const CubeFormat&) const = default;
};

// One axis of a layout's grid: cell k holds the pixels [edge[k], edge[k + 1]), its face's centre
// and half-size (the 90-degree edges at centre +- half) in pixels.
struct CubeAxis {
  int n = 1;
  std::array<int64_t, 7> edge{};
  std::array<double, 6> center{}, half{};
  int cell(double p) const {
    int k = 0;
    while (k + 1 < n && p >= static_cast<double>(edge[k + 1])) ++k;
    return k;
  }
  CubeAxis scaled(double s) const;  // throws Error unless the edges stay whole pixels
};

// The faces' names (front, right, back, left, up, down) and the axes' (px nx py ny pz nz).
extern const char* const kFaceNames[6];
extern const char* const kAxisNames[6];

// The face in each slot of a cube's six (the cubemap's order= key) and the axis it looks along (in
// the frame of its preset=; without one, panoproj's: x right, y down, z forward).
struct FaceOrder {
  std::array<int, 6> face{0, 1, 2, 3, 4, 5};
  std::array<int, 6> axis{4, 0, 5, 1, 3, 2};  // index into kAxisNames: front is +z, up -y
};
inline constexpr FaceOrder kDefaultFaceOrder{};

class ProjectionSpec;
// The FaceOrder of a cubemap spec's layout, order and preset keys.
FaceOrder cube_face_order(const ProjectionSpec& spec);

class Cubemap {
 public:
  // Square cells of face_size pixels.
  Cubemap(int64_t face_size, CubeLayout layout, const CubeFormat& format = {});
  // FFmpeg's EAC frame of `size` (border=ffmpeg).
  Cubemap(Size size, const CubeFormat& format);
  // A partial cube (layout Cells): faces in the cells of grid ax x ay (angular: the EAC law).
  Cubemap(const CubeAxis& ax, const CubeAxis& ay, const std::array<FaceCell, 6>& cells,
          bool angular);
  // The same field on a frame scaled by (sx, sy) (Error unless its cells stay whole pixels).
  Cubemap scaled(double sx, double sy) const;

  // Layout grid size in cells, and the cell of slot k.
  static std::array<int, 2> grid(CubeLayout layout);
  static std::array<int, 2> slot_cell(CubeLayout layout, int slot);
  CubeLayout layout() const { return layout_; }
  // Whether a face has a cell (every face but in a partial cube).
  bool has_face(int face) const { return cells_[face].col >= 0; }
  const CubeFormat& format() const { return format_; }
  const CubeAxis& x_axis() const { return ax_; }
  const CubeAxis& y_axis() const { return ay_; }
  // The cell of a face: pixels [x0, x1) x [y0, y1).
  std::array<int64_t, 4> cell_box(int face) const {
    const Slot& s = slots_[face];
    return {ax_.edge[s.col], ay_.edge[s.row], ax_.edge[s.col + 1], ay_.edge[s.row + 1]};
  }
  std::array<int64_t, 2> face_origin(int face) const { return {cell_box(face)[0], cell_box(face)[1]}; }
  // A square cell's side (a uniform cube's).
  int64_t face_size() const { return size_.width / ax_.n; }
  // Whether every cell is face_size() square (not border=ffmpeg's frame, nor a cube scaled by
  // unequal factors: a 4:2:2 frame's chroma plane).
  bool uniform() const { return uniform_; }
  // Face at a layout pixel position, or -1 outside every face.
  int face_at(double x, double y) const {
    if (!(x >= 0 && y >= 0 && x <= static_cast<double>(size_.width) && y <= static_cast<double>(size_.height))) return -1;
    return cell_face_[ay_.cell(y) * ax_.n + ax_.cell(x)];
  }
  // The face's rotated basis in its cell: the ray at tangents (A, B) of the cell's own axes is
  // fwd + A right + B down.
  const CubeFace& cell_basis(int face) const { return slots_[face].basis; }
  // Cell coordinate -> tangent and back (the face law, continued past the face's edges).
  double tangent(double s) const {
    if (!format_.angular || (format_.ffmpeg_border && std::fabs(s) > 1)) return s;
    // (Cells reach |s| = 1 / (1 - pad) <= 5/3; guard taps further out stay short of 90 degrees.)
    return std::tan(0.25 * kPi * std::clamp(s, -1.95, 1.95));
  }
  double cell_coordinate(double a) const {
    if (!format_.angular || (format_.ffmpeg_border && std::fabs(a) > 1)) return a;
    return std::atan(a) * (4 / kPi);
  }

  // Ray through face coordinates (a, b) of the canonical face; a, b may go past [-1, 1].
  static Ray face_ray(int face, double a, double b) {
    const CubeFace& c = cube_faces()[face];
    return (c.fwd + a * c.right + b * c.down).normalized();
  }
  // The ray at position (x, y) read on `face`'s cell, continued past its edges (guard taps).
  Ray cell_ray(int face, double x, double y) const {
    const Slot& s = slots_[face];
    const double A = tangent((x - ax_.center[s.col]) / ax_.half[s.col]);
    const double B = tangent((y - ay_.center[s.row]) / ay_.half[s.row]);
    return (s.basis.fwd + A * s.basis.right + B * s.basis.down).normalized();
  }
  // Position of ray d on `face`'s cell, unclamped; false if d is not in front of the face.
  bool cell_position(int face, const Ray& d, double& x, double& y) const {
    const Slot& s = slots_[face];
    const double depth = d.dot(s.basis.fwd);
    if (!(depth > 0)) return false;
    x = ax_.center[s.col] + ax_.half[s.col] * cell_coordinate(d.dot(s.basis.right) / depth);
    y = ay_.center[s.row] + ay_.half[s.row] * cell_coordinate(d.dot(s.basis.down) / depth);
    return true;
  }

  bool to_ray(double x, double y, Ray& d) const {
    const int face = face_at(x, y);
    if (face < 0) return false;
    d = cell_ray(face, x, y);
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    if (!d.allFinite() || d.isZero()) return false;
    int face = cube_face_of(d);
    if (partial_) {
      if (!has_face(face) || !cell_position(face, d, x, y)) return false;
      const auto b = cell_box(face);
      const double slack = kEdgeSlack * static_cast<double>(std::max(size_.width, size_.height));
      if (!(x >= static_cast<double>(b[0]) - slack && x <= static_cast<double>(b[2]) + slack &&
            y >= static_cast<double>(b[1]) - slack && y <= static_cast<double>(b[3]) + slack))
        return false;
    } else {
      cell_position(face, d, x, y);
    }
    if (!partial_ && !in_cell(face, x, y)) {
      // border=ffmpeg: a face's 90 degrees reach past its cell by under a pixel; that strip of
      // rays is held by a neighbouring cell's border (the faces of the next largest components).
      const auto alt = other_faces_of(d);
      for (int k = 0; k < 2; ++k) {
        double x2, y2;
        if (cell_position(alt[k], d, x2, y2) && in_cell(alt[k], x2, y2)) {
          face = alt[k], x = x2, y = y2;
          break;
        }
      }
    }
    // Kept inside the face's own cell; the clamp is applied in frame coordinates, where the
    // spacing of doubles is coarser.
    const auto b = cell_box(face);
    x = std::fmin(std::fmax(x, static_cast<double>(b[0])), std::nextafter(static_cast<double>(b[2]), 0.0));
    y = std::fmin(std::fmax(y, static_cast<double>(b[1])), std::nextafter(static_cast<double>(b[3]), 0.0));
    return true;
  }

  // Whether pixel position (x, y) has a ray (inside a face).
  bool contains(double x, double y) const { return in_frame(x, y, size_) && face_at(x, y) >= 0; }

  // True only if every position in [x0, x1] x [y0, y1] has a ray: both corners in one face's cell.
  bool covers(double x0, double y0, double x1, double y1) const {
    const int f = face_at(x0, y0);
    if (f < 0 || !in_frame(x0, y0, size_) || !in_frame(x1, y1, size_)) return false;
    const auto b = cell_box(f);
    return x1 < static_cast<double>(b[2]) && y1 < static_cast<double>(b[3]);
  }
  Size size() const { return size_; }
  // Pixels per radian at a face's centre: the cell's half-size times ds/da at 0.
  double center_density() const {
    return std::min(ax_.half[0], ay_.half[0]) * (format_.angular ? 4 / kPi : 1.0);
  }

 private:
  struct Slot {
    int col = 0, row = 0;
    CubeFace basis;
  };
  Cubemap(CubeLayout layout, const CubeFormat& format, const CubeAxis& ax, const CubeAxis& ay,
          const std::array<FaceCell, 6>& cells);
  // The cells of a layout's slots, by face.
  static std::array<FaceCell, 6> layout_cells(CubeLayout layout, const CubeFormat& format);
  // (The frame's far edges, x = W or y = H, belong to the last cells, as in face_at.)
  bool in_cell(int face, double x, double y) const {
    const auto b = cell_box(face);
    const double x1 = static_cast<double>(b[2]), y1 = static_cast<double>(b[3]);
    return x >= static_cast<double>(b[0]) && (x < x1 || (x == x1 && b[2] == size_.width)) &&
           y >= static_cast<double>(b[1]) && (y < y1 || (y == y1 && b[3] == size_.height));
  }
  // The faces of d's second and third largest |components| (of their signs).
  static std::array<int, 2> other_faces_of(const Ray& d);

  CubeLayout layout_;
  CubeFormat format_;
  CubeAxis ax_, ay_;
  Size size_;
  bool uniform_ = true;
  bool partial_ = false;             // layout Cells
  std::array<FaceCell, 6> cells_{};  // by face
  std::array<Slot, 6> slots_{};      // by face
  std::array<int, 12> cell_face_{};
};

}  // namespace panoproj
