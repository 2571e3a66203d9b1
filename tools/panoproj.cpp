// The panoproj command: a thin front end over the library (lib/include/panoproj/convert_job.hpp).
#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "panoproj/convert_job.hpp"
#include "panoproj/error.hpp"
#include "panoproj/parallel.hpp"
#include "panoproj/spec.hpp"

namespace {

using namespace panoproj;

Size parse_size(const std::string& text) {
  const auto x = text.find('x');
  if (x != std::string::npos) {
    try {
      size_t a = 0, b = 0;
      const long long w = std::stoll(text.substr(0, x), &a), h = std::stoll(text.substr(x + 1), &b);
      if (a == x && b == text.size() - x - 1 && w > 0 && h > 0) return {w, h};
    } catch (const std::exception&) {
    }
  }
  throw Error("size: " + text + " (expected WxH with positive integers, e.g. 2048x1024)");
}

std::optional<PixelType> parse_depth(const std::string& text) {
  if (text.empty() || text == "keep") return std::nullopt;
  for (PixelType t : {PixelType::U8, PixelType::U16, PixelType::F16, PixelType::F32})
    if (text == name_of(t)) return t;
  throw Error("depth: " + text + " (expected keep, uint8, uint16, half or float)");
}

// Image libraries (libpng, libjpeg via OpenImageIO) print their own messages to stderr; the
// CLI reports failures itself in one line, so it holds stderr while a job runs.
class QuietStderr {
 public:
  explicit QuietStderr(bool active) {
    if (!active) return;
    std::fflush(stderr);
    saved_ = ::dup(2);
    const int null_fd = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null_fd >= 0) ::dup2(null_fd, 2);
    if (null_fd >= 0) ::close(null_fd);
  }
  ~QuietStderr() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;
  // The real stderr while held (for the progress bar).
  int fd() const { return saved_ >= 0 ? saved_ : 2; }

 private:
  int saved_ = -1;
};

// "[#####.....]  52%" redrawn in place, only on a terminal.
class ProgressBar {
 public:
  ProgressBar(int fd, bool enabled) : fd_(fd), enabled_(enabled && ::isatty(fd)) {}
  ~ProgressBar() {
    if (enabled_ && shown_) (void)!::write(fd_, "\r\033[K", 4);
  }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  void update(double fraction) {
    if (!enabled_) return;
    const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100);
    if (percent == last_) return;
    last_ = percent;
    shown_ = true;
    char line[128];
    const int filled = percent * 30 / 100;
    const int n = std::snprintf(line, sizeof line, "\r[%.*s%.*s] %3d%%", filled,
                                "##############################", 30 - filled,
                                "..............................", percent);
    (void)!::write(fd_, line, static_cast<size_t>(n));
  }

 private:
  int fd_;
  bool enabled_, shown_ = false;
  int last_ = -1;
};

void print_info() {
  std::cout << "Projections (spec: name[:key=value,...], angles in degrees, sizes in pixels):\n";
  for (const auto& d : projection_catalog()) {
    std::cout << "\n  " << d.name << " - " << d.summary << "\n";
    for (const auto& p : d.params) {
      std::ostringstream range;
      if (p.type == ParamType::Choice) {
        range << p.choices;
      } else {
        range << (p.lo_open ? "(" : "[") << p.lo << ", " << p.hi << (p.hi_open ? ")" : "]");
      }
      std::cout << "      " << p.key << "=" << (*p.default_text ? p.default_text : "<derived>")
                << "  " << range.str() << "  " << p.help << "\n";
    }
  }
  std::cout << "\nInterpolators: nearest, bilinear, bicubic (Keys a=-0.5, default), lanczos3\n"
               "Rotation: --yaw (positive looks right), --pitch (positive looks up), --roll "
               "(positive turns the view clockwise); applied roll, then pitch, then yaw.\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"panoproj: convert images between panoramic, fisheye, pinhole, cubemap and map "
               "projections"};
  app.require_subcommand(1);

  ConvertJob job;
  std::string size_text, interp_text = "bicubic", depth_text, engine_text = "simd";
  std::string from_text;
  auto* convert = app.add_subcommand("convert", "convert one image (or cube-face set) to another projection");
  std::vector<std::string> files;
  convert->add_option("files", files,
                      "IN... OUT: an input image (or a cube-face pattern with {face}/{index}) and the "
                      "output; several inputs (same size) need an output pattern with {stem} or {n}")
      ->required()
      ->expected(2, -1);
  convert->add_option("--from", from_text,
                      "source projection spec (default: 2:1 image = equirect; face pattern = "
                      "cubemap:layout=files)");
  convert->add_option("--to", job.to, "target projection spec, e.g. fisheye:fov=180")->required();
  convert->add_option("--size", size_text,
                      "output size WxH (cube faces: one face); default: source resolution, square "
                      "pixels");
  convert->add_option("--yaw", job.options.yaw, "degrees, positive looks right");
  convert->add_option("--pitch", job.options.pitch, "degrees, positive looks up");
  convert->add_option("--roll", job.options.roll, "degrees, positive turns the view clockwise");
  convert->add_option("--interp", interp_text, "nearest|bilinear|bicubic|lanczos3 (default bicubic)");
  convert->add_option("--threads", job.options.threads, "worker threads (default: all cores)");
  convert->add_option("--engine", engine_text,
                      "simd (default) | scalar (same tiles, no SIMD) | reference (exact, slow)");
  convert->add_option("--depth", depth_text, "output samples: keep|uint8|uint16|half|float");
  convert->add_flag("--overwrite", job.write.overwrite, "replace an existing output");
  bool quiet = false, verbose = false;
  convert->add_flag("-q,--quiet", quiet, "print nothing on success");
  convert->add_flag("-v,--verbose", verbose, "let image libraries print their own warnings");

  MapsJob maps_job;
  std::string maps_size, maps_source_size, maps_convention = "opencv";
  auto* maps = app.add_subcommand("maps", "write the source-coordinate map of a conversion (float x, y)");
  maps->add_option("output", maps_job.output, "map file: .exr or .tif (2 float channels: x, y)")->required();
  maps->add_option("--from", maps_job.from, "source projection spec")->required();
  maps->add_option("--source-size", maps_source_size, "source image size WxH")->required();
  maps->add_option("--to", maps_job.to, "target projection spec")->required();
  maps->add_option("--size", maps_size, "output size WxH (default: as for convert)");
  maps->add_option("--yaw", maps_job.options.yaw, "degrees, positive looks right");
  maps->add_option("--pitch", maps_job.options.pitch, "degrees, positive looks up");
  maps->add_option("--roll", maps_job.options.roll, "degrees, positive turns the view clockwise");
  maps->add_option("--convention", maps_convention,
                   "opencv (default: centres at integers, -1 where no source, for cv::remap) | "
                   "panoproj (centres at i + 0.5, NaN where no source)");
  maps->add_option("--threads", maps_job.options.threads, "worker threads (default: all cores)");
  maps->add_flag("--overwrite", maps_job.write.overwrite, "replace an existing output");

  auto* info = app.add_subcommand("info", "list projections, their parameters and defaults");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (info->parsed()) {
      print_info();
      return 0;
    }
    if (maps->parsed()) {
      maps_job.source_size = parse_size(maps_source_size);
      if (!maps_size.empty()) maps_job.options.size = parse_size(maps_size);
      if (maps_convention != "opencv" && maps_convention != "panoproj")
        throw Error("convention: " + maps_convention + " (expected opencv or panoproj)");
      maps_job.convention = maps_convention == "opencv" ? MapConvention::OpenCV : MapConvention::Panoproj;
      const Size out = run_maps(maps_job);
      std::printf("%s: %lldx%lld map (x, y float32, %s convention)\n", maps_job.output.c_str(),
                  static_cast<long long>(out.width), static_cast<long long>(out.height), maps_convention.c_str());
      return 0;
    }
    if (!from_text.empty()) job.from = from_text;
    if (!size_text.empty()) job.options.size = parse_size(size_text);
    job.options.interp = parse_interp(interp_text);
    job.options.engine = parse_engine(engine_text);
    job.write.type = parse_depth(depth_text);
    job.output = files.back();
    job.inputs.assign(files.begin(), files.end() - 1);
    auto dims = [](Size sz, bool faces) {
      return std::string(faces ? "6 faces of " : "") + std::to_string(sz.width) + "x" +
             std::to_string(sz.height);
    };
    QuietStderr hold(!verbose);
    ProgressBar bar(hold.fd(), !quiet);
    run_convert(
        job,
        [&](const ConvertReport& r) {
          if (quiet) return;
          std::printf("\r%s (%s, %s) -> %s (%s, %s): %.3f s, %s, %s engine (%s), %d threads, "
                      "read %.0f%% of the source\n",
                      r.input.c_str(), dims(r.input_size, r.input_faces).c_str(), r.from.c_str(),
                      r.output.c_str(), dims(r.output_size, r.output_faces).c_str(), r.to.c_str(),
                      r.seconds, interp_text.c_str(), engine_text.c_str(), simd_target(),
                      resolve_threads(job.options.threads), 100 * r.read_fraction);
          std::fflush(stdout);
        },
        [&](double f) { bar.update(f); });
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "panoproj: error: %s\n", e.what());
    return 1;
  }
}
