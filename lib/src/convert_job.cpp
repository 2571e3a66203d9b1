#include "panoproj/convert_job.hpp"

#include <chrono>
#include <filesystem>
#include <vector>

#include "panoproj/error.hpp"

namespace panoproj {
namespace fs = std::filesystem;
namespace {

bool is_cube_files(const ProjectionSpec& s) {
  return s.kind() == Kind::Cubemap && s.choice("layout") == "files";
}

std::vector<std::string> expand(const std::string& path, bool faces) {
  std::vector<std::string> out;
  if (!faces) return {path};
  for (int f = 0; f < 6; ++f) out.push_back(face_path(path, f));
  return out;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

}  // namespace

ProjectionSpec infer_source_spec(const std::optional<std::string>& from, const std::string& input,
                                 Size size) {
  if (from) return parse_spec(*from);
  if (is_face_pattern(input)) return parse_spec("cubemap:layout=files");
  if (size.width == 2 * size.height) return parse_spec("equirect");
  throw Error("cannot tell the projection of " + input + " (" + std::to_string(size.width) + "x" +
              std::to_string(size.height) + " is not a 2:1 equirect): give --from SPEC");
}

ConvertReport run_convert(const ConvertJob& job) {
  const ProjectionSpec to = parse_spec(job.to);
  const bool in_faces = is_face_pattern(job.input), out_faces = is_cube_files(to);
  if (out_faces != is_face_pattern(job.output))
    throw Error(out_faces ? "output " + job.output +
                                " needs {face} or {index} for cubemap:layout=files"
                          : "output " + job.output +
                                " has {face}/{index} but --to is not cubemap:layout=files");
  // The output must not be an input, checked before reading anything.
  for (const auto& o : expand(job.output, out_faces))
    for (const auto& i : expand(job.input, in_faces))
      if (same_file(o, i))
        throw Error("output " + o + " is the input (choose another output path)");
  if (!job.write.overwrite)
    for (const auto& o : expand(job.output, out_faces))
      if (std::error_code ec; fs::exists(o, ec))
        throw Error("output " + o + " exists (pass --overwrite to replace it)");

  std::optional<ProjectionSpec> from;
  if (job.from) from = parse_spec(*job.from);  // early: a bad spec fails before any reading
  if (from && is_cube_files(*from) != in_faces)
    throw Error(in_faces ? "input " + job.input + " is a face pattern but --from is not "
                                                  "cubemap:layout=files"
                         : "--from cubemap:layout=files needs an input pattern with {face} or "
                           "{index}");
  const Image source = in_faces ? read_cube_faces(job.input) : read_image(job.input);
  if (!from) from = infer_source_spec(std::nullopt, job.input, source.size());

  ConvertOptions options = job.options;
  if (options.size && out_faces) {
    // For separate face files the size is one face's.
    if (options.size->width != options.size->height)
      throw Error("size " + std::to_string(options.size->width) + "x" +
                  std::to_string(options.size->height) +
                  " is not square (cube faces are square; or use face=N)");
    options.size = Size{6 * options.size->width, options.size->height};
  }
  const Plan plan = make_plan(source.size(), *from, to, options);
  const auto t0 = std::chrono::steady_clock::now();
  const Image out = fast_remap(source, plan.source, plan.target, plan.rotation, options.interp,
                               options.engine, options.threads);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (out_faces) write_cube_faces(out, job.output, job.write);
  else write_image(out, job.output, job.write);
  auto face_size = [](Size strip) { return Size{strip.height, strip.height}; };
  return {from->str(),
          to.str(),
          in_faces ? face_size(source.size()) : source.size(),
          out_faces ? face_size(out.size()) : out.size(),
          in_faces,
          out_faces,
          seconds};
}

Size run_maps(const MapsJob& job) {
  const std::string ext = fs::path(job.output).extension().string();
  if (ext != ".exr" && ext != ".tif" && ext != ".tiff")
    throw Error("output " + job.output + " cannot hold float maps (use .exr or .tif)");
  if (!job.write.overwrite && fs::exists(job.output))
    throw Error("output " + job.output + " exists (pass --overwrite to replace it)");
  const Plan plan = make_plan(job.source_size, parse_spec(job.from), parse_spec(job.to), job.options);
  const Image map = build_map(plan.source, plan.target, plan.rotation, job.convention, job.options.threads);
  WriteOptions w = job.write;
  w.channel_names = {"x", "y"};
  write_image(map, job.output, w);
  return map.size();
}

}  // namespace panoproj
