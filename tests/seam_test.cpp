// Sources whose frame holds a whole turn of longitude have no seam: every case-table row whose
// columns are longitudes and rows latitudes (a normal cylindrical frame), found by its rays, not
// by its type. A view across the seam equals the view of the same source rolled by half a turn
// (the seam then in the middle), within 1 level, for every kernel, antialiasing and engine; and
// where the outline sits at fractional pixels inside a keep-aspect frame, a view across the seam
// errs against the analytic truth no more than a view of the frame's middle does.
#include <cstring>

#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/rotation.hpp"
#include "panoproj/spec.hpp"
#include "projections/module.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

using test::get;

double lon_of(const Projection& p, double x, double y) {
  Ray d;
  return to_ray(p, x, y, d) ? longitude(d) : NAN;
}
double lat_of(const Projection& p, double x, double y) {
  Ray d;
  return to_ray(p, x, y, d) ? latitude(d) : NAN;
}

// The columns [c0, c1) that hold a whole turn on a normal cylindrical frame, where they are whole
// pixels; nullopt otherwise.
struct Turn {
  int64_t c0, c1;
  double seam_lon;  // the longitude at the seam (radians)
};
std::optional<Turn> whole_turn(const Projection& p) {
  const Size s = size_of(p);
  if (s.width < 16 || s.height < 8) return std::nullopt;
  // The outline's extent along the middle column, then its columns along the middle row.
  const double xm = 0.5 * static_cast<double>(s.width);
  int64_t r0 = 0, r1 = s.height;
  while (r0 < s.height && std::isnan(lat_of(p, xm, static_cast<double>(r0) + 0.5))) ++r0;
  while (r1 > r0 && std::isnan(lat_of(p, xm, static_cast<double>(r1) - 0.5))) --r1;
  const double ym = 0.5 * static_cast<double>(r0 + r1);
  int64_t c0 = 0, c1 = s.width;
  while (c0 < s.width && std::isnan(lon_of(p, static_cast<double>(c0) + 0.5, ym))) ++c0;
  while (c1 > c0 && std::isnan(lon_of(p, static_cast<double>(c1) - 0.5, ym))) --c1;
  if (c1 - c0 < 16 || r1 - r0 < 8) return std::nullopt;
  // Rows of one latitude, columns of one longitude, longitude linear in x (every ray there).
  const double step = kTwoPi / static_cast<double>(c1 - c0),
               l0 = lon_of(p, static_cast<double>(c0) + 0.5, ym);
  for (double fy : {0.05, 0.3, 0.5, 0.7, 0.95}) {
    const double y = static_cast<double>(r0) + fy * static_cast<double>(r1 - r0);
    const double lat = lat_of(p, static_cast<double>(c0) + 0.5, y);
    for (int64_t x = c0; x < c1; x += std::max<int64_t>(1, (c1 - c0) / 32)) {
      const double lon = lon_of(p, static_cast<double>(x) + 0.5, y),
                   expect = l0 + step * static_cast<double>(x - c0);
      if (!(std::fabs(lat_of(p, static_cast<double>(x) + 0.5, y) - lat) < 1e-9) ||
          !(std::fabs(std::remainder(lon - expect, kTwoPi)) < 1e-6 * step))
        return std::nullopt;
    }
  }
  // The last column's centre is one step short of a turn from the first's (whole pixels).
  const double l1 = lon_of(p, static_cast<double>(c1) - 0.5, ym);
  if (!(std::fabs(std::remainder(l1 - l0 + step, kTwoPi)) < 1e-6 * step)) return std::nullopt;
  return Turn{c0, c1, l0 - 0.5 * step};
}

// The rows of the case tables that hold a whole turn: each at its widest size that does in whole
// pixels, halved while even down to 2048 px wide (taller frames tried where the outline
// sits at fractional columns).
struct Wrapping {
  std::string spec;
  Projection p;
  Turn turn;
};
std::vector<Wrapping> wrapping_rows() {
  std::vector<Wrapping> rows;
  for (const ProjectionCase& row : projection_cases()) {
    const ProjectionSpec spec = parse_spec(row.spec);
    std::optional<Wrapping> found;
    for (Size s : row.sizes) {
      while (s.width % 2 == 0 && s.height % 2 == 0 && s.width > 2048)
        s = {s.width / 2, s.height / 2};
      if (s.width > 2048 || s.height > 4096) continue;
      std::optional<Turn> t;
      std::optional<Projection> p;
      for (int taller = 0; taller < 3 && !t; ++taller, s = {s.width, 2 * s.height}) {
        try {
          p = make_projection(spec, s);
        } catch (const Error&) {
          break;  // a frame this form does not take
        }
        t = whole_turn(*p);
      }
      if (!t || (t->c1 - t->c0) % 2) continue;
      if (!found || size_of(found->p).width < size_of(*p).width) found = Wrapping{row.spec, *p, *t};
    }
    if (found) rows.push_back(*found);
  }
  return rows;
}

// Uniform noise, and the same rolled by half a turn inside its columns.
Image noise(Size s, uint32_t seed) {
  Image im(s, 3, PixelType::U8, -1);
  std::mt19937 rng(seed);
  for (size_t i = 0; i < im.byte_size(); ++i)
    im.data()[i] = static_cast<unsigned char>(rng() & 255);
  return im;
}
Image rolled(const Image& im, const Turn& t) {
  Image out = im;
  const int64_t half = (t.c1 - t.c0) / 2;
  for (int64_t y = 0; y < im.height(); ++y)
    for (int64_t x = t.c0; x < t.c1; ++x)
      std::memcpy(const_cast<unsigned char*>(out.at(t.c0 + (x - t.c0 + half) % (t.c1 - t.c0), y)),
                  im.at(x, y), 3);
  return out;
}

int worst_level(const Image& a, const Image& b) {
  int worst = 0;
  for (size_t i = 0; i < a.byte_size(); ++i)
    worst = std::max(worst, std::abs(int(a.data()[i]) - int(b.data()[i])));
  return worst;
}

TEST(Seam, EveryWrappingCaseRowEqualsItsRolledSource) {
  const std::vector<Wrapping> rows = wrapping_rows();
  // The forms known to hold a turn must be among those found (the finder is not the code tested).
  for (const char* name :
       {"equirect", "cylindrical", "mercator", "miller", "cylindrical-equal-area"})
    EXPECT_TRUE(std::any_of(rows.begin(), rows.end(), [&](const Wrapping& w) {
      return w.spec.rfind(name, 0) == 0;
    })) << name;
  const Interp kernels[] = {Interp::Nearest,  Interp::Bilinear,      Interp::Bicubic,
                            Interp::Lanczos3, Interp::BicubicDering, Interp::Lanczos3Dering};
  struct Run {
    Engine engine;
    Antialias aa;
  };
  std::vector<Run> runs{{Engine::Reference, {}}};
  for (Engine e : {Engine::Simd, Engine::Scalar})
    for (const char* a : {"off", "auto", "mip", "3"}) runs.push_back({e, parse_antialias(a)});
  // Straddling: the odd-width view's middle column on the seam, shrinking a 2048-px source about
  // 4.6x; magnifying: 255 px over 10 degrees, 4.5x (512 px over 20 degrees also passes, at four
  // times the time). (Wider views shrinking more also differ by the interpolated maps' error,
  // which grows with the cells' angle: up to 8 levels of raw noise on an equirect at 41 px over 90
  // degrees, interpolated on one side of the seam, exact on the other.)
  const struct {
    const char* spec;
    Size size;
  } views[] = {{"pinhole:hfov=20", {25, 25}}, {"pinhole:hfov=10", {255, 255}}};
  int n = 0;
  for (const Wrapping& w : rows) {
    const double seam = rad2deg(w.turn.seam_lon);
    for (const auto& v : views) {
      const Image src = noise(size_of(w.p), 11), roll = rolled(src, w.turn);
      const Projection view = make_projection(parse_spec(v.spec), v.size);
      // At yaw = the seam's longitude the view looks at the seam; the rolled source holds it half
      // a turn away. (A quarter pixel off it, so that no sample lies on a pixel edge, where the
      // two would pick their nearest pixel by rounding.)
      const double yaw = seam + 0.25 * 360.0 / static_cast<double>(w.turn.c1 - w.turn.c0);
      const Eigen::Matrix3d across = rotation_from_ypr(yaw, 0, 0),
                            middle = rotation_from_ypr(yaw + 180, 0, 0);
      for (Interp k : kernels)
        for (const Run& r : runs) {
          // (nearest never averages: antialiasing is refused with it, as in every front end)
          if (k == Interp::Nearest && r.aa.mode != Antialias::Mode::Off) continue;
          const Image a =
              test::converter(w.p, view, across, k, r.engine, 2, Keep::Nothing, r.aa).run(src);
          const Image b =
              test::converter(w.p, view, middle, k, r.engine, 2, Keep::Nothing, r.aa).run(roll);
          EXPECT_LE(worst_level(a, b), 1)
              << w.spec << " " << size_text(size_of(w.p)) << " -> " << v.spec << " " << name_of(k)
              << " " << name_of(r.engine) << " antialias " << name_of(r.aa);
          ++n;
        }
    }
  }
  std::printf("[seam] %zu wrapping rows, %d comparisons\n", rows.size(), n);
}

// The outline at fractional columns or pole rows inside a keep-aspect frame: no rolled source
// exists, so against the truth. A wrapped tap between pixel centres is read linearly, so a bicubic
// view across the seam errs no more than a bilinear view of the frame's middle (with the taps
// clamped instead: 0.2 to 0.5, the letterbox read).
TEST(Seam, FractionalOutlinesWrapAgainstTheTruth) {
  const test::Scene scene = test::band_limited_scene(0.05, 1024);
  const Projection view = make_projection(parse_spec("pinhole:hfov=40"), {121, 121});
  for (const char* spec : {"miller", "cylindrical-equal-area:lat_ts=45", "cylindrical-equal-area",
                           "mercator:lat_max=80"}) {
    const Projection p = make_projection(parse_spec(spec), {1024, 512});
    const SamplingFacts f = sampling_facts(p);
    const Image src = test::render(p, scene, PixelType::F32);
    auto error = [&](double yaw, double pitch, Engine e, Interp k) {
      const Eigen::Matrix3d r = rotation_from_ypr(yaw, pitch, 0);
      const Image out = test::converter(p, view, r, k, e, 2).run(src);
      double worst = 0, rgb[3];
      for (int64_t y = 0; y < 121; ++y)
        for (int64_t x = 0; x < 121; ++x) {
          Ray d;
          if (!to_ray(view, x + 0.5, y + 0.5, d)) continue;
          double sx, sy;
          if (!to_pixel(p, r * d, sx, sy)) continue;
          scene(r * d, rgb);
          for (int ch = 0; ch < 3; ++ch)
            worst = std::max(worst, std::fabs(get(out, x, y, ch) - rgb[ch]));
        }
      return worst;
    };
    for (Engine e : {Engine::Simd, Engine::Reference}) {
      const double middle = error(0, 0, e, Interp::Bilinear),
                   seam = error(180, 0, e, Interp::Bicubic);
      std::printf(
          "[seam] %-36s box x %.3f..%.3f y %.3f..%.3f  %s: bilinear middle %.2e, bicubic seam "
          "%.2e\n",
          spec, f.x0, f.x1, f.y0, f.y1, name_of(e), middle, seam);
      EXPECT_LT(seam, middle) << spec << " " << name_of(e);
    }
  }
}

// Miller's pole line (lat_max=90; its rows keep their resolution up to the pole, unlike the
// equal-area map's, which has almost none there): a view across the pole errs no more than one
// beside it that stays inside the frame, where the pole is a row edge; where it lies between rows,
// the mirrored taps are read linearly, so no more than a bilinear view beside it.
TEST(Seam, MillerContinuesOverItsPole) {
  const test::Scene scene = test::band_limited_scene(0.02, 1024);
  const Projection view = make_projection(parse_spec("pinhole:hfov=30"), {121, 121});
  for (const Size size : {Size{1024, 512}, Size{800, 800}}) {
    const Projection p = make_projection(parse_spec("miller"), size);
    const SamplingFacts f = sampling_facts(p);
    ASSERT_TRUE(f.north_pole && f.south_pole);
    const bool on_edge = f.y0 == std::floor(f.y0);
    const Image src = test::render(p, scene, PixelType::F32);
    auto error = [&](double yaw, double pitch, Interp k) {
      const Eigen::Matrix3d r = rotation_from_ypr(yaw, pitch, 0);
      const Image out = test::converter(p, view, r, k, Engine::Simd, 2).run(src);
      double worst = 0, rgb[3];
      for (int64_t y = 0; y < 121; ++y)
        for (int64_t x = 0; x < 121; ++x) {
          Ray d;
          double sx, sy;
          if (!to_ray(view, x + 0.5, y + 0.5, d) || !to_pixel(p, r * d, sx, sy)) continue;
          scene(r * d, rgb);
          for (int ch = 0; ch < 3; ++ch)
            worst = std::max(worst, std::fabs(get(out, x, y, ch) - rgb[ch]));
        }
      return worst;
    };
    const double beside =
        on_edge ? 2 * error(30, 60, Interp::Bicubic) : error(30, 60, Interp::Bilinear);
    const double north = error(30, 90, Interp::Bicubic), south = error(30, -90, Interp::Bicubic);
    std::printf(
        "[seam] miller %s, pole rows %.3f, %.3f: bound %.2e, north pole %.2e, south pole %.2e\n",
        size_text(size).c_str(), f.y0, f.y1, beside, north, south);
    EXPECT_LT(north, beside);
    EXPECT_LT(south, beside);
  }
}

}  // namespace
}  // namespace panoproj
