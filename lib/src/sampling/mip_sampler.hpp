#pragma once
// Antialias's mip for one output tile: the footprint rho of each pixel from its tile map,
// then the map scaled to each mip level in use, sampled there by the engine's own sampler, and
// the levels blended. Internal.
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/tile_map.hpp"
#include "sampling/pyramid.hpp"

namespace panoproj {

struct MipScratch {
  std::vector<float> rho;       // per pixel: the blend f
  std::vector<int8_t> level;    // per pixel: the lower level
  std::vector<float> acc;       // per pixel and channel, premultiplied where there is alpha
  TileMap level_map;            // the positions of one level
  std::vector<unsigned char> samples;  // one level's samples, the tile's layout
};

// Samples map tm (level-k positions, ok where the pixel uses level k) into out (rows of stride
// bytes), as the engine samples level 0.
using LevelSampler = std::function<void(int k, const TileMap& tm, unsigned char* out, int64_t stride)>;

// Writes the tile's pixels into out. wrap_width: the source frame's width where x wraps (a full
// circle of longitude), else 0.
void sample_mip_tile(const Pyramid& pyramid, const TileMap& tm, double wrap_width, const LevelSampler& sample,
                     unsigned char* out, int64_t out_stride, MipScratch& scratch);

}  // namespace panoproj
