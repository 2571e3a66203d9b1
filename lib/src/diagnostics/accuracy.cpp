#include "panoproj/diagnostics/accuracy.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <numeric>
#include <string>

#include "base/sample_io.hpp"
#include "io/formats.hpp"
#include "panoproj/error.hpp"
#include "panoproj/io.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {

std::vector<uint8_t> compared_pixels(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation) {
  const Size s = size_of(dst);
  std::vector<uint8_t> mask(static_cast<size_t>(s.width * s.height));
  for (int64_t y = 0; y < s.height; ++y)
    for (int64_t x = 0; x < s.width; ++x) {
      Ray d;
      double sx, sy;
      mask[static_cast<size_t>(y * s.width + x)] =
          to_ray(dst, x + 0.5, y + 0.5, d) && to_pixel(src, rotation * d.normalized(), sx, sy);
    }
  return mask;
}

ErrorStats compare_images(const Image& result, const Image& truth, const std::vector<uint8_t>& mask) {
  if (result.size() != truth.size() || result.type() != truth.type() || result.channels() < 3 || truth.channels() < 3)
    throw Error("compare_images: the result (" + std::to_string(result.width()) + "x" + std::to_string(result.height()) +
                ", " + name_of(result.type()) + ") and the truth differ in size or type, or have under 3 channels");
  const int64_t w = truth.width(), h = truth.height();
  std::vector<float> la(static_cast<size_t>(w * h)), lb(static_cast<size_t>(w * h));  // luminance
  ErrorStats st;
  double se = 0;
  with_sample_type(truth.type(), [&](auto tag) {
    using T = decltype(tag);
    const double inv = 1.0 / unit_of(truth.type());
    for (int64_t y = 0; y < h; ++y)
      for (int64_t x = 0; x < w; ++x) {
        const size_t k = static_cast<size_t>(y * w + x);
        if (!mask[k]) continue;
        double ya = 0, yb = 0;
        for (int c = 0; c < 3; ++c) {
          const double a = load<T>(result.pixel(x, y) + c * sizeof(T)) * inv, b = load<T>(truth.pixel(x, y) + c * sizeof(T)) * inv;
          se += (a - b) * (a - b);
          st.max_abs = std::max(st.max_abs, std::fabs(a - b));
          ya += a / 3, yb += b / 3;
        }
        la[k] = static_cast<float>(ya), lb[k] = static_cast<float>(yb);
        ++st.pixels;
      }
  });
  if (st.pixels == 0) return st;
  st.rmse = std::sqrt(se / (3.0 * static_cast<double>(st.pixels)));
  st.psnr = st.rmse > 0 ? -20.0 * std::log10(st.rmse) : 999.0;
  // SSIM (Wang et al. 2004) with C1 = (0.01)^2, C2 = (0.03)^2 for a peak of 1.
  constexpr int kWin = 8, kStep = 4;
  constexpr double c1 = 1e-4, c2 = 9e-4;
  double sum = 0;
  int64_t windows = 0;
  for (int64_t y0 = 0; y0 + kWin <= h; y0 += kStep)
    for (int64_t x0 = 0; x0 + kWin <= w; x0 += kStep) {
      double ma = 0, mb = 0, vaa = 0, vbb = 0, vab = 0;
      bool whole = true;
      for (int64_t y = y0; y < y0 + kWin && whole; ++y)
        for (int64_t x = x0; x < x0 + kWin; ++x) {
          const size_t k = static_cast<size_t>(y * w + x);
          if (!mask[k]) {
            whole = false;
            break;
          }
          ma += la[k], mb += lb[k], vaa += la[k] * la[k], vbb += lb[k] * lb[k], vab += la[k] * lb[k];
        }
      if (!whole) continue;
      constexpr double n = kWin * kWin;
      ma /= n, mb /= n;
      vaa = vaa / n - ma * ma, vbb = vbb / n - mb * mb, vab = vab / n - ma * mb;
      sum += (2 * ma * mb + c1) * (2 * vab + c2) / ((ma * ma + mb * mb + c1) * (vaa + vbb + c2));
      ++windows;
    }
  st.ssim = windows ? sum / static_cast<double>(windows) : 0.0;
  return st;
}

std::vector<SweepOption> sweep_options(const std::vector<Interp>& interps, const std::vector<Antialias>& antialias,
                                       const std::vector<Engine>& engines, const std::vector<int>& decode_scales) {
  std::vector<SweepOption> v;
  for (int d : decode_scales)
    for (Engine e : engines)
      for (Interp k : interps) {
        if (e == Engine::Reference) {
          v.push_back({k, Antialias{}, e, d});
          continue;
        }
        for (const Antialias& a : antialias) v.push_back({k, a, e, d});
      }
  return v;
}

std::string decode_name(int decode_scale, PixelType type) {
  if (decode_scale == 0) return "memory";
  const std::string file = scaled_format_for(type).name;
  return decode_scale == 1 ? file : file + " 1/" + std::to_string(decode_scale);
}

namespace {

// The rendered source as a file (uint8: JPEG, float: Radiance HDR) in a fresh temporary folder,
// removed with it.
class EncodedSource {
 public:
  explicit EncodedSource(const Image& source)
      : extension_(scaled_format_for(source.type()).extensions[0]) {
    std::string dir = (std::filesystem::temp_directory_path() / "panoproj-accuracy-XXXXXX").string();
    if (!::mkdtemp(dir.data())) throw Error("accuracy: cannot make a temporary folder: " + std::string(std::strerror(errno)), ErrorKind::File);
    dir_ = dir;
    write_image(source, path(), {});
  }
  ~EncodedSource() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  EncodedSource(const EncodedSource&) = delete;
  EncodedSource& operator=(const EncodedSource&) = delete;
  std::string path() const { return (dir_ / ("source" + extension_)).string(); }

 private:
  std::string extension_;
  std::filesystem::path dir_;
};

}  // namespace

std::vector<SweepResult> run_sweep(const Projection& sp, const Projection& dp, const Eigen::Matrix3d& rotation,
                                   const SweepSetup& setup, const std::vector<SweepOption>& options) {
  if (setup.runs < 1) throw Error("runs: " + std::to_string(setup.runs) + " (expected at least 1)");
  const Image source = render_scene(setup.scene, sp, setup.type, setup.source_supersample, setup.threads);
  const Image truth = render_scene(setup.scene, dp, setup.type, setup.truth_supersample, setup.threads);
  const std::vector<uint8_t> mask = compared_pixels(sp, dp, rotation);
  std::unique_ptr<EncodedSource> file;
  const Size size = size_of(sp);
  for (const SweepOption& o : options) {
    if (o.decode_scale > 0 && !file) file = std::make_unique<EncodedSource>(source);
    if (o.decode_scale > 1 && (size.width % o.decode_scale != 0 || size.height % o.decode_scale != 0))
      throw Error("accuracy: decode scale " + std::to_string(o.decode_scale) + " needs the source's sides (" +
                  size_text(size) + ") to be multiples of it");
  }
  std::vector<SweepResult> results;
  for (const SweepOption& o : options) {
    std::vector<double> ms;
    Image out;
    const int s = std::max(1, o.decode_scale);
    const Projection from = s > 1 ? rescaled(sp, {size.width / s, size.height / s}) : sp;
    for (int r = 0; r < setup.runs; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      ConvertOptions options;
      options.interp = o.interp, options.engine = o.engine, options.threads = setup.threads;
      options.antialias = o.antialias;
      const Converter c(ConversionGeometry{from, dp, rotation}, options);
      if (o.decode_scale > 0) c.run(read_image_region(file->path(), 0, 0, INT64_MAX, INT64_MAX, 0, 0, s), out);
      else c.run(source, out);
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
    results.push_back({o, decode_name(o.decode_scale, setup.type), ms[ms.size() / 2], compare_images(out, truth, mask)});
  }
  return results;
}

std::vector<size_t> pareto_front(const std::vector<SweepResult>& results) {
  std::vector<size_t> order(results.size()), front;
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return results[a].median_ms < results[b].median_ms ||
           (results[a].median_ms == results[b].median_ms && results[a].error.psnr > results[b].error.psnr);
  });
  double best = -HUGE_VAL;  // walking from the fastest, keep each that beats every faster one
  for (size_t i : order)
    if (results[i].error.psnr > best) front.push_back(i), best = results[i].error.psnr;
  return front;
}

namespace {

std::string format(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* f, ...) {
  char buf[512];
  va_list a;
  va_start(a, f);
  std::vsnprintf(buf, sizeof buf, f, a);
  va_end(a);
  return buf;
}

}  // namespace

std::string sweep_table(const std::vector<SweepResult>& results) {
  const auto front = pareto_front(results);
  std::string t = "| source | kernel | antialias | engine | median ms | PSNR dB | max abs error | SSIM | Pareto |\n"
                  "|---|---|---|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < results.size(); ++i) {
    const SweepResult& r = results[i];
    const bool best = std::find(front.begin(), front.end(), i) != front.end();
    t += format("| %s | %s | %s | %s | %.2f | %.2f | %.4f | %.4f | %s |\n", r.source.c_str(),
                name_of(r.option.interp),
                name_of(r.option.antialias).c_str(), name_of(r.option.engine), r.median_ms, r.error.psnr, r.error.max_abs,
                r.error.ssim, best ? "yes" : "");
  }
  return t;
}

std::string sweep_csv(const std::vector<SweepResult>& results) {
  const auto front = pareto_front(results);
  std::string t = "source,kernel,antialias,engine,median_ms,psnr_db,rmse,max_abs,ssim,pixels,pareto\n";
  for (size_t i = 0; i < results.size(); ++i) {
    const SweepResult& r = results[i];
    t += format("%s,%s,%s,%s,%.4f,%.4f,%.6g,%.6g,%.6f,%lld,%d\n", r.source.c_str(),
                name_of(r.option.interp), name_of(r.option.antialias).c_str(),
                name_of(r.option.engine), r.median_ms, r.error.psnr, r.error.rmse, r.error.max_abs, r.error.ssim,
                static_cast<long long>(r.error.pixels), std::find(front.begin(), front.end(), i) != front.end() ? 1 : 0);
  }
  return t;
}

std::string sweep_json(const std::vector<SweepResult>& results, const std::string& about) {
  const auto front = pareto_front(results);
  std::string escaped;
  for (char c : about) escaped += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  std::string t = "{\n  \"about\": \"" + escaped + "\",\n  \"results\": [\n";
  for (size_t i = 0; i < results.size(); ++i) {
    const SweepResult& r = results[i];
    t += format("    {\"source\": \"%s\", \"kernel\": \"%s\", \"antialias\": \"%s\", \"engine\": \"%s\", \"median_ms\": %.4f, "
                "\"psnr_db\": %.4f, \"rmse\": %.6g, \"max_abs\": %.6g, \"ssim\": %.6f, \"pixels\": %lld, "
                "\"pareto\": %s}%s\n",
                r.source.c_str(), name_of(r.option.interp), name_of(r.option.antialias).c_str(),
                name_of(r.option.engine), r.median_ms, r.error.psnr, r.error.rmse, r.error.max_abs, r.error.ssim,
                static_cast<long long>(r.error.pixels), std::find(front.begin(), front.end(), i) != front.end() ? "true" : "false",
                i + 1 < results.size() ? "," : "");
  }
  return t + "  ]\n}\n";
}

}  // namespace panoproj
