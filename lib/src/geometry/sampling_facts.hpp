#pragma once
// What sampling needs to know of a source projection, declared by its module
// (projections/module.hpp): which pixels hold the image, where taps past them read from, and
// whether its taps cross into other cells. The engine and the samplers ask these facts; none of
// them looks at the projection's type.
#include "panoproj/projection.hpp"

namespace panoproj {

struct SamplingFacts {
  // The pixel positions that hold the image, x0 <= x < x1 and y0 <= y < y1: the frame, or a
  // cylindrical map's outline inside a keep-aspect frame (fractional there). Taps outside it
  // follow the rules below, else are clamped into it.
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  // [x0, x1) holds one whole turn of longitude, linear in x: a tap past one side reads the other.
  bool wraps_x = false;
  // With wraps_x: y0 (north) or y1 (south) is the pole, a line of the frame; a tap past it
  // continues on the far side, its row mirrored about that line, half a turn away in x.
  bool north_pole = false, south_pole = false;
  // Cells whose taps do not stop at their edges: a cube's faces (a tap past a face reads the
  // neighbouring face), a dual fisheye's lenses (a tap stays in the sample's lens, and the blend
  // reads both) or a GoPro MAX's (a tap past a cell reads the neighbouring face in the sample's
  // lens, and the blend reads both). Each makes the source read whole.
  const Cubemap* cube = nullptr;
  const DualFisheye* dual = nullptr;
  const GoProMax* max = nullptr;
  // Every row holds a whole turn at every latitude (an equirect): footprints count x steps at
  // cos(latitude) (footprint_kernel.cpp).
  bool rows_hold_turn = false;

  bool has_cells() const { return cube != nullptr || lensed(); }
  // Two lenses, each sampled alone and blended where both see a ray (with a feather), else cut.
  bool lensed() const { return dual != nullptr || max != nullptr; }
  double lens_feather() const { return dual ? dual->feather() : max ? max->feather() : 0.0; }
};

// The frame as the box, no other rule: what a module without facts of its own has.
SamplingFacts framed_facts(const Projection& p);

// The facts of p's module (they may point into p: keep p alive and in place).
SamplingFacts sampling_facts(const Projection& p);

}  // namespace panoproj
