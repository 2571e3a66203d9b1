#include "panoproj/maps.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include "base/parallel.hpp"
#include "geometry/tile_map.hpp"

namespace panoproj {

Image build_map(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation,
                MapConvention convention, int threads) {
  const Size size = size_of(dst);
  Image map(size, 2, PixelType::F32);
  const double shift = convention == MapConvention::OpenCV ? kCvPixelShift : 0.0;
  const float none = convention == MapConvention::OpenCV ? -1.0f : std::numeric_limits<float>::quiet_NaN();
  // Bands of whole tile rows, so each band maps complete tiles.
  const int64_t tile_rows = (size.height + kTile - 1) / kTile;
  parallel_rows(tile_rows, threads, [&](int64_t r0, int64_t r1) {
    TileMap tm;
    for (int64_t ty = r0 * kTile; ty < std::min(size.height, r1 * kTile); ty += kTile)
      for (int64_t tx = 0; tx < size.width; tx += kTile) {
        const PixelRect rect{tx, ty, std::min(tx + kTile, size.width),
                             std::min(ty + kTile, size.height)};
        map_tile(src, dst, rotation, rect, tm);
        for (int64_t j = 0; j < rect.height(); ++j) {
          float* row = reinterpret_cast<float*>(map.pixel(tx, ty + j));
          for (int64_t i = 0; i < rect.width(); ++i) {
            const size_t k = static_cast<size_t>(j * rect.width() + i);
            row[2 * i] = tm.ok[k] ? static_cast<float>(tm.xs[k] - shift) : none;
            row[2 * i + 1] = tm.ok[k] ? static_cast<float>(tm.ys[k] - shift) : none;
          }
        }
      }
  });
  return map;
}

}  // namespace panoproj
