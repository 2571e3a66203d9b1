// The panoproj command: a thin front end over the library (lib/include/panoproj/jobs.hpp).
#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "panoproj/diagnostics/accuracy.hpp"
#include "panoproj/jobs.hpp"
#include "panoproj/io.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/options.hpp"
#include "panoproj/rotation.hpp"
#include "panoproj/diagnostics/stability.hpp"
#include "panoproj/error.hpp"
#include "panoproj/spec.hpp"
#include "panoproj/tiles.hpp"
#include "panoproj/views.hpp"

namespace {

using namespace panoproj;

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
    if (saved_ >= 0) set_notice_handler([fd = saved_](const std::string& text) { ::dprintf(fd, "panoproj: %s\n", text.c_str()); });
  }
  ~QuietStderr() {
    if (saved_ < 0) return;
    set_notice_handler({});
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

// Comma-separated items, each through parse.
template <class F>
auto parse_list(const std::string& text, F&& parse) {
  std::vector<decltype(parse(std::string_view{}))> v;
  std::string_view rest = text;
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    v.push_back(parse(rest.substr(0, comma)));
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
  }
  return v;
}

// The options table's rows (options.hpp) that a subcommand takes, each bound to storage of its
// type; apply() sets those given on the command line.
class TableOptions {
 public:
  TableOptions(CLI::App* sub, unsigned use) {
    for (const OptionDef& d : conversion_options()) {
      if (!(d.use & use)) continue;
      Row& r = rows_.emplace_back(Row{&d, {}, false, nullptr});
      // Flags bound to a bool (CLI11 refuses --alpha=maybe); values as text, which the table's
      // types parse (CLI11 saturates integers).
      r.option = d.type == OptionType::Flag ? sub->add_flag(flag_of(d), r.flag, d.help)
                                            : sub->add_option(flag_of(d), r.text, d.help);
    }
  }
  void apply(ConvertOptions& options) const {
    for (const Row& r : rows_)
      if (r.option->count() > 0)
        r.def->set(options, r.def->type == OptionType::Flag ? OptionValue(r.flag) : option_value(*r.def, r.text));
  }

 private:
  struct Row {
    const OptionDef* def;
    std::string text;
    bool flag;
    CLI::Option* option;
  };
  std::deque<Row> rows_;  // (stable addresses: CLI11 keeps pointers to text and flag)
};

void print_info() {
  std::cout << "Projections (spec: name[:key=value,...], angles in degrees, sizes in pixels):\n";
  for (const auto& d : projection_catalog()) {
    std::cout << "\n  " << d.name << " - " << d.summary << "\n";
    for (const auto& p : d.params) {
      std::ostringstream range;
      if (p.type == ParamType::Choice) {
        range << p.choices;
      } else if (p.type == ParamType::Text) {
        range << "text";
      } else {
        range << (p.lo_open ? "(" : "[") << p.lo << ", " << p.hi << (p.hi_open ? ")" : "]");
      }
      std::cout << "      " << p.key << "=" << (*p.default_text ? p.default_text : "<derived>")
                << "  " << range.str() << "  " << p.help << "\n";
    }
  }
  std::cout << "\nInterpolators: nearest, bilinear, bicubic (Keys a=-0.5, default), lanczos3; bicubic-dering and\n"
               "lanczos3-dering clamp to the 2x2 taps around each sample (no ringing at sharp edges, e.g. around an\n"
               "HDR sun)\n"
               "Rotation: --yaw (positive looks right), --pitch (positive looks up), --roll "
               "(positive turns the view clockwise); applied roll, then pitch, then yaw.\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"panoproj: convert images between panoramic, fisheye, pinhole, cubemap and map "
               "projections"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "panoproj " PANOPROJ_VERSION);

  ConvertJob job;
  std::string depth_text;
  std::string from_text;
  auto* convert = app.add_subcommand("convert", "convert one image (or cube-face set) to another projection");
  std::vector<std::string> files;
  convert->add_option("files", files,
                      "IN... OUT: an input image (or a cube-face pattern with {face}/{index}/{axis}) and the "
                      "output; several inputs (same size) need an output pattern with {stem} or {n}")
      ->required()
      ->expected(2, -1);
  convert->add_option("--from", from_text,
                      "source projection spec (default: 2:1 image = equirect; face pattern = "
                      "cubemap:layout=files)");
  convert->add_option("--to", job.to, "target projection spec, e.g. fisheye:fov=180")->required();
  const TableOptions convert_options(convert, kUseConvert | kUseFiles);
  convert->add_option("--depth", depth_text, "output samples: keep|uint8|uint16|half|float");
  convert->add_flag("--overwrite", job.write.overwrite, "replace an existing output");
  std::string subsampling_text = "420";
  convert->add_option("--quality", job.write.quality, "JPEG output quality, 1 to 100 (default 95)");
  convert->add_option("--subsampling", subsampling_text,
                      "JPEG output chroma: 420 (default: half width and height), 422 (half width) or 444 (full)");
  bool no_metadata = false;
  convert->add_flag("--no-metadata", no_metadata,
                    "write no metadata (default: the input's EXIF, ICC profile ..., less orientation, size and thumbnail)");
  bool quiet = false, verbose = false;
  convert->add_flag("-q,--quiet", quiet, "print nothing on success");
  convert->add_flag("-v,--verbose", verbose, "let image libraries print their own warnings");

  MapsJob maps_job;
  std::string maps_source_size, maps_convention = "opencv";
  auto* maps = app.add_subcommand("maps", "write the source-coordinate map of a conversion (float x, y)");
  maps->add_option("output", maps_job.output, "map file: .exr or .tif (2 float channels: x, y)")->required();
  maps->add_option("--from", maps_job.from, "source projection spec")->required();
  maps->add_option("--source-size", maps_source_size, "source image size WxH")->required();
  maps->add_option("--to", maps_job.to, "target projection spec")->required();
  const TableOptions maps_options(maps, kUseMaps);
  maps->add_option("--convention", maps_convention,
                   "opencv (default: centres at integers, -1 where no source, for cv::remap) | "
                   "panoproj (centres at i + 0.5, NaN where no source)");
  maps->add_flag("--overwrite", maps_job.write.overwrite, "replace an existing output");

  TilesJob tiles_job;
  std::string tiles_viewer = "pannellum", tiles_from;
  bool tiles_quiet = false;
  auto* tiles = app.add_subcommand("tiles", "write a multires cube tile pyramid for a web viewer (Pannellum, Marzipano)");
  tiles->add_option("input", tiles_job.input, "the panorama (default projection as for convert: 2:1 = equirect, Photo Sphere metadata)")->required();
  tiles->add_option("output", tiles_job.output, "the folder to make (tiles, config.json, index.html, preview)")->required();
  tiles->add_option("--viewer", tiles_viewer, "pannellum (default) | marzipano: directory layout, names, config and page");
  tiles->add_option("--from", tiles_from, "source projection spec (default as convert infers it)");
  tiles->add_option("--tile", tiles_job.tile, "tile size in pixels (default 512)");
  tiles->add_option("--levels", tiles_job.levels, "levels to keep from the top (default: all, down to one tile a face)");
  tiles->add_option("--cube-size", tiles_job.cube_size,
                    "the top level's face size (default: the source's resolution; marzipano: tile x 2^k)");
  tiles->add_option("--format", tiles_job.format, "jpg (default) | png");
  tiles->add_option("--quality", tiles_job.write.quality, "JPEG quality, 1 to 100 (default 95)");
  tiles->add_option("--preview", tiles_job.preview,
                    "fallback face size (pannellum, default 1024) or preview face size (marzipano, default <= 256)");
  tiles->add_option("--script-url", tiles_job.script_url,
                    "folder index.html loads the viewer's script from (default: the npm package on jsDelivr)");
  const TableOptions tiles_options(tiles, kUseTiles);
  tiles->add_flag("--overwrite", tiles_job.write.overwrite, "replace an existing output folder");
  tiles->add_flag("-q,--quiet", tiles_quiet, "print nothing on success");

  ViewsJob views_job;
  std::vector<std::string> views_files;
  std::string views_from;
  bool views_quiet = false;
  auto* views = app.add_subcommand("views", "split panoramas into perspective views with COLMAP and nerfstudio cameras");
  views->add_option("files", views_files, "panoramas (one size and projection; each a frame), then the folder to make")
      ->required()->expected(2, -1);
  views->add_option("--rig", views_job.rig,
                    "cube (default) | ring:n=8,fov=90,pitch=0[,vfov=,yaw=] | A+B | @rig.yaml (views: name, yaw, pitch, "
                    "roll, hfov, vfov, size)");
  views->add_option("--from", views_from, "source projection spec (default as convert infers it)");
  views->add_option("--format", views_job.format, "jpg (default) | png");
  views->add_option("--layout", views_job.layout,
                    "flat (default: images/{stem}_{view}) | folders (images/{view}/{stem} and rig_config.json for "
                    "COLMAP's rig_configurator)");
  views->add_option("--quality", views_job.write.quality, "JPEG quality, 1 to 100 (default 95)");
  const TableOptions views_options(views, kUseViews);
  views->add_flag("--overwrite", views_job.write.overwrite, "replace an existing output folder");
  views->add_flag("-q,--quiet", views_quiet, "print nothing on success");

  SweepSetup sweep;
  std::string acc_scene = "chart", acc_from = "equirect", acc_from_size = "4096x2048", acc_to,
              acc_type = "uint8", acc_interp = "nearest,bilinear,bicubic,lanczos3", acc_antialias = "off,auto,mip,4",
              acc_engine = "simd,reference", acc_decode = "memory", acc_csv, acc_json, acc_plot;
  bool acc_overwrite = false;
  auto* accuracy = app.add_subcommand(
      "accuracy", "measure error against time: a synthetic scene converted with each option, against its truth");
  accuracy->add_option("--scene", acc_scene, "waves | chart (default) | gradient | sun (HDR: use --type float)");
  accuracy->add_option("--from", acc_from, "source projection spec (default equirect)");
  accuracy->add_option("--from-size", acc_from_size, "source size WxH (default 4096x2048)");
  accuracy->add_option("--to", acc_to, "target projection spec")->required();
  const TableOptions accuracy_options(accuracy, kUseAccuracy);
  accuracy->add_option("--type", acc_type, "samples: uint8 (default) | uint16 | half | float");
  accuracy->add_option("--interp", acc_interp, "kernels to sweep (default nearest,bilinear,bicubic,lanczos3)");
  accuracy->add_option("--antialias", acc_antialias, "antialiasing to sweep (default off,auto,mip,4)");
  accuracy->add_option("--engine", acc_engine,
                       "engines to sweep: simd (float geometry where within 1/1024 px), reference (exact double, "
                       "no antialiasing); default both");
  accuracy->add_option("--decode-scale", acc_decode,
                       "sources to sweep: memory (default: the rendered source as is), or the source as a file "
                       "decoded at 1, 2, 4, 8 (1/N scale, inside the timing), e.g. memory,1,4: a JPEG (quality 95, "
                       "4:2:0) for --type uint8, a Radiance HDR for --type float");
  accuracy->add_option("--runs", sweep.runs, "timed runs per option, median reported (default 5)");
  accuracy->add_option("--truth-supersample", sweep.truth_supersample,
                       "rays per axis of each truth pixel (default 8: its area average)");
  accuracy->add_option("--csv", acc_csv, "also write the results as CSV");
  accuracy->add_option("--json", acc_json, "also write the results as JSON");
  accuracy->add_option("--plot", acc_plot, "also write PSNR against time, Pareto front marked (PNG)");
  accuracy->add_flag("--overwrite", acc_overwrite, "replace existing outputs");

  auto* stability = app.add_subcommand(
      "stability", "round-trip every projection at its extremes and singular points; exit 1 if a bound fails");

  auto* info = app.add_subcommand("info", "list projections, their parameters and defaults");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, exit 1 (CLI11's own codes are 100 and up).
    std::fprintf(stderr, "panoproj: error: %s (see panoproj %s--help)\n", one_line(e.what()).c_str(),
                 argc > 1 && argv[1][0] != '-' ? (std::string(argv[1]) + " ").c_str() : "");
    return 1;
  }
  install_signal_cleanup();

  try {
    if (info->parsed()) {
      print_info();
      return 0;
    }
    if (stability->parsed()) {
      std::vector<StabilityResult> results;
      for (const StabilityCase& c : stability_cases()) results.push_back(run_stability_case(c));
      std::printf("%s", stability_table(results).c_str());
      const auto failed = std::count_if(results.begin(), results.end(), [](const auto& r) { return !r.pass(); });
      std::printf("\n%zu cases, %lld outside their bounds\n", results.size(), static_cast<long long>(failed));
      return failed ? 1 : 0;
    }
    if (accuracy->parsed()) {
      // Every parameter and output path is checked before the sweep.
      ConvertOptions o;
      accuracy_options.apply(o);
      sweep.threads = o.threads;
      if (sweep.runs < 1 || sweep.runs > 1000)
        throw Error("runs: " + std::to_string(sweep.runs) + " (expected 1 to 1000)");
      if (sweep.truth_supersample < 1 || sweep.truth_supersample > 64)
        throw Error("truth-supersample: " + std::to_string(sweep.truth_supersample) + " (expected 1 to 64)");
      for (const std::string* path : {&acc_csv, &acc_json, &acc_plot})
        if (!path->empty()) check_output_path(*path, acc_overwrite);
      require_distinct_outputs({{option_text("csv"), acc_csv}, {option_text("json"), acc_json}, {option_text("plot"), acc_plot}});
      const ConversionGeometry geometry =
          make_geometry(parse_size(acc_from_size), parse_spec(acc_from), parse_spec(acc_to), o);
      sweep.scene = parse_scene(acc_scene);
      const auto type = parse_depth(acc_type);
      if (!type) throw Error("type: keep (expected uint8, uint16, half or float)");
      sweep.type = *type;
      const auto options = sweep_options(parse_list(acc_interp, [](std::string_view t) { return parse_interp(t); }),
                                         parse_list(acc_antialias, parse_antialias),
                                         parse_list(acc_engine, [](std::string_view t) { return parse_engine(t); }),
                                         parse_list(acc_decode, [](std::string_view t) {
                                           if (t == "memory") return 0;
                                           if (t == "1" || t == "2" || t == "4" || t == "8") return t[0] - '0';
                                           throw Error("--decode-scale: " + std::string(t) +
                                                       " (expected memory, 1, 2, 4 or 8, comma-separated)");
                                         }));
      require_mono(geometry, "accuracy");
      const Size fs = size_of(geometry.source), ts = size_of(geometry.target);
      const std::string about = std::string("scene ") + acc_scene + ", " + acc_from + " " + std::to_string(fs.width) + "x" +
                                std::to_string(fs.height) + " -> " + acc_to + " " + std::to_string(ts.width) + "x" +
                                std::to_string(ts.height) + ", " + acc_type + ", " +
                                std::to_string(resolve_threads(sweep.threads)) + " threads, median of " +
                                std::to_string(sweep.runs) + " runs, SIMD " + simd_target();
      // The scene, the truth and an output per option in flight (4 channels at most).
      require_memory("the accuracy sweep", add_bytes(image_bytes(fs, 4, bytes_of(sweep.type)), image_bytes(ts, 12, bytes_of(sweep.type))), o.memory_limit);
      const auto results = run_sweep(geometry.source, geometry.target, geometry.rotation, sweep, options);
      std::printf("%s\n\n%s", about.c_str(), sweep_table(results).c_str());
      if (!acc_csv.empty()) write_text(sweep_csv(results), acc_csv, acc_overwrite);
      if (!acc_json.empty()) write_text(sweep_json(results, about), acc_json, acc_overwrite);
      if (!acc_plot.empty()) {
        WriteOptions w;
        w.overwrite = acc_overwrite;
        write_image(plot_sweep(results, about), acc_plot, w);
      }
      return 0;
    }
    if (tiles->parsed()) {
      tiles_job.viewer = parse_viewer(tiles_viewer);
      if (!tiles_from.empty()) tiles_job.from = tiles_from;
      tiles_options.apply(tiles_job.options);
      QuietStderr hold(true);
      ProgressBar bar(hold.fd(), !tiles_quiet);
      const TilesReport r = run_tiles(tiles_job, [&](double f) { bar.update(f); });
      if (tiles_quiet) return 0;
      std::string sizes;
      for (const TileLevel& l : r.pyramid.levels) sizes += (sizes.empty() ? "" : ", ") + std::to_string(l.size);
      std::printf("\r%s (%s, %s) -> %s: %s, %zu levels (faces %s px), %lld tiles of %lld px written",
                  tiles_job.input.c_str(), size_text(r.source_size).c_str(), r.from.c_str(), tiles_job.output.c_str(),
                  name_of(r.pyramid.viewer), r.pyramid.levels.size(), sizes.c_str(), static_cast<long long>(r.written),
                  static_cast<long long>(r.pyramid.tile));
      if (r.empty) std::printf(" (%lld empty, not written)", static_cast<long long>(r.empty));
      std::printf(", %.3f s\n", r.seconds);
      for (const std::string& n : r.notes) std::printf("  %s\n", n.c_str());
      return 0;
    }
    if (views->parsed()) {
      views_job.output = views_files.back();
      views_job.inputs.assign(views_files.begin(), views_files.end() - 1);
      if (!views_from.empty()) views_job.from = views_from;
      views_options.apply(views_job.options);
      QuietStderr hold(true);
      ProgressBar bar(hold.fd(), !views_quiet);
      const ViewsReport r = run_views(views_job, [&](double f) { bar.update(f); });
      if (views_quiet) return 0;
      std::string sizes;
      for (const ViewCamera& c : r.views)
        if (sizes.find(size_text(c.size)) == std::string::npos) sizes += (sizes.empty() ? "" : ", ") + size_text(c.size);
      std::printf("\r%zu panorama%s (%s, %s) -> %s: %zu views each (%s), %lld images%s, COLMAP model in sparse/0, "
                  "transforms.json, %.3f s\n",
                  r.stems.size(), r.stems.size() == 1 ? "" : "s", size_text(r.source_size).c_str(), r.from.c_str(),
                  views_job.output.c_str(), r.views.size(), sizes.c_str(), static_cast<long long>(r.images),
                  r.masks ? " with masks" : "", r.seconds);
      if (r.empty) std::printf("  %lld views see no part of the panorama (written black, masked)\n", static_cast<long long>(r.empty));
      return 0;
    }
    if (maps->parsed()) {
      maps_job.source_size = parse_size(maps_source_size);
      maps_options.apply(maps_job.options);
      if (maps_convention != "opencv" && maps_convention != "panoproj")
        throw Error("convention: " + maps_convention + " (expected opencv or panoproj)");
      maps_job.convention = maps_convention == "opencv" ? MapConvention::OpenCV : MapConvention::Panoproj;
      const Size out = run_maps(maps_job);
      std::printf("%s: %lldx%lld map (x, y float32, %s convention)\n", maps_job.output.c_str(),
                  static_cast<long long>(out.width), static_cast<long long>(out.height), maps_convention.c_str());
      return 0;
    }
    if (!from_text.empty()) job.from = from_text;
    convert_options.apply(job.options);
    job.write.type = parse_depth(depth_text);
    job.write.subsampling = parse_subsampling(subsampling_text);
    check_write_options(job.write);
    job.keep_metadata = !no_metadata;
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
          const std::string decoded =
              r.source_format.empty() ? "" : " (" + r.source_format + (r.decode_scale > 1 ? " at 1/" + std::to_string(r.decode_scale) + " scale" : "") + ")";
          std::printf("\r%s (%s, %s) -> %s (%s, %s): %.3f s, %s, antialias %s, %s engine (%s), %d threads, "
                      "decoded %.0f%% of the source%s%s\n",
                      r.input.c_str(), dims(r.input_size, r.input_faces).c_str(), r.from.c_str(),
                      r.output.c_str(), dims(r.output_size, r.output_faces).c_str(), r.to.c_str(),
                      r.seconds, name_of(job.options.interp), name_of(antialias_of(job.options)).c_str(), name_of(job.options.engine), simd_target(),
                      resolve_threads(job.options.threads), 100 * r.read_fraction, decoded.c_str(),
                      r.stereo.empty() ? "" : (", " + r.stereo).c_str());
          std::fflush(stdout);
        },
        [&](double f) { bar.update(f); });
    return 0;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "panoproj: error: out of memory (ask for a smaller size, or set --memory-limit to be "
                         "refused before the work starts)\n");
    return 1;
  } catch (const InternalError& e) {
    std::fprintf(stderr, "panoproj: %s (a bug: please report it with the command line)\n", one_line(e.what()).c_str());
    return 70;  // EX_SOFTWARE
  } catch (const std::exception& e) {
    std::fprintf(stderr, "panoproj: error: %s\n", one_line(e.what()).c_str());
    return 1;
  }
}
