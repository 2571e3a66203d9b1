#pragma once
// Mip levels of a source for antialiasing (Antialias's auto). Level k + 1 is level k shrunk
// 2 times on each axis, each pixel the mean of a 2x2 block (integers rounded to nearest; colour
// weighted by alpha where there is one); the projection of level k is the source's rescaled to
// its size, so a position x at level 0 is x / 2^k there. Levels exist while the frame (and a cubemap's faces, which then start on even
// pixels: blocks never straddle a face edge) stay even. Rows are built in bands on request, so
// a view that shrinks only part of the source (the polar rows of an equirect seen as a cube)
// pays only for those; safe to call from several threads. Internal.
#include <memory>
#include <mutex>
#include <vector>

#include "panoproj/image.hpp"
#include "panoproj/projection.hpp"
#include "geometry/source_taps.hpp"

namespace panoproj {

// Halvings p allows (0: none).
int deepest_level(const Projection& p);

class Pyramid {
 public:
  // src: the source image (may be a window of its frame: a level holds the blocks the window
  // touches, a block half outside averaging the pixels held), which must outlive the pyramid.
  // Allocates the levels (untouched memory costs nothing); their rows are built on request.
  Pyramid(const Image& src, const Projection& p);
  int levels() const { return static_cast<int>(levels_.size()); }  // including level 0

  struct Level {
    Projection projection;
    SourceTaps taps;  // refers to projection: levels never move
    Image image;        // empty at level 0 (the source itself)
    std::unique_ptr<std::once_flag[]> bands;  // one per kBand rows of image
  };
  const Level& level(int k) const { return *levels_[static_cast<size_t>(k)]; }
  const Image& image(int k) const { return k == 0 ? src_ : level(k).image; }
  // Builds (once; any thread) the rows of level k that frame rows [y0, y1) fall in, with the
  // rows of the levels before it that they need. Only those are defined afterwards.
  void build_rows(int k, int64_t y0, int64_t y1) const;

 private:
  static constexpr int64_t kBand = 16;  // rows built together
  const Image& src_;
  std::vector<std::unique_ptr<Level>> levels_;
};

}  // namespace panoproj
