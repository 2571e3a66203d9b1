#pragma once
// Error of a conversion against a ground truth rendered straight into the target (scene.hpp):
// the numbers `panoproj accuracy` reports for each option so users can weigh them against time.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "panoproj/options.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/image.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/diagnostics/scene.hpp"

namespace panoproj {

struct ErrorStats {
  double psnr = 0;     // dB, peak 1 (the type's full range; float images: 1.0)
  double rmse = 0;     // in units of that peak
  double max_abs = 0;  // largest channel difference, same units
  double ssim = 0;     // mean SSIM of the luminance over 8x8 windows (step 4) wholly compared
  int64_t pixels = 0;  // pixels compared
};

// 1 where the output pixel's centre has a ray in dst whose rotation has a source pixel in src.
std::vector<uint8_t> compared_pixels(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation);

// Channels [0, 3) of result against truth (same size and type) over the pixels where mask is 1.
ErrorStats compare_images(const Image& result, const Image& truth, const std::vector<uint8_t>& mask);

// An error-against-time sweep: the scene rendered in the source (each pixel the mean of
// source_supersample^2 rays, as a camera integrates), converted with each option (the
// Converter built and run inside the timing, compute only), against the truth rendered in the
// target (truth_supersample^2 rays per pixel: its area average).
struct SweepSetup {
  Scene scene = Scene::Chart;
  PixelType type = PixelType::U8;
  int threads = 0;
  int runs = 5;  // timed runs per option (the median is reported)
  int source_supersample = 2, truth_supersample = 8;
};
struct SweepOption {
  Interp interp;
  Antialias antialias;
  Engine engine;  // simd: float geometry where within 1/1024 px; reference: exact double
  // 0: the rendered source as it is; 1, 2, 4, 8: the source written as a file and decoded at
  // 1/decode_scale inside the timing, the geometry rescaled to that frame, as `convert
  // --decode-scale` does: uint8 as a JPEG (quality 95, 4:2:0; DCT scaling), float as a Radiance
  // HDR (block means, rows read in bands).
  int decode_scale = 0;
};
struct SweepResult {
  SweepOption option;
  std::string source;  // decode_name of its decode scale and the setup's type
  double median_ms = 0;
  ErrorStats error;
};

// The sweep over every listed engine x kernel x antialiasing x decode scale (the reference
// engine: off only); by default all four kernels, off, auto, mip and 4x4, simd and reference,
// the source in memory.
std::vector<SweepOption> sweep_options(const std::vector<Interp>& interps = {Interp::Nearest, Interp::Bilinear,
                                                                               Interp::Bicubic, Interp::Lanczos3},
                                       const std::vector<Antialias>& antialias = {Antialias{},
                                                                                  {Antialias::Mode::Auto, 1},
                                                                                  {Antialias::Mode::Mip, 1},
                                                                                  {Antialias::Mode::Supersample, 4}},
                                       const std::vector<Engine>& engines = {Engine::Simd, Engine::Reference},
                                       const std::vector<int>& decode_scales = {0});
// "memory" (0), "jpeg" (1), "jpeg 1/4", "hdr 1/8" ... (the file: JPEG for uint8, HDR for float)
std::string decode_name(int decode_scale, PixelType type);
std::vector<SweepResult> run_sweep(const Projection& source, const Projection& target, const Eigen::Matrix3d& rotation,
                                   const SweepSetup& setup, const std::vector<SweepOption>& options);
// The results as a Markdown table (Pareto-optimal rows marked), CSV and JSON (with `about`, a
// line describing the setup).
std::string sweep_table(const std::vector<SweepResult>& results);
std::string sweep_csv(const std::vector<SweepResult>& results);
std::string sweep_json(const std::vector<SweepResult>& results, const std::string& about);
// Indices of the results no other beats on both time and PSNR, fastest first.
std::vector<size_t> pareto_front(const std::vector<SweepResult>& results);
// PSNR against median time (log scale), the Pareto front marked: an 8-bit RGB chart (labels
// need the DejaVu Sans font, which the install script adds; without it, none).
Image plot_sweep(const std::vector<SweepResult>& results, const std::string& title);

}  // namespace panoproj
