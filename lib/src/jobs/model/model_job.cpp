// The model job: a COLMAP model read, checked and written back as text or binary (as COLMAP's
// model_converter; io/colmap/model.hpp).
#include "io/atomic_output.hpp"
#include "io/colmap/model.hpp"
#include "jobs/list.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {
namespace {

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows = job_rows(
      {
          {"model", OptionType::Path, 0, "None",
           "a COLMAP model folder (e.g. sparse/0: cameras, images, points3D, rigs and frames as "
           ".bin or .txt)",
           nullptr, nullptr, nullptr, kPositional | kRequired},
          {"out_dir", OptionType::Path, 0, "None", "the folder to make", nullptr, nullptr, nullptr,
           kPositional | kRequired},
          {"format", OptionType::Text, 0, "'txt'",
           "txt (default) | bin: COLMAP's text or binary files", nullptr, "txt|bin"},
      },
      0,
      {with_help(write_option("overwrite"),
                 "replace an existing output folder (one panoproj made)"),
       command_option("quiet")});
  return rows;
}

Report run(const Arguments& args, const JobEvents& events) {
  const std::string in = args.text("model"), out = args.text("out_dir"),
                    format = args.text("format");
  if (format != "txt" && format != "bin")
    throw Error("format: " + format + " (expected txt or bin)");
  const WriteOptions write = args.write();
  OutputFolder folder(out, write.overwrite, std::vector<std::string>{in}, "model");
  // (Each file is held once as read and once parsed.)
  const colmap::Model m = colmap::read_model(in, static_cast<int64_t>(memory_budget(0) / 4));
  for (const colmap::File& f : colmap::model_files(m, format == "bin", ""))
    folder.writer().write(f.path, f.bytes);
  folder.commit();
  if (events.line)
    events.line(in + " -> " + out + " (" + format + "): " + std::to_string(m.cameras.size()) +
                " cameras, " + std::to_string(m.images.size()) + " images, " +
                std::to_string(m.points.size()) + " points3D" +
                (m.rigs_and_frames ? ", " + std::to_string(m.rigs.size()) + " rigs, " +
                                         std::to_string(m.frames.size()) + " frames"
                                   : ", no rigs or frames (COLMAP 3.x)"));
  return {{"cameras", {static_cast<int64_t>(m.cameras.size())}},
          {"images", {static_cast<int64_t>(m.images.size())}},
          {"points3D", {static_cast<int64_t>(m.points.size())}},
          {"rigs", {static_cast<int64_t>(m.rigs.size())}},
          {"frames", {static_cast<int64_t>(m.frames.size())}},
          {"rigs_and_frames", {m.rigs_and_frames}}};
}

}  // namespace

const JobDef model_job{
    .name = "model",
    .summary = "read a COLMAP model, check it, and write it as text or binary",
    .python =
        R"(Reads the COLMAP model in the folder ``model`` (``cameras``, ``images``, ``points3D`` and,
from COLMAP 3.12, ``rigs`` and ``frames``; ``.bin`` or ``.txt``), checks every reference and
number in it, and writes it into the new folder ``out_dir`` as ``format`` (``"txt"`` or
``"bin"``), every value as read (as ``panoproj model``; COLMAP's model_converter). A model
without rigs and frames (COLMAP 3.x) is written without them. Returns the counts.)",
    .rows = rows,
    .run = run,
    .python_name = "convert_model",
};

}  // namespace panoproj
