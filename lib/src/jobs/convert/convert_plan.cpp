#include "jobs/convert/convert_plan.hpp"

#include <filesystem>
#include <set>

#include "io/atomic_output.hpp"
#include "jobs/file_source.hpp"
#include "panoproj/error.hpp"
#include "panoproj/jobs.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/photo_sphere.hpp"

namespace panoproj {
namespace fs = std::filesystem;
namespace {

bool is_cube_files(const ProjectionSpec& s) {
  return s.kind() == Kind::Cubemap && s.choice("layout") == "files";
}

// A path, or the six of a face pattern in this face order.
std::vector<std::string> expand(const std::string& path, const FaceOrder* order) {
  if (!order) return {path};
  std::vector<std::string> out;
  for (int f = 0; f < 6; ++f) out.push_back(face_path(path, f, *order));
  return out;
}

std::string batch_output(const std::string& pattern, const std::string& input, size_t n) {
  std::string s = pattern;
  for (const auto& [key, value] :
       {std::pair<std::string, std::string>{"{stem}", fs::path(input).stem().string()},
        {"{n}", std::to_string(n)}})
    for (size_t at; (at = s.find(key)) != std::string::npos;) s.replace(at, key.size(), value);
  return s;
}

// The inputs' and outputs' forms, then every output path: distinct, not an input, not existing
// (unless overwrite).
void plan_paths(ConvertPlan& p) {
  const ConvertRequest& job = p.request;
  if (job.inputs.empty()) throw Error("no input given (expected one or more images)");
  p.to = parse_spec(job.to);
  if (job.from) p.from = parse_spec(*job.from);  // early: a bad spec fails before any reading
  // (A GoPro MAX's two strips are one frame.)
  p.in_pair = p.from && p.from->kind() == Kind::GoProMax && job.inputs.size() == 2;
  p.batch = job.inputs.size() > 1 && !p.in_pair;
  p.in_faces = !p.batch && is_face_pattern(job.inputs[0]), p.out_faces = is_cube_files(*p.to);
  if (p.from && p.from->kind() == Kind::GoProMax && job.inputs.size() > 2)
    throw Error(std::to_string(job.inputs.size()) + " inputs for " + option_text("from") + " " +
                p.from->str() +
                " (expected the two strips of one frame, the first stream's first; or one image of "
                "both stacked)");
  if (p.out_faces != is_face_pattern(job.output))
    throw Error(p.out_faces ? "output " + job.output +
                                  " needs {face}, {index} or {axis} for cubemap:layout=files"
                            : "output " + job.output + " has {face}/{index}/{axis} but " +
                                  option_text("to") + " is not cubemap:layout=files");
  if (p.batch) {
    if (job.output.find("{stem}") == std::string::npos &&
        job.output.find("{n}") == std::string::npos)
      throw Error("output " + job.output + " names one file for " +
                  std::to_string(job.inputs.size()) +
                  " inputs (put {stem} or {n} in it, e.g. out/{stem}.jpg)");
    for (const auto& in : job.inputs)
      if (is_face_pattern(in))
        throw Error("input " + in + " is a face pattern: cube faces convert one set at a time");
  }
  for (size_t n = 0; n < (p.in_pair ? 1 : job.inputs.size()); ++n)
    p.outputs.push_back(p.batch ? batch_output(job.output, job.inputs[n], n) : job.output);
  if (p.out_faces) p.out_order = cube_face_order(*p.to);
  if (p.from && is_cube_files(*p.from)) p.in_order = cube_face_order(*p.from);
  std::vector<std::string> files_in;
  for (const auto& o : p.outputs)
    for (const auto& f : expand(o, p.out_faces ? &p.out_order : nullptr)) p.files_out.push_back(f);
  for (const auto& i : job.inputs)
    for (const auto& f : expand(i, p.in_faces ? &p.in_order : nullptr)) files_in.push_back(f);
  // Outputs against each other by their resolved paths (x.png and ./x.png are one file).
  std::set<fs::path> resolved;
  for (const std::string& out : p.files_out) {
    if (!resolved.insert(resolved_path(out)).second)
      throw Error("output " + out + " would be written twice (make the pattern unique per input)");
    for (const auto& i : files_in)
      if (same_file(out, i))
        throw Error("output " + out + " is the input (choose another output path)");
    check_output_path(out, job.write.overwrite, p.batch || p.out_faces);  // (MadeFolders)
  }
  if (p.from && is_cube_files(*p.from) != p.in_faces)
    throw Error(
        p.in_faces
            ? "input " + job.inputs[0] + " is a face pattern but " + option_text("from") +
                  " is not cubemap:layout=files"
            : option_text("from") +
                  " cubemap:layout=files needs an input pattern with {face}, {index} or {axis}");
}

// Every header, read once before any work (a batch shares one geometry); a face set's come with
// its pixels.
void plan_headers(ConvertPlan& p) {
  const ConvertRequest& job = p.request;
  if (p.held()) {
    p.faces = p.in_pair ? read_strip_pair(job.inputs[0], job.inputs[1], p.options.memory_limit)
                        : read_cube_faces(job.inputs[0], p.options.memory_limit, p.in_order);
    p.frame = p.faces->size(), p.channels = p.faces->channels(), p.type = p.faces->type();
    return;
  }
  for (const auto& in : job.inputs) p.infos.push_back(read_image_info(in));
  const Size first = p.infos[0].size;
  for (size_t n = 0; n < p.infos.size(); ++n)
    if (p.infos[n].size != first)
      throw Error("input " + job.inputs[n] + " is " + size_text(p.infos[n].size) + " but " +
                  job.inputs[0] + " is " + size_text(first) + " (a batch shares one size)");
  p.frame = first, p.channels = p.infos[0].channels, p.type = p.infos[0].type;
}

// The geometry from the first input's header and the decode scale: a JPEG source the view samples
// at under half its resolution everywhere decodes at 1/2, 1/4 or 1/8 (DCT scaling); the
// conversion, its antialiasing and its footprint are planned on that frame (the same field: the
// scale divides the sides).
void plan_geometry(ConvertPlan& p) {
  const ConvertRequest& job = p.request;
  if (p.options.size && p.out_faces) {  // for separate face files the size is one face's
    if (p.options.size->width != p.options.size->height)
      throw Error("size " + size_text(*p.options.size) +
                  " is not square (cube faces are square; or use face=N)");
    p.options.size = Size{6 * p.options.size->width, p.options.size->height};
  }
  // (The Photo Sphere packet, read once, gives the projection and the pose unless --from does.)
  const auto ps = job.from || p.held() ? std::nullopt : read_photo_sphere(job.inputs[0]);
  if (!p.from) p.from = infer_source_spec(std::nullopt, job.inputs[0], p.frame, ps);
  p.geometry = make_geometry(p.frame, *p.from, *p.to, p.options);
  p.from_text = level_by_pose(*p.geometry, ps, p.from->str());
  bool scalable = !p.held();  // every input decodes at 1/2, 1/4, 1/8 (JPEG)
  for (const ImageInfo& i : p.infos) scalable = scalable && i.scalable;
  const int scale = p.options.decode_scale;
  const std::string refused = option_text("decode-scale") + " " + std::to_string(scale);
  if (scale > 1 && !scalable)
    throw Error(refused + ": only JPEG sources decode at a scale (" + job.inputs[0] +
                " is not one; use auto or 1)");
  if (scale > 1 && (p.frame.width % scale != 0 || p.frame.height % scale != 0))
    throw Error(refused + ": the source's " + size_text(p.frame) + " is not a multiple of " +
                std::to_string(scale) + " (use auto or a divisor)");
  if (scale > 1 && p.geometry->stereo.any())
    throw Error(refused + ": stereo sources decode whole (use auto or 1)");
  p.scale = scale != 0 ? scale
            : scalable && !p.geometry->stereo.any()
                ? coarsest_decode_scale(*p.geometry, finest_source_step(*p.geometry, 4))
                : 1;
  if (p.scale > 1)
    p.geometry->source =
        rescaled(p.geometry->source, {p.frame.width / p.scale, p.frame.height / p.scale});
  // Sizes the output formats cannot hold stop before any work.
  const Size out = p.geometry->target_frame();
  for (const auto& o : p.files_out)
    check_writable_size(o, p.out_faces ? Size{out.height, out.height} : out);
}

// The memory, and the converter: the map is kept (built once for the footprint, the first image
// and the rest of a batch) while it fits kMapCacheBudget, and a batch keeps the taps the first
// frame plans too; beyond, memory stays source + output + tile buffers and the map is made twice
// (footprint, then conversion) and again per frame. A job over the budget stops before any work.
void plan_memory(ConvertPlan& p) {
  const Size out = p.geometry->target_frame();
  const uint64_t map_bytes = image_bytes(out, 1, kept_bytes_per_pixel(*p.geometry));
  const bool keep = map_bytes <= static_cast<uint64_t>(kMapCacheBudget);
  const PixelType out_type = p.request.write.type.value_or(p.type);
  const int out_channels = output_channels(p.channels, p.options);
  ConvertMemory& m = p.memory;
  m.map = keep ? map_bytes : 0;
  m.converted = out_type == p.type ? 0 : image_bytes(out, p.channels + 1, bytes_of(out_type));
  m.output = image_bytes(out, out_channels, bytes_of(p.type));
  m.written = image_bytes(out, out_channels, bytes_of(out_type));
  require_job_memory(*p.geometry, p.channels, p.type, p.options, add_bytes(m.map, m.converted));
  const auto t0 = std::chrono::steady_clock::now();
  p.converter.emplace(*p.geometry, p.options,
                      !keep     ? Keep::Nothing
                      : p.batch ? Keep::MapsAndTaps
                                : Keep::Maps);
  p.need = p.converter->source_footprint();
  p.map_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.window =
      image_bytes({p.need.x1 - p.need.x0, p.need.y1 - p.need.y0}, p.channels, bytes_of(p.type));
  if (p.geometry->correction) m.corrected = m.window;
}

}  // namespace

uint64_t ConvertMemory::job() const {
  return add_bytes(add_bytes(add_bytes(map, converted), output), corrected);
}

uint64_t ConvertMemory::pipeline(int readers) const {
  uint64_t bytes = job();
  for (int i = 0; i < readers; ++i) bytes = add_bytes(bytes, window);
  for (int i = 0; i < 4; ++i) bytes = add_bytes(bytes, written);
  return bytes;
}

ConvertPlan plan_convert(ConvertRequest request) {
  ConvertPlan p;
  p.request = std::move(request);
  p.options = p.request.options;
  plan_paths(p);
  plan_headers(p);
  plan_geometry(p);
  plan_memory(p);
  return p;
}

}  // namespace panoproj
