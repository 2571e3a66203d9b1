// The GoPro MAX module (module.hpp): the camera's two EAC strips held as one frame, its presets
// (chosen from the strips' size) and the parametric form, the two lenses blended across the seam.
#include <sstream>

#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {
namespace {
using namespace spec_support;

// A strip's shape: the centre face C (= the strip's height), the outer faces' width S, the band
// D both lenses see in an outer face; a strip is 2 S + C wide.
struct MaxStrip {
  int64_t face = 0, outer = 0, band = 0;
  int64_t width() const { return 2 * outer + face; }
};

struct MaxPreset {
  const char* name;
  MaxStrip strip;  // a face of 0: the strip's from the frame (outer = (W - H) / 2)
  bool by_size;    // chosen by preset=auto from the strips' size
};
// 5.6K and 3K: measured on real frames (docs/gopro_max.md); before firmware 1.5 the strips had no
// overlap (gopro/gpmf-parser#108); the MAX2's bands as reported (gmat/goproMax-ffmpeg-v5#5),
// unverified: no frames here.
constexpr MaxPreset kPresets[] = {
    {"max-5.6k", {1344, 1376, 64}, true},       {"max-3k", {736, 768, 32}, true},
    {"max-pre1.5-5.6k", {1344, 1344, 0}, true}, {"max-pre1.5-3k", {736, 736, 0}, true},
    {"max2-8bit", {0, 0, 64}, false},           {"max2-10bit", {0, 0, 96}, false}};

std::string preset_names() {
  std::string s = "auto";
  for (const MaxPreset& p : kPresets) s += std::string("|") + p.name;
  return s;
}

std::vector<ProjectionDef> catalog() {
  static const std::string presets = preset_names();
  return {{"gopro-max",
           "a GoPro MAX's two EAC strips (streams 0:0 and 0:5), the first above the second, "
           "blended across the lens seam",
           {choice("preset", "auto", presets.c_str(),
                   "the camera mode's strip layout; auto: the MAX preset of the strips' size "
                   "(max2-*: unverified)"),
            {"face", ParamType::Integer, "", 1, 1 << 28, false, false, "",
             "parametric: the centre face's width in pixels; default: the strip's height"},
            {"outer", ParamType::Integer, "", 1, 1 << 28, false, false, "",
             "parametric: an outer face's width in pixels; default: (strip width - face) / 2"},
            {"band", ParamType::Integer, "", 0, 1 << 28, false, false, "",
             "parametric: the band both lenses see around the seam, in an outer face's pixels"},
            number("feather", "", 0, 90, false, false,
                   "width of the blend across the band (deg of the outer faces' EAC angle); "
                   "default: the whole band; 0: a hard cut")}}};
}

bool parametric(const ProjectionSpec& s) {
  return s.given("face") || s.given("outer") || s.given("band");
}

void check(const ProjectionSpec& s) {
  if (parametric(s) && s.given("preset"))
    fail(s, "preset=" + s.choice("preset") +
                " and face/outer/band both given (give a preset or the parameters)");
  if (parametric(s) && !s.given("band"))
    fail(s, "face= or outer= without band= (give band=, 0 for strips without an overlap)");
}

// The strip a spec gives on a frame of `size` (two strips stacked); throws naming the mismatch.
MaxStrip strip_of(const ProjectionSpec& s, Size size) {
  if (size.height % 2 != 0) {
    std::ostringstream o;
    o << "a " << size.width << "x" << size.height
      << " frame is not two strips stacked (an odd height)";
    fail(s, o.str());
  }
  const int64_t W = size.width, H = size.height / 2;
  const auto derived = [&](int64_t band) {
    const int64_t face = s.given("face") ? static_cast<int64_t>(*s.number("face")) : H;
    const int64_t outer =
        s.given("outer") ? static_cast<int64_t>(*s.number("outer")) : (W - face) / 2;
    return MaxStrip{face, outer, band};
  };
  MaxStrip m;
  if (parametric(s)) {
    m = derived(static_cast<int64_t>(*s.number("band")));
  } else if (s.choice("preset") == "auto") {
    bool found = false;
    for (const MaxPreset& p : kPresets)
      if (p.by_size && p.strip.width() == W && p.strip.face == H) m = p.strip, found = true;
    if (!found) {
      std::ostringstream o;
      o << "strips of " << W << "x" << H
        << " match no preset (max-5.6k 4096x1344, max-3k 2272x736, max-pre1.5-5.6k 4032x1344, "
        << "max-pre1.5-3k 2208x736; give preset=max2-8bit|max2-10bit, or face=, outer= and band=)";
      fail(s, o.str());
    }
  } else {
    for (const MaxPreset& p : kPresets)
      if (s.choice("preset") == p.name) m = p.strip.face ? p.strip : derived(p.strip.band);
  }
  std::ostringstream o;
  o << "strips of " << W << "x" << H << " do not hold faces of face=" << m.face
    << ", outer=" << m.outer << ", band=" << m.band;
  if (m.face != H || m.width() != W)
    fail(s, o.str() + " (expected 2 outer + face = the width, face = the height)");
  if (m.outer % 2 != 0 || m.band % 2 != 0 || m.band >= m.outer || m.outer < 2)
    fail(s, o.str() + " (expected an even outer face, an even band narrower than it)");
  return m;
}

// The grid both lenses share: columns [0, S/2), [S/2, S), [S, S + C), [S + C, S + C + S/2),
// [S + C + S/2, W); rows the two strips. Each column's face centre and half-size (gopro_max.hpp).
std::array<CubeAxis, 2> grid_of(const MaxStrip& m) {
  CubeAxis ax, ay;
  const int64_t S = m.outer, C = m.face, D = m.band;
  ax.n = 5;
  ax.edge = {0, S / 2, S, S + C, S + C + S / 2, 2 * S + C, 0};
  const double so = 0.5 * static_cast<double>(S - D), sl = so,
               sr = 0.5 * static_cast<double>(S + D);
  const double x2 = static_cast<double>(S + C);
  ax.center = {sl, sr, static_cast<double>(S) + 0.5 * static_cast<double>(C), x2 + sl, x2 + sr, 0};
  ax.half = {so, so, 0.5 * static_cast<double>(C), so, so, 0};
  ay.n = 2;
  ay.edge = {0, C, 2 * C, 0, 0, 0, 0};
  ay.center = {0.5 * static_cast<double>(C), 1.5 * static_cast<double>(C), 0, 0, 0, 0};
  ay.half = {0.5 * static_cast<double>(C), 0.5 * static_cast<double>(C), 0, 0, 0, 0};
  return {ax, ay};
}

// The lenses' cells by face (front right back left up down): EAC's l f r / d b u, each outer
// face's half by the centre face (top row) or as turned (bottom: down's left half, up's right
// half face the front) the front lens's.
std::array<Cubemap, 2> lenses_of(const std::array<CubeAxis, 2>& g) {
  const FaceCell none{};
  const std::array<FaceCell, 6> front = {
      {{2, 0, 0}, {3, 0, 0}, none, {1, 0, 0}, {4, 1, 3}, {0, 1, 3}}};
  const std::array<FaceCell, 6> back = {
      {none, {4, 0, 0}, {2, 1, 1}, {0, 0, 0}, {3, 1, 3}, {1, 1, 3}}};
  return {Cubemap(g[0], g[1], front, true), Cubemap(g[0], g[1], back, true)};
}

Projection make(const ProjectionSpec& s, Size size) {
  const MaxStrip m = strip_of(s, size);
  const double beta =
      0.25 * kPi * static_cast<double>(m.band) / static_cast<double>(m.outer - m.band);
  const double feather = s.given("feather") ? rad(s, "feather") : 2 * beta;
  if (feather > 2 * beta * (1 + 1e-12)) {
    std::ostringstream o;
    o << "feather=" << *s.number("feather") << " is wider than the band of " << rad2deg(2 * beta)
      << " deg (band=" << m.band << " px of an outer face): give feather <= " << rad2deg(2 * beta);
    fail(s, o.str());
  }
  return GoProMax(lenses_of(grid_of(m)), beta, feather);
}

// The preset's frame (auto: the 5.6K's), or the parameters'; the field is the camera's.
Size size_for(const ProjectionSpec& s, double) {
  MaxStrip m = kPresets[0].strip;
  if (parametric(s)) {
    if (!s.given("face") || !s.given("outer"))
      fail(s, "as a target the parametric form needs face=, outer= and band=");
    m = {static_cast<int64_t>(*s.number("face")), static_cast<int64_t>(*s.number("outer")),
         static_cast<int64_t>(*s.number("band"))};
  } else {
    for (const MaxPreset& p : kPresets)
      if (s.choice("preset") == p.name) {
        if (!p.strip.face)
          fail(s, "preset=" + s.choice("preset") +
                      " takes its size from the strips: give a size as a target");
        m = p.strip;
      }
  }
  return framed_size(s, static_cast<double>(m.width()), static_cast<double>(2 * m.face));
}

Projection rescale(const Projection& p, Size, double sx, double sy) {
  const auto& q = std::get<GoProMax>(p);
  return GoProMax({q.lens(0).scaled(sx, sy), q.lens(1).scaled(sx, sy)}, q.beta(), q.feather());
}

std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> rows = {
      {"gopro-max", {{4096, 2688}, {2272, 1472}, {4032, 2688}}},
      {"gopro-max:feather=0", {{4096, 2688}}},
      {"gopro-max:preset=max2-10bit", {{5952, 3840}}},
      {"gopro-max:face=2,outer=4,band=2", {{10, 4}}},
      {"gopro-max:face=20000,outer=20480,band=960", {{60960, 40000}}}};
  for (auto& row : rows) row.bound_px = 1e-9;
  return rows;
}

}  // namespace

const ProjectionModule kGoProMaxModule{
    catalog, check, make, size_for, rescale, cases, always, [](const Projection& p) {
      SamplingFacts f = framed_facts(p);
      f.max = &std::get<GoProMax>(p);
      return f;
    }};

}  // namespace panoproj
