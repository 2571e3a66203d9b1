// No size limit: a generated 40000x20000 uint8 RGB equirect (2.4 GB) converted to a 90-degree
// pinhole (4096x4096) and to a cubemap with 10000-px faces (6 x 10000^2, 1.8 GB), in memory.
// Memory stays source + output + per-thread tile buffers (no per-pixel tables): peak RSS is
// printed after each step. Spot checks compare 2000 output pixels with the exact reference
// sampling of the same positions. Needs ~4.5 GB. Usage: bench_big [--threads N]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>

#include <OpenImageIO/imageio.h>
#include <string>

#include "panoproj/convert.hpp"
#include "panoproj/jobs.hpp"
#include "panoproj/rotation.hpp"
#include "simd_converter.hpp"

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

// Converts in a child process; returns its peak RSS in GB and prints its report.
double convert_in_child(const Arguments& job) {
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    try {
      JobEvents events;
      events.line = [](const std::string& line) { std::printf("  %s\n", line.c_str()); };
      job_named("convert").run(job, events);
      std::fflush(stdout);
      _exit(0);
    } catch (const std::exception& e) {
      std::printf("  failed: %s\n", e.what());
      _exit(1);
    }
  }
  int status = 0;
  rusage ru{};
  wait4(pid, &status, 0, &ru);
  return ru.ru_maxrss / 1024.0 / 1024.0;
}

void region_reads(const std::string& dir, int threads) {
  const Size s{32768, 16384};
  const std::string tif = dir + "/panoproj_big_tiled.tif", jpg = dir + "/panoproj_big.jpg";
  {  // the generated image is freed before the conversions fork, so they do not inherit it
  Image src(s, 3, PixelType::U8);
  for (int64_t y = 0; y < s.height; ++y)
    for (int64_t x = 0; x < s.width; ++x)
      for (int c = 0; c < 3; ++c) src.pixel(x, y)[c] = pattern(x, y, c);
  {
    auto out = OIIO::ImageOutput::create(tif);
    OIIO::ImageSpec spec(static_cast<int>(s.width), static_cast<int>(s.height), 3, OIIO::TypeDesc::UINT8);
    spec.tile_width = spec.tile_height = 256;
    spec.attribute("compression", "zip");
    out->open(tif, spec);
    out->write_image(OIIO::TypeDesc::UINT8, src.data());
    out->close();
  }
  WriteOptions w;
  w.overwrite = true;
  write_image(src, jpg, w);
  }
  std::printf("\nregion reads: 32768x16384 RGB equirect, decoded 1.61 GB, written as %s and %s\n", tif.c_str(), jpg.c_str());
  for (const std::string& in : {tif, jpg}) {
    for (const char* view : {"pinhole:hfov=90", "pinhole:hfov=90,vfov=90"}) {
      const double pitch =
          std::string(view).find("vfov") != std::string::npos ? 70 : 0;  // at the pole, or level
      Arguments job(job_named("convert").rows());
      job.set("inputs", std::vector<std::string>{in}).set("output", dir + "/panoproj_big_view.png");
      job.set("dst", std::string(view))
          .set("size", std::string("2048x2048"))
          .set("pitch", pitch)
          .set("yaw", 30.0);
      job.set("threads", int64_t{threads}).set("overwrite", true);
      const double gb = convert_in_child(job);
      std::printf(
          "  pitch %.0f: peak memory of the converting process %.2f GB (decoded source 1.61 GB)\n",
          pitch, gb);
    }
  }
  std::remove(tif.c_str());
  std::remove(jpg.c_str());
  std::remove((dir + "/panoproj_big_view.png").c_str());
}

int main(int argc, char** argv) {
  int threads = 0;
  std::string dir = "/tmp";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--dir")) dir = argv[i + 1];
  }
  {
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
    const Image out = bench::simd_converter(e, dst, r, Interp::Bilinear, threads).run(src, &st);
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
    std::printf("equirect 40000x20000 -> %s %lldx%lld bilinear: %.2f s (%lld tiles, %lld fused; %lld SIMD misses), "
                "%.1f Mpx/s; spot checks off by > 1 LSB: %d; peak RSS %.2f GB\n",
                j.spec, static_cast<long long>(j.size.width), static_cast<long long>(j.size.height), t,
                static_cast<long long>(st.tiles), static_cast<long long>(st.fused_tiles), static_cast<long long>(st.simd_misses),
                j.size.width * j.size.height / t / 1e6, bad, peak_gb());
  }
  }
  region_reads(dir, threads);
}
