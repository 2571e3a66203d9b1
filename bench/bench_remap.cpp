// panoproj against OpenCV's cv::remap and a memcpy of the output, in one process, on the same
// input (the Jordan Pond panorama, RGB uint8), compute only (no file I/O).
//   panoproj: the whole conversion, its geometry computed inside the timing (a new Converter per
//   run), into an output buffer kept across runs like cv::remap's.
//   cv::remap: remap only, given maps for free (float CV_32FC1 pairs, and fixed-point
//   CV_16SC2 + CV_16UC1 from cv::convertMaps; the faster of the two is the reference).
//   memcpy: copying a buffer the size of the output (the floor for any method).
// Median of --runs runs (default 9), the four taken in turns. OpenCV has no Lanczos-3: its LANCZOS4 (8x8) stands in,
// labelled so. Usage: bench_remap [--threads N] [--runs N] [--case I] [--ours-only]
// (--case runs only the I-th row, --ours-only skips the peers: for profiling).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "panoproj/convert.hpp"
#include "panoproj/io.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/rotation.hpp"
#include "simd_converter.hpp"

using namespace panoproj;

namespace {

// Medians (ms) of runs of each function, taken in turns (f0, f1, ..., f0, f1, ...) so that a
// load change on this shared machine hits all of them alike; one warm-up run each.
std::vector<double> median_ms(int runs, const std::vector<std::function<void()>>& fs) {
  std::vector<std::vector<double>> t(fs.size());
  for (const auto& f : fs) f();
  for (int i = 0; i < runs; ++i)
    for (size_t k = 0; k < fs.size(); ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      fs[k]();
      t[k].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  std::vector<double> med;
  for (auto& v : t) {
    std::sort(v.begin(), v.end());
    med.push_back(v[v.size() / 2]);
  }
  return med;
}

// The exact map in cv::remap's convention (pixel centres at integers: subtract 0.5).
void cv_maps(const Projection& src, const Projection& dst, cv::Mat& mx, cv::Mat& my) {
  const Size s = size_of(dst);
  mx.create(static_cast<int>(s.height), static_cast<int>(s.width), CV_32FC1);
  my.create(mx.size(), CV_32FC1);
  for (int64_t y = 0; y < s.height; ++y)
    for (int64_t x = 0; x < s.width; ++x) {
      Ray d;
      double sx = -10, sy = -10;
      if (!(to_ray(dst, x + 0.5, y + 0.5, d) && to_pixel(src, d, sx, sy))) sx = sy = -10;
      mx.at<float>(static_cast<int>(y), static_cast<int>(x)) = static_cast<float>(sx - 0.5);
      my.at<float>(static_cast<int>(y), static_cast<int>(x)) = static_cast<float>(sy - 0.5);
    }
}

cv::Mat as_mat(const Image& im) {
  return cv::Mat(static_cast<int>(im.height()), static_cast<int>(im.width()), CV_8UC3,
                 const_cast<unsigned char*>(im.data()), im.row_bytes());
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 2, runs = 9, only = -1;
  bool ours_only = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--ours-only")) ours_only = true;
    if (i + 1 == argc) break;
    if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--case")) only = std::atoi(argv[i + 1]);
  }
  cv::setNumThreads(threads);
  const Image pano = read_image(std::string(PANOPROJ_SOURCE_DIR) + "/samples/images/jordan_pond_4096x2048.jpg");
  const Projection equirect = make_projection(parse_spec("equirect"), {4096, 2048});
  const Projection cube = make_projection(parse_spec("cubemap"), {6 * 1024, 1024});
  const Image cube_img =
      bench::simd_converter(equirect, cube, Eigen::Matrix3d::Identity(), Interp::Bicubic, threads)
          .run(pano);
  const Projection dual = make_projection(parse_spec("dual-fisheye:fov=200"), {4096, 2048});
  const Image dual_img =
      bench::simd_converter(equirect, dual, Eigen::Matrix3d::Identity(), Interp::Bicubic, threads)
          .run(pano);

  struct Case {
    const char* name;
    const Image* src;
    const Projection* sp;
    const char* dst;
    Size size;
    Interp interp;
    int cv_interp;
  };
  const Case cases[] = {
      {"equirect 4096x2048 -> cubemap 6x1024^2", &pano, &equirect, "cubemap", {6 * 1024, 1024}, Interp::Bilinear, cv::INTER_LINEAR},
      {"equirect 4096x2048 -> cubemap 6x1024^2", &pano, &equirect, "cubemap", {6 * 1024, 1024}, Interp::Bicubic, cv::INTER_CUBIC},
      {"equirect 4096x2048 -> cubemap 6x1024^2", &pano, &equirect, "cubemap", {6 * 1024, 1024}, Interp::Lanczos3, cv::INTER_LANCZOS4},
      {"equirect 4096x2048 -> fisheye 2048^2 180", &pano, &equirect, "fisheye:fov=180", {2048, 2048}, Interp::Bilinear, cv::INTER_LINEAR},
      {"equirect 4096x2048 -> fisheye 2048^2 180", &pano, &equirect, "fisheye:fov=180", {2048, 2048}, Interp::Bicubic, cv::INTER_CUBIC},
      {"equirect 4096x2048 -> pinhole 1920x1080 90", &pano, &equirect, "pinhole:hfov=90", {1920, 1080}, Interp::Bilinear, cv::INTER_LINEAR},
      {"cubemap 6x1024^2 -> equirect 4096x2048", &cube_img, &cube, "equirect", {4096, 2048}, Interp::Bilinear, cv::INTER_LINEAR},
      // OpenCV's map can only cut between the lenses; panoproj blends the 20-degree overlap.
      {"dual fisheye 2x2048^2 200 -> equirect 4096x2048 (panoproj blends; OpenCV: hard cut)", &dual_img, &dual, "equirect",
       {4096, 2048}, Interp::Bilinear, cv::INTER_LINEAR},
  };
  std::printf("panoproj %s engine (%s), %d threads, median of %d runs, uint8 RGB\n\n", "simd", simd_target(), threads, runs);
  std::printf("| conversion | kernel | panoproj ms | cv::remap float ms | cv::remap fixed ms | memcpy ms | panoproj / OpenCV | panoproj / memcpy |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const Case& c : cases) {
    if (only >= 0 && &c != &cases[only]) continue;
    const Projection dst = make_projection(parse_spec(c.dst), c.size);
    // Both sides write into an output buffer kept across runs (as a video or batch does).
    Image ours_out;
    auto ours_run = [&] {
      bench::simd_converter(*c.sp, dst, Eigen::Matrix3d::Identity(), c.interp, threads)
          .run(*c.src, ours_out);
    };
    if (ours_only) {
      std::printf("| %s | %s | %.1f | | | | | |\n", c.name, name_of(c.interp), median_ms(runs, {ours_run})[0]);
      continue;
    }
    cv::Mat mx, my, fx, fy, out;
    cv_maps(*c.sp, dst, mx, my);
    cv::convertMaps(mx, my, fx, fy, CV_16SC2);
    const cv::Mat in = as_mat(*c.src);
    const size_t bytes = static_cast<size_t>(c.size.width * c.size.height * 3);
    std::vector<unsigned char> a(bytes, 1), b(bytes);
    const auto ms = median_ms(runs, {ours_run, [&] { cv::remap(in, out, mx, my, c.cv_interp, cv::BORDER_CONSTANT); },
                                     [&] { cv::remap(in, out, fx, fy, c.cv_interp, cv::BORDER_CONSTANT); },
                                     [&] { std::memcpy(b.data(), a.data(), bytes); }});
    const double ours = ms[0], cv_float = ms[1], cv_fixed = ms[2], copy = ms[3];
    const double best_cv = std::min(cv_float, cv_fixed);
    std::printf("| %s | %s%s | %.1f | %.1f | %.1f | %.2f | %.2f | %.1f |\n", c.name, name_of(c.interp),
                c.interp == Interp::Lanczos3 ? " (OpenCV: LANCZOS4 8x8)" : "", ours, cv_float, cv_fixed,
                copy, ours / best_cv, ours / copy);
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  std::printf("\npeak memory (whole process, incl. OpenCV maps): %.0f MB\n", ru.ru_maxrss / 1024.0);
}
