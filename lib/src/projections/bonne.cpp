// The Bonne module (module.hpp): the equal-area pseudoconic map (sinusoidal at phi1 = 0, Werner at
// 90 degrees), and its frame.
#include <algorithm>
#include <cmath>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {

Bonne::Bonne(Size size, double phi1, double lon0)
    : MapProjection(lon0), p1_(std::fabs(phi1)), sign_(phi1 < 0 ? -1.0 : 1.0),
      t_(std::tan(std::fabs(phi1))), cot_(0.0), small_(std::fabs(phi1) < kSmallPhi1) {
  if (!small_) cot_ = std::cos(p1_) / std::sin(p1_);
  // Bounding box: X peaks on the outline lambda = +-pi; Y is monotonic in |lambda| on each
  // parallel (|E| < pi), so its extremes lie on lambda = 0 or on the outline. Dense sampling
  // then golden-section refinement of each extreme.
  auto outline = [&](double phi, int which) {
    double X, Y;
    forward(kPi, phi, X, Y);
    return which == 0 ? X : (which == 1 ? Y : -Y);
  };
  double ext[3];
  for (int which = 0; which < 3; ++which) {
    constexpr int kSamples = 2048;
    int best = 0;
    double best_v = -HUGE_VAL;
    for (int i = 0; i <= kSamples; ++i) {
      const double v = outline(-kHalfPi + kPi * i / kSamples, which);
      if (v > best_v) best_v = v, best = i;
    }
    double a = -kHalfPi + kPi * std::max(0, best - 1) / kSamples;
    double b = -kHalfPi + kPi * std::min(kSamples, best + 1) / kSamples;
    const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 80; ++it) {
      const double c = b - gr * (b - a), d = a + gr * (b - a);
      if (outline(c, which) > outline(d, which)) b = d; else a = c;
    }
    ext[which] = std::max(best_v, outline(0.5 * (a + b), which));
  }
  // lambda = 0 reaches Y = +-pi/2 - phi1 (mirrored for a southern phi1).
  const double ymax = std::max(ext[1], sign_ > 0 ? kHalfPi - p1_ : p1_ + kHalfPi);
  const double ymin = std::min(-ext[2], sign_ > 0 ? -kHalfPi - p1_ : p1_ - kHalfPi);
  frame_ = {size, -ext[0], ext[0], ymin, ymax};
}

namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"bonne",
           "Bonne equal-area map (phi1 = 0: sinusoidal; 90: Werner)",
           {number("phi1", "45", -90, 90, false, false, "standard parallel (deg)"), lon0(),
            map_aspect(), map_hfov()}},
          {"sinusoidal",
           "sinusoidal equal-area map (Bonne with phi1 = 0)",
           {lon0(), map_aspect(), map_hfov()}}};
}

double phi1(const ProjectionSpec& s) { return s.name() == "sinusoidal" ? 0.0 : rad(s, "phi1"); }

Projection make(const ProjectionSpec& s, Size size) { return map_framed(s, Bonne(size, phi1(s), rad(s, "lon0"))); }

// Unit scale at the centre: the frame in plane units.
Size size_for(const ProjectionSpec& s, double density) {
  return map_size(s, Bonne({1000, 1000}, phi1(s), rad(s, "lon0")).frame(), density);
}

Projection rescale(const Projection& p, Size size, double, double) { return std::get<Bonne>(p).resized(size); }

// phi1 at 0 (sinusoidal), 1e-9, around the series switch (kSmallPhi1, 5.72958 degrees), both
// hemispheres, near and at the pole (Werner); the default; a turned central meridian.
std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> c;
  for (const char* p : {"0", "1e-9", "5.7", "5.72", "5.73", "5.8", "45", "-45", "89.99", "90", "-90"})
    c.push_back({std::string("bonne:phi1=") + p, {{512, 256}, {2048, 2048}, kPhotoFrame, kHugeFrame}});
  c.push_back({"bonne", {{2784, 2643}}});
  c.push_back({"bonne:phi1=-30,lon0=10", {{2048, 2048}}});
  c.push_back({"bonne:aspect=stretch", {{2048, 1024}}});
  c.push_back({"sinusoidal", {{512, 256}, {1000, 1000}, kPhotoFrame, kHugeFrame}, 1e-9});
  c.push_back({"sinusoidal:hfov=300", {{2048, 1024}}, 1e-9});
  return c;
}

}  // namespace

const ProjectionModule kBonneModule{catalog, nullptr, make,    size_for,         rescale,
                                    cases,   always,  nullptr, map_window<Bonne>};

}  // namespace panoproj
