// The maps job: a conversion's source-coordinate map written as a 2-channel float image
// (channels x, y; maps.hpp), for cv::remap and the like: .npy (NumPy, any OpenCV), .exr, .tif.
#include <cstdio>
#include <filesystem>

#include "io/formats.hpp"
#include "io/npy.hpp"
#include "jobs/list.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/maps.hpp"

namespace panoproj {
namespace {

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows = job_rows(
      {
          {"output", OptionType::Path, 0, "None",
           "map file: .npy (np.load gives cv2.remap's map), .exr or .tif (2 float channels: x, y)",
           nullptr, nullptr, nullptr, kPositional | kRequired},
          {"src", OptionType::Text, 0, "None", "source projection spec", nullptr, nullptr, "from",
           kRequired},
          {"source_size", OptionType::Text, 0, "None", "source image size WxH", nullptr, nullptr,
           nullptr, kRequired},
          {"dst", OptionType::Text, 0, "None", "target projection spec", nullptr, nullptr, "to",
           kRequired},
      },
      kUseMaps,
      {{"convention", OptionType::Text, 0, "'opencv'",
        "opencv (default: centres at integers, -1 where no source, for cv::remap) | panoproj "
        "(centres at i + 0.5, NaN "
        "where no source)",
        nullptr, "opencv|panoproj"},
       write_option("overwrite"),
       command_option("quiet")});
  return rows;
}

MapConvention convention_of(const std::string& text) {
  if (text == "opencv") return MapConvention::OpenCV;
  if (text == "panoproj") return MapConvention::Panoproj;
  throw Error("convention: " + text + " (expected opencv or panoproj)");
}

Report run(const Arguments& args, const JobEvents& events) {
  const std::string output = args.text("output");
  const MapConvention convention = convention_of(args.text("convention"));
  const ConvertOptions options = args.options();
  const WriteOptions write = args.write();
  const bool npy = std::filesystem::path(output).extension() == ".npy";
  if (!npy && !format_of_path(output).float_channels) {
    std::string holding = ".npy";
    for (const ImageFormat* f : image_formats())
      if (f->float_channels) holding += ", " + std::string(f->extensions[0]);
    throw Error("output " + output + " cannot hold float maps (use " + holding + ")");
  }
  check_output_path(output, write.overwrite);
  const ConversionGeometry geometry =
      make_geometry(parse_size(args.text("source_size")), parse_spec(args.text("src")),
                    parse_spec(args.text("dst")), options);
  require_mono(geometry, "maps");
  require_no_correction(geometry, "maps", "a map holds positions (drop them)");
  // The map (2 floats a pixel) and its encoded copy.
  const Size out = size_of(geometry.target);
  if (!npy) check_writable_size(output, out);
  require_memory("map " + size_text(out), image_bytes(out, 4, sizeof(float)), options.memory_limit);
  const Image map =
      build_map(geometry.source, geometry.target, geometry.rotation, convention, options.threads);
  WriteOptions w = write;
  w.channel_names = {"x", "y"};
  npy ? write_bytes(npy_bytes(map), output, w.overwrite) : write_image(map, output, w);
  if (events.line)
    events.line(output + ": " + size_text(map.size()) + " map (x, y float32, " +
                args.text("convention") + " convention)");
  return {{"output", {output}}, {"size", report_size(map.size())}};
}

}  // namespace

const JobDef maps_job{
    .name = "maps",
    .summary = "write the source-coordinate map of a conversion (float x, y)",
    .python = nullptr,
    .rows = rows,
    .run = run,
};

}  // namespace panoproj
