#include "geometry/tile_map.hpp"

#include <algorithm>
#include <array>
#include <utility>
#include <cmath>

namespace panoproj {
namespace {

// lagrange_cubic at t = i / kCell.
struct Lagrange {
  double w[kCell + 1][4];
  Lagrange() {
    for (int i = 0; i <= kCell; ++i) lagrange_cubic(static_cast<double>(i) / kCell, w[i]);
  }
};
const Lagrange kLagrange;

}  // namespace

void map_tile(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation,
              PixelRect rect, TileMap& out, bool exact, const Siting& siting) {
  // Target sample k sits at k + hx (hy); source positions are read at p - (source_x, source_y).
  const double hx = 0.5 + siting.target_x, hy = 0.5 + siting.target_y;
  const auto n = static_cast<size_t>(rect.width() * rect.height());
  out.rect = rect;
  out.xs.resize(n);
  out.ys.resize(n);
  out.ok.assign(n, 0);
  out.exact_cells = out.interpolated_cells = 0;

  // Node i sits at offset (i - 1) * kCell from the tile's corner.
  const int64_t ncx = (rect.width() + kCell - 1) / kCell, ncy = (rect.height() + kCell - 1) / kCell;
  const int64_t nx = ncx + 3, ny = ncy + 3;
  std::vector<double> nxs(static_cast<size_t>(nx * ny)), nys(nxs.size());
  std::vector<uint8_t> nok(nxs.size());
  for (int64_t j = 0; j < ny; ++j)
    for (int64_t i = 0; i < nx; ++i) {
      const size_t k = static_cast<size_t>(j * nx + i);
      nok[k] = source_pixel(src, dst, rotation, static_cast<double>(rect.x0 + (i - 1) * kCell) + hx,
                            static_cast<double>(rect.y0 + (j - 1) * kCell) + hy, nxs[k], nys[k]);
    }

  std::array<Ray, kCell> rays;
  std::array<double, kCell> rx, ry;
  std::array<uint8_t, kCell> rok;
  for (int64_t cy = 0; cy < ncy; ++cy)
    for (int64_t cx = 0; cx < ncx; ++cx) {
      const int64_t w = std::min<int64_t>(kCell, rect.width() - cx * kCell);
      const int64_t h = std::min<int64_t>(kCell, rect.height() - cy * kCell);
      const int64_t px0 = rect.x0 + cx * kCell, py0 = rect.y0 + cy * kCell;
      // The cell's 4x4 stencil starts at node (cx, cy), one cell up and left.
      auto node = [&](int a, int b) { return static_cast<size_t>((cy + b) * nx + cx + a); };
      bool accept = true;
      for (int b = 0; b < 4; ++b)
        for (int a = 0; a < 4; ++a) accept = accept && nok[node(a, b)];
      // Separable: along y per stencil column (for row j), then along x (for column i).
      double col_x[kCell][4], col_y[kCell][4];
      auto columns = [&](int j) {
        for (int a = 0; a < 4; ++a) {
          double sx = 0, sy = 0;
          for (int b = 0; b < 4; ++b) {
            sx += kLagrange.w[j][b] * nxs[node(a, b)];
            sy += kLagrange.w[j][b] * nys[node(a, b)];
          }
          col_x[j][a] = sx;
          col_y[j][a] = sy;
        }
      };
      auto interp = [&](int i, int j, double& sx, double& sy) {
        sx = sy = 0;
        for (int a = 0; a < 4; ++a) {
          sx += kLagrange.w[i][a] * col_x[j][a];
          sy += kLagrange.w[i][a] * col_y[j][a];
        }
      };
      if (accept) {
        // The centre first (cubic error peaks mid-cell); where it errs by over kMapTolerance/16
        // the map is curved enough to need eight more: quarter points and the inner square's
        // edge midpoints.
        constexpr int q = kCell / 4, h3 = 3 * kCell / 4, c = kCell / 2;
        constexpr std::pair<int, int> kChecks[9] = {{c, c},  {q, q}, {h3, q}, {q, h3}, {h3, h3},
                                                    {c, q},  {q, c}, {h3, c}, {c, h3}};
        for (int k = 0; k < 9 && accept; ++k) {
          const auto [i, j] = kChecks[k];
          double ex, ey, ix, iy;
          if (!source_pixel(src, dst, rotation, static_cast<double>(px0 + i) + hx,
                            static_cast<double>(py0 + j) + hy, ex, ey)) {
            accept = false;
            break;
          }
          columns(j);
          interp(i, j, ix, iy);
          const double e = std::hypot(ix - ex, iy - ey);
          accept = e <= kMapTolerance;
          if (k == 0 && e <= kMapTolerance / 16) break;
        }
      }
      if (accept) {
        ++out.interpolated_cells;
        double gx[4][4], gy[4][4];  // the stencil's nodes, [b][a]
        for (int b = 0; b < 4; ++b)
          for (int a = 0; a < 4; ++a) {
            gx[b][a] = nxs[node(a, b)];
            gy[b][a] = nys[node(a, b)];
          }
        double bx0 = HUGE_VAL, by0 = HUGE_VAL, bx1 = -HUGE_VAL, by1 = -HUGE_VAL;
        for (int64_t j = 0; j < h; ++j) {
          const double* wj = kLagrange.w[j];
          double cx4[4], cy4[4];
          for (int a = 0; a < 4; ++a) {
            cx4[a] = wj[0] * gx[0][a] + wj[1] * gx[1][a] + wj[2] * gx[2][a] + wj[3] * gx[3][a];
            cy4[a] = wj[0] * gy[0][a] + wj[1] * gy[1][a] + wj[2] * gy[2][a] + wj[3] * gy[3][a];
          }
          const size_t row = static_cast<size_t>((cy * kCell + j) * rect.width() + cx * kCell);
          for (int64_t i = 0; i < w; ++i) {
            const double* wi = kLagrange.w[i];
            double sx = wi[0] * cx4[0] + wi[1] * cx4[1] + wi[2] * cx4[2] + wi[3] * cx4[3];
            double sy = wi[0] * cy4[0] + wi[1] * cy4[1] + wi[2] * cy4[2] + wi[3] * cy4[3];
            auto near = [](double v) { return std::fabs(v - std::round(v)) < kMapEdgeGuard; };
            if (exact && (near(sx - siting.source_x) || near(sy - siting.source_y))) {
              double ex, ey;
              if (source_pixel(src, dst, rotation, static_cast<double>(px0 + i) + hx,
                               static_cast<double>(py0 + j) + hy, ex, ey))
                sx = ex, sy = ey;
            }
            out.xs[row + i] = sx;
            out.ys[row + i] = sy;
            bx0 = std::min(bx0, sx), bx1 = std::max(bx1, sx);
            by0 = std::min(by0, sy), by1 = std::max(by1, sy);
          }
        }
        // Validity: one dispatch per cell and side, the pixel loops seeing the concrete
        // projection type (one visit over both would instantiate every pair: 225 bodies that took
        // minutes to compile under ASan). Per-pixel tests run only where the cell's rectangle
        // (output) or its positions' bounding box (source) is not covered as a whole.
        std::visit(
            [&](const auto& d) {
              const bool all = d.covers(
                  static_cast<double>(px0) + hx, static_cast<double>(py0) + hy,
                  static_cast<double>(px0 + w - 1) + hx, static_cast<double>(py0 + h - 1) + hy);
              for (int64_t j = 0; j < h; ++j) {
                const size_t row =
                    static_cast<size_t>((cy * kCell + j) * rect.width() + cx * kCell);
                const double py = static_cast<double>(py0 + j) + hy;
                for (int64_t i = 0; i < w; ++i)
                  out.ok[row + i] = all || d.contains(static_cast<double>(px0 + i) + hx, py);
              }
            },
            dst);
        std::visit(
            [&](const auto& sp) {
              if (sp.covers(bx0, by0, bx1, by1)) return;
              for (int64_t j = 0; j < h; ++j) {
                const size_t row =
                    static_cast<size_t>((cy * kCell + j) * rect.width() + cx * kCell);
                for (int64_t i = 0; i < w; ++i)
                  out.ok[row + i] = out.ok[row + i] && sp.contains(out.xs[row + i], out.ys[row + i]);
              }
            },
            src);
      } else {
        ++out.exact_cells;
        for (int64_t j = 0; j < h; ++j) {
          to_ray_row(dst, static_cast<double>(py0 + j) + hy, px0, w, rays.data(), rok.data(), hx);
          for (int64_t i = 0; i < w; ++i) rays[i] = rotation * rays[i];
          to_pixel_row(src, rays.data(), w, rx.data(), ry.data(), rok.data());
          for (int64_t i = 0; i < w; ++i) {
            const size_t k = static_cast<size_t>((cy * kCell + j) * rect.width() + cx * kCell + i);
            out.xs[k] = rx[i];
            out.ys[k] = ry[i];
            out.ok[k] = rok[i];
          }
        }
      }
    }
  if (siting.source_x != 0 || siting.source_y != 0)
    for (size_t k = 0; k < n; ++k) out.xs[k] -= siting.source_x, out.ys[k] -= siting.source_y;
}

}  // namespace panoproj
