#include "engine/tile_sampling.hpp"

#include <algorithm>

#include "sampling/dual_blend.hpp"
#include "sampling/reference_sampler.hpp"
#include "simd/geometry.hpp"

namespace panoproj {

SimdSource simd_source(const Image& src, const SourceTaps& taps) {
  const SamplingFacts& f = taps.facts();
  int64_t cw = 0, ch = 0;
  const Cubemap* c = f.cube;
  if (c && c->uniform()) cw = ch = c->face_size();
  if (f.dual) cw = f.dual->cell_width(), ch = f.dual->cell_height();
  const int64_t x0 = std::max(src.origin_x(), taps.col0()),
                y0 = std::max(src.origin_y(), taps.row0());
  const int64_t x1 = std::max(x0, std::min(src.origin_x() + src.width(), taps.col1()));
  const int64_t y1 = std::max(y0, std::min(src.origin_y() + src.height(), taps.row1()));
  const auto row = static_cast<int64_t>(src.row_bytes());
  const unsigned char* base = src.data() + (y0 - src.origin_y()) * row +
                              (x0 - src.origin_x()) * static_cast<int64_t>(src.pixel_bytes());
  SimdSource s{base, row, src.channels(), src.alpha_channel(), src.type(), x0, y0, x1, y1, cw, ch};
  if (c && !c->uniform()) s.cells_x = &c->x_axis(), s.cells_y = &c->y_axis();
  if (f.max)
    s.cells_x = &f.max->lens(0).x_axis(),
    s.cells_y = &f.max->lens(0).y_axis();  // (the lenses' one grid)
  return s;
}

std::vector<LensSource> lens_sources(const SamplingFacts& f, const Eigen::Matrix3d& rotation) {
  if (f.max) return {{f.max->lens(0), rotation}, {f.max->lens(1), rotation}};
  const DualFisheye& d = *f.dual;
  return {{d.lens(0), d.rotation(0).transpose() * rotation}, {d.lens(1), d.rotation(1).transpose() * rotation}};
}

TileSampling::TileSampling(const Image& src, const Projection& source,
                           const std::vector<LensSource>& lenses, const Eigen::Matrix3d& rotation,
                           Interp interp, bool simd, const Siting& siting, Size target)
    : src_(src),
      source_(source),
      lenses_(lenses),
      rotation_(rotation),
      interp_(interp),
      simd_(simd),
      siting_(siting),
      target_(target),
      taps_(source),
      simd_src_(simd_source(src, taps_)) {}

void widen_to_positions(const Projection& sp, const Eigen::Matrix3d& r, const Projection& t,
                        const PixelRect& rect, const TileMap* tm, bool simd, TileMap& scratch,
                        std::array<double, 4>& b, const Siting& siting) {
  SimdGeometry g;
  if (!tm && simd && simd_geometry_for(sp, t, r, rect, g, siting))
    return simd_tile_bounds(g, rect, b);
  if (!tm) map_tile(sp, t, r, rect, scratch, false, siting), tm = &scratch;
  for (size_t i = 0; i < tm->ok.size(); ++i)
    if (tm->ok[i])
      b = {std::min(b[0], tm->xs[i]), std::min(b[1], tm->ys[i]), std::max(b[2], tm->xs[i]), std::max(b[3], tm->ys[i])};
}

bool TileSampling::fused(const Projection& sp, const Eigen::Matrix3d& r, const Projection& t,
                         const PixelRect& rect, SimdGeometry& g) const {
  return simd_ && simd_geometry_for(sp, t, r, rect, g, siting_for(t)) && exact_for(interp_, g);
}

void TileSampling::resolve_misses(const Image& im, const SourceTaps& taps, const PixelRect& r,
                                  const SimdMisses& m, unsigned char* out, int64_t stride,
                                  TileScratch& wk, const FootprintField* fp) const {
  const uint8_t one = 1;
  const auto pb = static_cast<int64_t>(im.pixel_bytes());
  for (size_t q = 0; q < m.index.size(); ++q) {
    const int64_t i = m.index[q] % r.width(), j = m.index[q] / r.width();
    unsigned char* o = out + j * stride + i * pb;
    if (!fp) {
      sample_reference(im, taps, interp_, &m.xs[q], &m.ys[q], &one, 1, o);
      continue;
    }
    float ex, ey;
    fp->at(i, j, ex, ey);
    sample_footprint_reference(im, taps, &m.xs[q], &m.ys[q], &ex, &ey, &one, 1, o);
  }
  wk.stats.simd_misses += static_cast<int64_t>(m.index.size());
}

void TileSampling::map(const Image& im, const SourceTaps& taps, const SimdSource& ss, const TileMap& m,
                       unsigned char* out, int64_t stride, TileScratch& wk, const FootprintField* fp) const {
  if (!simd_) {
    wk.ex.resize(static_cast<size_t>(m.rect.width())),
        wk.ey.resize(static_cast<size_t>(m.rect.width()));
    for (int64_t j = 0; j < m.rect.height(); ++j) {
      const size_t k = static_cast<size_t>(j * m.rect.width());
      if (!fp) {
        sample_reference(im, taps, interp_, m.xs.data() + k, m.ys.data() + k, m.ok.data() + k,
                         m.rect.width(), out + j * stride);
        continue;
      }
      for (int64_t i = 0; i < m.rect.width(); ++i)
        fp->at(i, j, wk.ex[static_cast<size_t>(i)], wk.ey[static_cast<size_t>(i)]);
      sample_footprint_reference(im, taps, m.xs.data() + k, m.ys.data() + k, wk.ex.data(),
                                 wk.ey.data(), m.ok.data() + k, m.rect.width(), out + j * stride);
    }
    return;
  }
  wk.misses.clear();
  simd_sample(ss, interp_, m, out, stride, wk.misses, fp);
  resolve_misses(im, taps, m.rect, wk.misses, out, stride, wk, fp);
}

void TileSampling::from(const Projection& sp, const Eigen::Matrix3d& r, const Projection& t,
                        const PixelRect& rect, const KeptTile& kept, unsigned char* out,
                        int64_t stride, TileScratch& wk, const FootprintField* fp) const {
  PlannedTaps* const planned = kept.taps[0];
  if (planned && planned->ready()) {  // the geometry and planning of an earlier run
    wk.stats.fused_tiles++, wk.stats.replayed_tiles++;
    simd_replay(*planned, rect, simd_src_, interp_, fp, out, stride);
    return resolve_misses(src_, taps_, rect, planned->misses, out, stride, wk, fp);
  }
  const TileMap* tm = kept.map();
  SimdGeometry g;
  const bool in_registers = !tm && fused(sp, r, t, rect, g);
  if (!tm && !in_registers)
    map_tile(sp, t, r, rect, wk.map, interp_ == Interp::Nearest, siting_for(t)), tm = &wk.map;
  if (tm) wk.stats.interpolated_cells += tm->interpolated_cells, wk.stats.exact_cells += tm->exact_cells;
  wk.stats.fused_tiles += in_registers;
  if (!in_registers) return map(src_, taps_, simd_src_, *tm, out, stride, wk, fp);
  wk.misses.clear();
  PlannedTaps* const record = planned && planned->claim() ? planned : nullptr;
  if (record)
    record->allocate(rect.width() * rect.height(), keeps_compact_taps(simd_src_, interp_, fp));
  simd_convert(g, rect, simd_src_, interp_, out, stride, wk.misses, fp, record);
  resolve_misses(src_, taps_, rect, wk.misses, out, stride, wk, fp);
  if (!record) return;
  if (static_cast<double>(wk.misses.index.size()) >
      PlannedTaps::kMostMisses * static_cast<double>(rect.width() * rect.height())) {
    record->release();
    return record->decline();
  }
  record->misses = wk.misses;
  record->publish();
}

void TileSampling::rect(const Projection& t, const PixelRect& rect, const KeptTile& kept,
                        unsigned char* out, int64_t stride, TileScratch& wk,
                        const FootprintField* fp) const {
  if (lenses_.empty()) return from(source_, rotation_, t, rect, kept, out, stride, wk, fp);
  KeptBlend* const b = kept.blend;
  const bool known = b && b->ready();
  const SamplingFacts& f = taps_.facts();
  const int side = known   ? b->side
                   : f.max ? dual_weights(*f.max, t, rotation_, rect, wk.weights)
                           : dual_weights(*f.dual, t, rotation_, rect, wk.weights);
  if (!known && b && b->claim()) {
    b->side = side;
    if (side < 0) b->weights = wk.weights;
    b->publish();
  }
  if (side >= 0) {
    const LensSource& l = lenses_[static_cast<size_t>(side)];
    return from(l.lens, l.rotation, t, rect, kept.part(side), out, stride, wk, fp);
  }
  const auto pb = static_cast<int64_t>(src_.pixel_bytes());
  wk.other.resize(static_cast<size_t>(rect.width() * rect.height() * pb));
  from(lenses_[0].lens, lenses_[0].rotation, t, rect, kept.part(0), out, stride, wk, fp);
  from(lenses_[1].lens, lenses_[1].rotation, t, rect, kept.part(1), wk.other.data(),
       rect.width() * pb, wk, fp);
  blend_lenses(known ? b->weights.data() : wk.weights.data(), rect, src_.type(), src_.channels(),
               src_.alpha_channel(), out, stride, wk.other.data(), rect.width() * pb);
}

}  // namespace panoproj
