// The accuracy job: a synthetic scene converted with each option, against its truth, timed
// (diagnostics/accuracy.hpp); the command only.
#include <tuple>

#include "jobs/list.hpp"
#include "panoproj/diagnostics/accuracy.hpp"
#include "panoproj/diagnostics/fitted_inverse.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/spec.hpp"

namespace panoproj {
namespace {

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows = job_rows(
      {
          {"scene", OptionType::Text, 0, "'chart'",
           "waves | chart (default) | gradient | sun (HDR: use --type float)"},
          {"src", OptionType::Text, 0, "'equirect'", "source projection spec (default equirect)",
           nullptr, nullptr, "from"},
          {"src_size", OptionType::Text, 0, "'4096x2048'", "source size WxH (default 4096x2048)",
           nullptr, nullptr, "from-size"},
          {"dst", OptionType::Text, 0, "None", "target projection spec", nullptr, nullptr, "to",
           kRequired},
      },
      kUseAccuracy,
      {
          {"type", OptionType::Text, 0, "'uint8'",
           "samples: uint8 (default) | uint16 | half | float"},
          {"interp", OptionType::Text, 0, "'nearest,bilinear,bicubic,lanczos3'",
           "kernels to sweep (default nearest,bilinear,bicubic,lanczos3)"},
          {"antialias", OptionType::Text, 0, "'off,auto,mip,4'",
           "antialiasing to sweep (default off,auto,mip,4)"},
          {"engine", OptionType::Text, 0, "'simd,reference'",
           "engines to sweep: simd (float geometry where within 1/1024 px), reference (exact "
           "double, no "
           "antialiasing); default both"},
          {"decode_scale", OptionType::Text, 0, "'memory'",
           "sources to sweep: memory (default: the rendered source as is), or the source as a file "
           "decoded at 1, 2, "
           "4, 8 (1/N scale, inside the timing), e.g. memory,1,4: a JPEG (quality 95, 4:2:0) for "
           "--type uint8, a "
           "Radiance HDR for --type float"},
          {"runs", OptionType::Integer, 0, "5",
           "timed runs per option, median reported (default 5)"},
          {"truth_supersample", OptionType::Integer, 0, "8",
           "rays per axis of each truth pixel (default 8: its area average)"},
          {"csv", OptionType::Text, 0, "None", "also write the results as CSV"},
          {"json", OptionType::Text, 0, "None", "also write the results as JSON"},
          {"plot", OptionType::Text, 0, "None",
           "also write PSNR against time, Pareto front marked (PNG)"},
          with_help(write_option("overwrite"), "replace existing outputs"),
      });
  return rows;
}

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

int parse_decode(std::string_view t) {
  if (t == "memory") return 0;
  if (t == "1" || t == "2" || t == "4" || t == "8") return t[0] - '0';
  throw Error("--decode-scale: " + std::string(t) +
              " (expected memory, 1, 2, 4 or 8, comma-separated)");
}

PixelType parse_type(const std::string& text) {
  for (PixelType t : {PixelType::U8, PixelType::U16, PixelType::F16, PixelType::F32})
    if (text == name_of(t)) return t;
  throw Error("type: " + text + " (expected uint8, uint16, half or float)");
}

std::vector<SweepOption> options_of(const Arguments& a) {
  return sweep_options(
      parse_list(a.text("interp"), [](std::string_view t) { return parse_interp(t); }),
      parse_list(a.text("antialias"), parse_antialias),
      parse_list(a.text("engine"), [](std::string_view t) { return parse_engine(t); }),
      parse_list(a.text("decode_scale"), parse_decode));
}

// Every parameter and output path is checked before the sweep.
Report run(const Arguments& a, const JobEvents& events) {
  const ConvertOptions o = a.options();
  SweepSetup sweep;
  sweep.threads = o.threads;
  const int64_t runs = a.integer("runs"), truth = a.integer("truth_supersample");
  if (runs < 1 || runs > 1000)
    throw Error("runs: " + std::to_string(runs) + " (expected 1 to 1000)");
  if (truth < 1 || truth > 64)
    throw Error("truth-supersample: " + std::to_string(truth) + " (expected 1 to 64)");
  sweep.runs = static_cast<int>(runs), sweep.truth_supersample = static_cast<int>(truth);
  const bool overwrite = a.flag("overwrite");
  const std::string csv = a.text("csv"), json = a.text("json"), plot = a.text("plot");
  for (const std::string* path : {&csv, &json, &plot})
    if (!path->empty()) check_output_path(*path, overwrite);
  require_distinct_outputs(
      {{option_text("csv"), csv}, {option_text("json"), json}, {option_text("plot"), plot}});
  const ConversionGeometry geometry = make_geometry(
      parse_size(a.text("src_size")), parse_spec(a.text("src")), parse_spec(a.text("dst")), o);
  sweep.scene = parse_scene(a.text("scene"));
  sweep.type = parse_type(a.text("type"));
  const std::vector<SweepOption> options = options_of(a);
  require_mono(geometry, "accuracy");
  require_no_correction(geometry, "accuracy", "it measures positions (drop them)");
  const Size fs = size_of(geometry.source), ts = size_of(geometry.target);
  const std::string about = "scene " + a.text("scene") + ", " + a.text("src") + " " +
                            size_text(fs) + " -> " + a.text("dst") + " " + size_text(ts) + ", " +
                            a.text("type") + ", " + std::to_string(resolve_threads(sweep.threads)) +
                            " threads, median of " + std::to_string(sweep.runs) + " runs, SIMD " +
                            simd_target();
  // The scene, the truth and an output per option in flight (4 channels at most).
  require_memory("the accuracy sweep",
                 add_bytes(image_bytes(fs, 4, bytes_of(sweep.type)),
                           image_bytes(ts, 12, bytes_of(sweep.type))),
                 o.memory_limit);
  const auto results =
      run_sweep(geometry.source, geometry.target, geometry.rotation, sweep, options);
  std::string table = sweep_table(results);
  if (!table.empty() && table.back() == '\n') table.pop_back();
  // A calibration's fitted inverse, measured against the law panoproj inverts exactly.
  std::string fitted;
  for (const auto& [side, text, p] : {std::tuple{"source", a.text("src"), &geometry.source},
                                      std::tuple{"target", a.text("dst"), &geometry.target}})
    if (const auto f = fitted_inverse(parse_spec(text), *p))
      fitted += std::string("\nThe ") + side + ": " + f->text();
  if (events.line) events.line(about + "\n\n" + table + fitted);
  if (!csv.empty()) write_text(sweep_csv(results), csv, overwrite);
  if (!json.empty()) write_text(sweep_json(results, about), json, overwrite);
  if (!plot.empty()) {
    WriteOptions w;
    w.overwrite = overwrite;
    write_image(plot_sweep(results, about), plot, w);
  }
  return {{"about", {about}}, {"table", {table}}, {"fitted_inverse", {fitted}}};
}

}  // namespace

const JobDef accuracy_job{
    .name = "accuracy",
    .summary =
        "measure error against time: a synthetic scene converted with each option, against its "
        "truth",
    .python = nullptr,
    .rows = rows,
    .run = run,
};

}  // namespace panoproj
