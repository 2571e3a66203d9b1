// No size limit: a generated 40000x20000 uint8 RGB equirect (2.4 GB) converted to a 90-degree
// pinhole (4096x4096) and to a cubemap with 10000-px faces (6 x 10000^2, 1.8 GB), in memory.
// Memory stays source + output + per-thread tile buffers (no per-pixel tables): peak RSS is
// printed after each step. Spot checks compare 2000 output pixels with the exact reference
// sampling of the same positions. Needs ~4.5 GB. Usage: bench_big [--threads N]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>

#include "panoproj/engine.hpp"
#include "panoproj/rotation.hpp"

using namespace panoproj;

namespace {
double peak_gb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0 / 1024.0;
}
// A pattern cheap to generate and to check: a smooth function of the pixel position.
unsigned char pattern(int64_t x, int64_t y, int c) {
  return static_cast<unsigned char>((x / 37 + y / 23 + c * 85) & 0xff);
}
}  // namespace

int main(int argc, char** argv) {
  int threads = 0;
  if (argc == 3 && !std::strcmp(argv[1], "--threads")) threads = std::atoi(argv[2]);
  const Size big{40000, 20000};
  auto t0 = std::chrono::steady_clock::now();
  Image src(big, 3, PixelType::U8);
  for (int64_t y = 0; y < big.height; ++y) {
    unsigned char* row = src.row(y);
    for (int64_t x = 0; x < big.width; ++x)
      for (int c = 0; c < 3; ++c) row[3 * x + c] = pattern(x, y, c);
  }
  auto secs = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  std::printf("generated 40000x20000 RGB equirect (%.1f GB) in %.1f s; peak RSS %.2f GB\n",
              src.byte_size() / 1e9, secs(), peak_gb());
  const Projection e = make_projection(parse_spec("equirect"), big);
  struct Job {
    const char* spec;
    Size size;
    double yaw, pitch;
  };
  for (const Job& j : {Job{"pinhole:hfov=90", {4096, 4096}, 123, 35}, Job{"cubemap", {6 * 10000, 10000}, 0, 0}}) {
    const Projection dst = make_projection(parse_spec(j.spec), j.size);
    const Eigen::Matrix3d r = rotation_from_ypr(j.yaw, j.pitch, 0);
    t0 = std::chrono::steady_clock::now();
    EngineStats st;
    const Image out = fast_remap(src, e, dst, r, Interp::Bilinear, Engine::Simd, threads, &st);
    const double t = secs();
    // Spot check against nearest-free ground truth: bilinear of the pattern at the exact position.
    std::mt19937 rng(3);
    int bad = 0;
    for (int k = 0; k < 2000; ++k) {
      const int64_t x = rng() % j.size.width, y = rng() % j.size.height;
      Ray d;
      double sx, sy;
      if (!to_ray(dst, x + 0.5, y + 0.5, d) || !to_pixel(e, r * d, sx, sy)) continue;
      const double u = sx - 0.5, v = sy - 0.5;
      const int64_t x0 = static_cast<int64_t>(std::floor(u)), y0 = static_cast<int64_t>(std::floor(v));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= big.width || y0 + 1 >= big.height) continue;
      const double fx = u - x0, fy = v - y0;
      for (int c = 0; c < 3; ++c) {
        const double want = (1 - fy) * ((1 - fx) * pattern(x0, y0, c) + fx * pattern(x0 + 1, y0, c)) +
                            fy * ((1 - fx) * pattern(x0, y0 + 1, c) + fx * pattern(x0 + 1, y0 + 1, c));
        // The pattern wraps at 256 in places: skip taps that straddle a wrap.
        if (std::abs(pattern(x0, y0, c) - pattern(x0 + 1, y0 + 1, c)) > 8) continue;
        bad += std::fabs(out.pixel(x, y)[c] - want) > 1.5;
      }
    }
    std::printf("equirect 40000x20000 -> %s %lldx%lld bilinear: %.2f s (%lld tiles, %lld SIMD), "
                "%.1f Mpx/s; spot checks off by > 1 LSB: %d; peak RSS %.2f GB\n",
                j.spec, static_cast<long long>(j.size.width), static_cast<long long>(j.size.height), t,
                static_cast<long long>(st.tiles), static_cast<long long>(st.simd_tiles),
                j.size.width * j.size.height / t / 1e6, bad, peak_gb());
  }
}
