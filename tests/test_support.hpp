#pragma once
// Helpers shared by the tests: analytic scenes (functions of ray direction) rendered directly
// into any projection, PSNR, area downsampling, pixel access.
#include <algorithm>
#include <Eigen/Geometry>
#include <Imath/half.h>

#include <gtest/gtest.h>

#include <stdlib.h>  // mkdtemp

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "panoproj/convert.hpp"
#include "panoproj/image.hpp"
#include "panoproj/projection.hpp"

namespace panoproj::test {

// What a shell command prints on stdout (the test oracles: ffmpeg, ffprobe, exiftool).
inline std::string shell(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  pclose(p);
  return out;
}

// A Converter from its parts, as the engine tests name them (antialiasing off unless given).
inline Converter converter(Projection source, Projection target, const Eigen::Matrix3d& rotation,
                           Interp interp, Engine engine, int threads, Keep keep = Keep::Nothing,
                           Antialias antialias = {}, EdgeFill edges = {}) {
  ConvertOptions o;
  o.interp = interp, o.engine = engine, o.threads = threads, o.antialias = antialias,
  o.edges = edges;
  return Converter(ConversionGeometry{std::move(source), std::move(target), rotation}, o, keep);
}

inline std::string source_dir() { return PANOPROJ_SOURCE_DIR; }

// A one-off conversion (a Converter without kept maps or antialiasing).
inline Image fast_remap(const Image& src, const Projection& sp, const Projection& dp, const Eigen::Matrix3d& rotation,
                        Interp interp, Engine engine, int threads, EngineStats* stats = nullptr) {
  return converter(sp, dp, rotation, interp, engine, threads).run(src, stats);
}
inline std::string samples_dir() { return source_dir() + "/samples/images"; }

// Scene value in [0, 1] for a unit ray, per channel.
using Scene = std::function<void(const Ray&, double* rgb)>;

// Sum of plane waves cos(omega (k . d) + phase) on the sphere. Along any great circle a wave has
// at most omega radians of phase per radian, so omega_max = 2 pi f W / (2 pi) = f W limits it to
// f cycles per pixel of a W-wide equirect at the equator.
inline Scene band_limited_scene(double cycles_per_px, int64_t equirect_width, uint32_t seed = 7) {
  struct Wave {
    Ray k;
    double omega, phase, amp;
    int channel;
  };
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> u01;
  const double omega_max = cycles_per_px * static_cast<double>(equirect_width);
  std::vector<Wave> waves;
  for (int i = 0; i < 36; ++i) {
    Ray k(n01(rng), n01(rng), n01(rng));
    k.normalize();
    waves.push_back({k, omega_max * (0.05 + 0.95 * u01(rng)), kTwoPi * u01(rng), 0.4 / 12.0, i % 3});
  }
  return [waves](const Ray& d, double* rgb) {
    rgb[0] = rgb[1] = rgb[2] = 0.5;
    for (const auto& w : waves) rgb[w.channel] += w.amp * std::cos(w.omega * w.k.dot(d) + w.phase);
  };
}

// A smooth scene: linear in the ray components (band-limited to the lowest frequencies).
inline Scene smooth_scene() {
  return [](const Ray& d, double* rgb) {
    rgb[0] = 0.5 + 0.4 * d.x();
    rgb[1] = 0.5 + 0.4 * d.y();
    rgb[2] = 0.5 + 0.4 * d.z();
  };
}

template <class T>
inline void put(unsigned char* p, double v, PixelType type) {
  if (type == PixelType::U8 || type == PixelType::U16) {
    const double unit = unit_of(type);
    const T t = static_cast<T>(std::fmin(unit, std::fmax(0.0, std::nearbyint(v * unit))));
    std::memcpy(p, &t, sizeof(T));
  } else {
    const T t = static_cast<T>(static_cast<float>(v));
    std::memcpy(p, &t, sizeof(T));
  }
}

inline double get(const Image& im, int64_t x, int64_t y, int c) {
  const unsigned char* p = im.pixel(x, y) + c * bytes_of(im.type());
  switch (im.type()) {
    case PixelType::U8: return *p;
    case PixelType::U16: { uint16_t t; std::memcpy(&t, p, 2); return t; }
    case PixelType::F16: { Imath::half t; std::memcpy(&t, p, 2); return float(t); }
    case PixelType::F32: { float t; std::memcpy(&t, p, 4); return t; }
  }
  return 0;
}

inline void set(Image& im, int64_t x, int64_t y, int c, double v_unit) {
  unsigned char* p = im.pixel(x, y) + c * bytes_of(im.type());
  switch (im.type()) {
    case PixelType::U8: put<uint8_t>(p, v_unit, im.type()); break;
    case PixelType::U16: put<uint16_t>(p, v_unit, im.type()); break;
    case PixelType::F16: put<Imath::half>(p, v_unit, im.type()); break;
    case PixelType::F32: put<float>(p, v_unit, im.type()); break;
  }
}

// Renders the scene at each pixel centre (3 channels, plus alpha = 1 where the pixel has a ray
// when with_alpha). Pixels without a ray are 0.
inline Image render(const Projection& proj, const Scene& scene, PixelType type,
                    bool with_alpha = false) {
  const Size s = size_of(proj);
  Image im(s, with_alpha ? 4 : 3, type, with_alpha ? 3 : -1);
  double rgb[3];
  for (int64_t y = 0; y < s.height; ++y)
    for (int64_t x = 0; x < s.width; ++x) {
      Ray d;
      if (!to_ray(proj, x + 0.5, y + 0.5, d)) continue;
      scene(d, rgb);
      for (int c = 0; c < 3; ++c) set(im, x, y, c, rgb[c]);
      if (with_alpha) set(im, x, y, 3, 1.0);
    }
  return im;
}

// PSNR over channels [0, 3) of the pixels where mask (if given) is true; peak = unit of type.
inline double psnr(const Image& a, const Image& b,
                   const std::function<bool(int64_t, int64_t)>& mask = nullptr) {
  double se = 0;
  int64_t n = 0;
  const int nc = std::min(3, a.channels());
  for (int64_t y = 0; y < a.height(); ++y)
    for (int64_t x = 0; x < a.width(); ++x) {
      if (mask && !mask(x, y)) continue;
      for (int c = 0; c < nc; ++c) {
        const double d = get(a, x, y, c) - get(b, x, y, c);
        se += d * d;
        ++n;
      }
    }
  const double unit = unit_of(a.type());
  return se == 0 ? 999.0 : 10.0 * std::log10(unit * unit * n / se);
}

// Box-filter downsample by an integer factor, in float.
inline Image area_downsample(const Image& im, int factor) {
  Image out({im.width() / factor, im.height() / factor}, im.channels(), PixelType::F32);
  const double unit = unit_of(im.type());
  for (int64_t y = 0; y < out.height(); ++y)
    for (int64_t x = 0; x < out.width(); ++x)
      for (int c = 0; c < im.channels(); ++c) {
        double s = 0;
        for (int j = 0; j < factor; ++j)
          for (int i = 0; i < factor; ++i) s += get(im, x * factor + i, y * factor + j, c);
        set(out, x, y, c, s / (factor * factor) / unit);
      }
  return out;
}

// A fixture with a fresh folder per test (named after it), removed afterwards.
// A test image whose samples all differ (alpha, where there is one, alternates 0.25 / 0.75).
inline Image pattern(Size s, int nc, PixelType t, int alpha) {
  Image im(s, nc, t, alpha);
  for (int64_t y = 0; y < s.height; ++y)
    for (int64_t x = 0; x < s.width; ++x)
      for (int c = 0; c < nc; ++c)
        set(im, x, y, c, c == alpha ? 0.25 + 0.5 * ((x + y) % 2) : std::fmod(0.013 * x + 0.029 * y + 0.3 * c, 1.0));
  return im;
}

class TempDirTest : public ::testing::Test {
 protected:
  // A fresh folder per run (mkdtemp): runs of two checkouts at once must not share one.
  void SetUp() override {
    // (A parameterized test's name holds '/': no folder of that name exists.)
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::replace(name.begin(), name.end(), '/', '_');
    std::string dir = (std::filesystem::temp_directory_path() / ("panoproj_" + name + "_XXXXXX")).string();
    ASSERT_NE(::mkdtemp(dir.data()), nullptr) << dir;
    dir_ = dir;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

// A test name from a case's parts: its index (unique, in table order) and its text with every
// character GoogleTest does not allow in names made '_' ("fisheye:fov=200" -> "3_fisheye_fov_200").
inline std::string case_name(size_t index, const std::string& text) {
  std::string s = std::to_string(index) + "_" + text;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

// Angle between two rays, robust for tiny angles.
inline double angle(const Ray& a, const Ray& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// A tile map against the exact per-pixel map: the largest position error in source pixels, and
// the pixels whose validity differs. Where the positions differ by more than `tolerance`, the
// error is also measured as the angle between the two rays over the angle of one source pixel
// there (the larger of its two sides), and the smaller counts: at the seam, a pole row or a
// shared cube edge, far-apart positions can be (nearly) the same ray.
struct MapComparison {
  double worst = 0;
  int64_t differ = 0, valid = 0;
};
template <class TileMapT, class RectT>
void compare_with_exact(const Projection& sp, const Projection& dp, const Eigen::Matrix3d& r,
                        const RectT& rect, const TileMapT& tm, double tolerance, MapComparison& acc) {
  for (int64_t j = 0; j < rect.height(); ++j)
    for (int64_t i = 0; i < rect.width(); ++i) {
      const size_t k = static_cast<size_t>(j * rect.width() + i);
      Ray d;
      double sx = 0, sy = 0;
      const bool ok = to_ray(dp, rect.x0 + i + 0.5, rect.y0 + j + 0.5, d) && to_pixel(sp, r * d, sx, sy);
      if (ok != static_cast<bool>(tm.ok[k])) {
        ++acc.differ;
        continue;
      }
      if (!ok) continue;
      ++acc.valid;
      double err = std::hypot(tm.xs[k] - sx, tm.ys[k] - sy);
      Ray d2, d3, dx, dy;
      if (err > tolerance && to_ray(sp, tm.xs[k], tm.ys[k], d2) && to_ray(sp, sx, sy, d3)) {
        const double step_x = to_ray(sp, sx + 0.5, sy, dx) || to_ray(sp, sx - 0.5, sy, dx) ? 2 * angle(d3, dx) : 0;
        const double step_y = to_ray(sp, sx, sy + 0.5, dy) || to_ray(sp, sx, sy - 0.5, dy) ? 2 * angle(d3, dy) : 0;
        const double pixel = std::max(step_x, step_y);
        if (pixel > 0) err = std::min(err, angle(d2, d3) / pixel);
      }
      acc.worst = std::max(acc.worst, err);
    }
}

}  // namespace panoproj::test
