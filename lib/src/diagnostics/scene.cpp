#include "panoproj/diagnostics/scene.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "panoproj/error.hpp"
#include "base/parallel.hpp"
#include "base/sample_io.hpp"

namespace panoproj {

Scene parse_scene(std::string_view name) {
  for (Scene s : {Scene::Waves, Scene::Chart, Scene::Gradient, Scene::Sun})
    if (name == name_of(s)) return s;
  throw Error("scene '" + std::string(name) + "' is unknown (expected waves, chart, gradient or sun)");
}

const char* name_of(Scene s) {
  switch (s) {
    case Scene::Waves: return "waves";
    case Scene::Chart: return "chart";
    case Scene::Gradient: return "gradient";
    case Scene::Sun: return "sun";
  }
  return "?";
}

std::array<double, 3> scene_radiance(Scene s, const Ray& d) {
  switch (s) {
    case Scene::Waves: {
      // Plane waves sin(2 pi k.d + phase): |k| <= 18 cycles per unit, a period of >= 1/18 in d.
      static const double k[3][3][3] = {{{6, 2, -3}, {-4, 11, 5}, {12, -7, 9}},
                                        {{-5, 7, 4}, {10, 3, -8}, {3, -12, 11}},
                                        {{8, -3, 6}, {-2, -9, 10}, {13, 6, -8}}};
      std::array<double, 3> v{};
      for (int c = 0; c < 3; ++c) {
        double a = 0.5;
        for (int w = 0; w < 3; ++w)
          a += (0.2 - 0.05 * w) * std::sin(2.0 * kPi * (k[c][w][0] * d.x() + k[c][w][1] * d.y() + k[c][w][2] * d.z()) + w + c);
        v[c] = a;
      }
      return v;
    }
    case Scene::Chart: {
      const double v = std::sin(72.0 * std::atan2(d.y(), d.x())) >= 0.0 ? 0.9 : 0.1;
      return {v, v, v};
    }
    case Scene::Gradient: return {0.5 * (1.0 + d.x()), 0.5 * (1.0 - d.y()), 0.5 * (1.0 + d.z())};
    case Scene::Sun: {
      static const Ray sun = ray_from_lonlat(40.0 * kPi / 180.0, 30.0 * kPi / 180.0);
      const double up = std::max(0.0, -d.y());
      const double sky = 0.05 + 0.95 * up * up;
      const double v = d.dot(sun) >= std::cos(0.5 * kPi / 180.0) ? 20000.0 : sky;
      return {v, v * (v > 1.0 ? 0.95 : 0.9), v * (v > 1.0 ? 0.85 : 1.0)};
    }
  }
  return {0, 0, 0};
}

Image render_scene(Scene s, const Projection& p, PixelType type, int supersample, int threads) {
  if (supersample < 1 || supersample > 64)
    throw Error("supersample " + std::to_string(supersample) + " is out of range (1 to 64 rays per axis)");
  const Size size = size_of(p);
  Image out(size, 3, type);
  const double unit = unit_of(type), step = 1.0 / supersample;
  parallel_rows(size.height, threads, [&](int64_t y0, int64_t y1) {
    with_sample_type(type, [&](auto tag) {
      using T = decltype(tag);
      Ray d;
      for (int64_t y = y0; y < y1; ++y) {
        unsigned char* row = out.row(y);
        for (int64_t x = 0; x < size.width; ++x) {
          if (!to_ray(p, static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, d)) continue;
          std::array<double, 3> sum{};
          int n = 0;
          for (int b = 0; b < supersample; ++b)
            for (int a = 0; a < supersample; ++a) {
              if (!to_ray(p, static_cast<double>(x) + (a + 0.5) * step, static_cast<double>(y) + (b + 0.5) * step, d)) continue;
              const auto v = scene_radiance(s, d.normalized());
              for (int c = 0; c < 3; ++c) sum[c] += v[c];
              ++n;
            }
          for (int c = 0; c < 3; ++c) store<T>(row + (3 * x + c) * sizeof(T), sum[c] / n * unit);
        }
      }
    });
  });
  return out;
}

}  // namespace panoproj
