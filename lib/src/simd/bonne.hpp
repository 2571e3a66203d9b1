#pragma once
// Bonne's SIMD lanes (vector forms in bonne-inl.h): bonne.hpp's equations for |phi1| (a southern
// phi1 mirrors phi and Y), in the 1/rho form for small |phi1|.
#include <algorithm>

#include "panoproj/projections/bonne.hpp"
#include "simd/map_frame.hpp"

namespace panoproj::simd {

template <class T>
struct BonneShape {
  T abs_phi1, mirror, tan_phi1, cot_phi1;
  bool small_form;
};

template <class T>
void describe(const Bonne& m, BonneShape<T>& l) {
  l = {lane<T>(m.abs_phi1()), lane<T>(m.mirror()), lane<T>(m.tan_phi1()),
       lane<T>(m.cot_phi1()), m.small_form()};
}

// As a target, in double lanes only: phi = cot + phi1 - rho cancels digits of rho (up to ~3 +
// cot), beyond float rays' error budget.
template <class T>
struct BonneRays {
  MapPlane<T> plane;
  BonneShape<T> shape;
};

template <class T>
void describe(const Bonne& m, BonneRays<T>& l) {
  describe(m.frame(), m.lon0(), l.plane);
  describe(m, l.shape);
}

// As a source: float lanes are coarse near Werner's apex (rho < coarse_rho), where E = lambda
// cos phi / rho loses digits. (The frame in MapPixels.)
template <class T>
struct BonneSource {
  BonneShape<T> shape;
  T coarse_rho;
};

// Returns whether float lanes serve: the plane error as Aitoff's plus, in the rho form, one
// rounding at rho's magnitude in X = rho sin E and Y = cot phi1 - rho cos E (rho <= cot phi1 +
// phi1 + pi/2: 11.5 just above the small form's switch, 3.4 at phi1 = 45; the table's sweep in
// tests/simd_geometry_test.cpp found 1.5e-3 px at phi1 = 5.8, 4096 px, without it).
template <class T>
bool describe(const Bonne& m, BonneSource<T>& l) {
  describe(m, l.shape);
  l.coarse_rho = lane<T>(0.1);
  const double rho_max = m.small_form() ? 0.0 : m.cot_phi1() + m.abs_phi1() + kHalfPi;
  return kFloatTolerance - rounding(m.frame()) -
             pixels_per_unit(m.frame()) * (4 * kFloatRayError + rho_max * kHalfUlp) > 0;
}

}  // namespace panoproj::simd
