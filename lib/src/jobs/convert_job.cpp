#include "panoproj/jobs.hpp"

#include <chrono>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "base/pixel_buffers.hpp"
#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "io/region_read.hpp"
#include "io/streamed_output.hpp"
#include "jobs/frame_pipeline.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
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
  std::vector<std::string> out;
  if (!order) return {path};
  for (int f = 0; f < 6; ++f) out.push_back(face_path(path, f, *order));
  return out;
}

}  // namespace

ProjectionSpec infer_source_spec(const std::optional<std::string>& from, const std::string& input, Size size,
                                 const std::optional<PhotoSphere>& photo_sphere) {
  if (from) return parse_spec(*from);
  if (is_face_pattern(input)) return parse_spec("cubemap:layout=files");
  if (photo_sphere) return parse_spec(photo_sphere_spec(*photo_sphere, size));
  if (size.width == 2 * size.height) return parse_spec("equirect");
  throw Error("cannot tell the projection of " + input + " (" + std::to_string(size.width) + "x" +
              std::to_string(size.height) + " is not a 2:1 equirect): give " + option_text("from") + " SPEC");
}

std::string level_by_pose(ConversionGeometry& geometry, const std::optional<PhotoSphere>& ps, std::string from_text) {
  if (!ps || (ps->pose_pitch == 0 && ps->pose_roll == 0)) return from_text;
  geometry.rotation = photo_sphere_pose(*ps).transpose() * geometry.rotation;
  std::ostringstream o;
  o << from_text << ", levelled by its Photo Sphere pose: pitch " << ps->pose_pitch << ", roll " << ps->pose_roll;
  return o.str();
}

namespace {

std::string batch_output(const std::string& pattern, const std::string& input, size_t n) {
  std::string s = pattern;
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{stem}", fs::path(input).stem().string()},
                                   {"{n}", std::to_string(n)}})
    for (size_t at; (at = s.find(key)) != std::string::npos;) s.replace(at, key.size(), value);
  return s;
}

// The input's metadata an output keeps: all but what described the old pixels (orientation: the
// conversion worked on the stored pixels; dimensions, thumbnail, pixel aspect, an EXR's screen
// window) and how the old file was stored (compression, layout, format-specific settings: an
// EXR's lossy DWAB must not pass to its output). By OpenImageIO's names, for TIFF, EXR and HDR
// inputs.
Metadata carried_metadata(const std::string& input) {
  static const char* const kDropped[] = {
      "Orientation",        "Exif:PixelXDimension", "Exif:PixelYDimension", "PixelAspectRatio",
      "screenWindowCenter", "screenWindowWidth",    "compression",          "planarconfig"};
  Metadata kept;
  for (Attribute& a : read_metadata(input)) {
    const std::string& n = a.name;
    bool drop = n.rfind("thumbnail", 0) == 0 ||
                n.rfind("rla:", 0) == 0;  // (RLA: a format OpenImageIO reads)
    for (const char* d : kDropped) drop |= n == d;
    for (const ImageFormat* f : image_formats())
      drop |= n.rfind(std::string(f->name) + ":", 0) == 0;
    if (!drop) kept.push_back(std::move(a));
  }
  return kept;
}

// Inputs whose blocks panoproj reads itself (JPEG, PNG) pass them as stored (the writer resets
// EXIF's orientation, rewrites its dimensions and drops its thumbnail; a Photo Sphere packet is
// not carried); formats without metadata (PPM) have none.
void carry_metadata(const std::string& input, const std::string& format, WriteOptions& write) {
  const ImageFormat& f = format_named(format);
  if (f.embedded_metadata)
    write.embedded = read_embedded_metadata(input);
  else if (f.holds_metadata)
    write.metadata = carried_metadata(input);
}

const char* layout_name(StereoLayout l) {
  return l == StereoLayout::TopBottom ? "tb" : l == StereoLayout::SideBySide ? "sbs" : "mono";
}

// The report's stereo words: the layouts, the eye taken, each eye's size.
std::string stereo_note(const ConversionGeometry& g) {
  if (!g.stereo.any()) return "";
  std::string s = std::string("stereo ") + layout_name(g.stereo.source) + " -> " + layout_name(g.stereo.target);
  if (g.stereo.source != StereoLayout::Mono && g.stereo.target == StereoLayout::Mono)
    s += g.stereo.eye ? " (right eye)" : " (left eye)";
  if (g.stereo.source == StereoLayout::Mono) s += " (both eyes from the one image)";
  return s + ", eyes " + size_text(size_of(g.source)) + " -> " + size_text(size_of(g.target));
}

}  // namespace

std::vector<ConvertReport> run_convert(const ConvertJob& job,
                                       const std::function<void(const ConvertReport&)>& on_frame,
                                       const std::function<void(double)>& progress) {
  if (job.inputs.empty()) throw Error("no input given (expected one or more images)");
  const ProjectionSpec to = parse_spec(job.to);
  std::optional<ProjectionSpec> from;
  if (job.from) from = parse_spec(*job.from);  // early: a bad spec fails before any reading
  const bool batch = job.inputs.size() > 1;
  const bool in_faces = !batch && is_face_pattern(job.inputs[0]), out_faces = is_cube_files(to);
  if (out_faces != is_face_pattern(job.output))
    throw Error(out_faces ? "output " + job.output +
                                " needs {face}, {index} or {axis} for cubemap:layout=files"
                          : "output " + job.output +
                                " has {face}/{index}/{axis} but " + option_text("to") + " is not cubemap:layout=files");
  if (batch) {
    if (job.output.find("{stem}") == std::string::npos && job.output.find("{n}") == std::string::npos)
      throw Error("output " + job.output + " names one file for " + std::to_string(job.inputs.size()) +
                  " inputs (put {stem} or {n} in it, e.g. out/{stem}.jpg)");
    for (const auto& in : job.inputs)
      if (is_face_pattern(in))
        throw Error("input " + in + " is a face pattern: cube faces convert one set at a time");
  }
  // Every output path, then: distinct, not an input, not existing (unless overwrite).
  std::vector<std::string> outputs;
  for (size_t n = 0; n < job.inputs.size(); ++n) outputs.push_back(batch ? batch_output(job.output, job.inputs[n], n) : job.output);
  std::vector<std::string> all_outputs, all_inputs;
  const FaceOrder out_order = out_faces ? cube_face_order(to) : kDefaultFaceOrder;
  const FaceOrder in_order = from && is_cube_files(*from) ? cube_face_order(*from) : kDefaultFaceOrder;
  for (const auto& o : outputs)
    for (const auto& f : expand(o, out_faces ? &out_order : nullptr)) all_outputs.push_back(f);
  for (const auto& i : job.inputs)
    for (const auto& f : expand(i, in_faces ? &in_order : nullptr)) all_inputs.push_back(f);
  // Outputs against each other by their resolved paths (x.png and ./x.png are one file).
  std::set<fs::path> resolved;
  for (size_t a = 0; a < all_outputs.size(); ++a) {
    if (!resolved.insert(resolved_path(all_outputs[a])).second)
      throw Error("output " + all_outputs[a] + " would be written twice (make the pattern unique per input)");
    for (const auto& i : all_inputs)
      if (same_file(all_outputs[a], i))
        throw Error("output " + all_outputs[a] + " is the input (choose another output path)");
    check_output_path(all_outputs[a], job.write.overwrite);
  }

  if (from && is_cube_files(*from) != in_faces)
    throw Error(in_faces ? "input " + job.inputs[0] + " is a face pattern but " + option_text("from") +
                               " is not cubemap:layout=files"
                         : option_text("from") + " cubemap:layout=files needs an input pattern with {face}, {index} or {axis}");
  // Every header, read once before any work (a batch shares one geometry); a face set's come with
  // its pixels.
  std::vector<ImageInfo> infos;
  if (!in_faces)
    for (const auto& in : job.inputs) infos.push_back(read_image_info(in));
  bool scalable = !in_faces;  // every input decodes at 1/2, 1/4, 1/8 (JPEG)
  for (size_t n = 0; n < infos.size(); ++n) {
    const Size s = infos[n].size, first = infos[0].size;
    scalable = scalable && infos[n].scalable;
    if (s != first)
      throw Error("input " + job.inputs[n] + " is " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                  " but " + job.inputs[0] + " is " + std::to_string(first.width) + "x" +
                  std::to_string(first.height) + " (a batch shares one size)");
  }

  std::vector<ConvertReport> reports;
  ConvertOptions options = job.options;
  if (options.size && out_faces) {
    // For separate face files the size is one face's.
    if (options.size->width != options.size->height)
      throw Error("size " + std::to_string(options.size->width) + "x" +
                  std::to_string(options.size->height) +
                  " is not square (cube faces are square; or use face=N)");
    options.size = Size{6 * options.size->width, options.size->height};
  }
  // The geometry from the first input's header; then of each input read only what the view needs.
  const ImageInfo info = in_faces ? ImageInfo{} : infos[0];
  const Size frame = info.size;
  std::optional<Image> faces;
  if (in_faces) faces = read_cube_faces(job.inputs[0], options.memory_limit, in_order);
  const Size source_size = in_faces ? faces->size() : frame;
  const int channels = in_faces ? faces->channels() : info.channels;
  const PixelType type = in_faces ? faces->type() : info.type;
  // (The Photo Sphere packet, read once, gives the projection and the pose unless --from does.)
  const auto ps = job.from || in_faces ? std::nullopt : read_photo_sphere(job.inputs[0]);
  if (!from) from = infer_source_spec(std::nullopt, job.inputs[0], source_size, ps);
  ConversionGeometry geometry = make_geometry(source_size, *from, to, options);
  const std::string from_text = level_by_pose(geometry, ps, from->str());
  // A JPEG source the view samples at under half its resolution everywhere decodes at 1/2, 1/4
  // or 1/8 (DCT scaling); the conversion, its antialiasing and its footprint are planned on that
  // frame (the same field: the scale divides the sides).
  int scale = options.decode_scale;
  if (scale > 1 && !scalable)
    throw Error(option_text("decode-scale") + " " + std::to_string(scale) + ": only JPEG sources decode at a scale (" +
                job.inputs[0] + " is not one; use auto or 1)");
  if (scale > 1 && (frame.width % scale != 0 || frame.height % scale != 0))
    throw Error(option_text("decode-scale") + " " + std::to_string(scale) + ": the source's " + size_text(frame) +
                " is not a multiple of " + std::to_string(scale) + " (use auto or a divisor)");
  if (scale > 1 && geometry.stereo.any())
    throw Error(option_text("decode-scale") + " " + std::to_string(scale) + ": stereo sources decode whole (use auto or 1)");
  if (scale == 0) scale = scalable && !geometry.stereo.any() ? coarsest_decode_scale(geometry, finest_source_step(geometry, 4)) : 1;
  if (scale > 1) geometry.source = rescaled(geometry.source, {frame.width / scale, frame.height / scale});
  // Sizes the output formats cannot hold, and jobs over the memory budget, stop before any work.
  const Size out_size = geometry.target_frame();
  for (const auto& o : all_outputs) check_writable_size(o, out_faces ? Size{out_size.height, out_size.height} : out_size);
  // The map is kept (built once for the footprint, the first image and the rest of a batch)
  // while it fits kMapCacheBudget, and a batch keeps the taps the first frame plans too;
  // beyond, memory stays source + output + tile buffers and the map is made twice (footprint,
  // then conversion) and again per frame.
  const uint64_t map_bytes = image_bytes(out_size, 1, kCachedMapBytesPerPixel);
  const bool cache = map_bytes <= static_cast<uint64_t>(kMapCacheBudget);
  const PixelType out_type = job.write.type.value_or(type);
  const uint64_t written = out_type == type ? 0 : image_bytes(out_size, channels + 1, bytes_of(out_type));
  require_job_memory(geometry, channels, type, options, add_bytes(cache ? map_bytes : 0, written));
  const auto t_map = std::chrono::steady_clock::now();
  const Converter converter =
      converter_for(geometry, options, !cache ? Keep::Nothing : job.inputs.size() > 1 ? Keep::MapsAndTaps : Keep::Maps);
  const PixelRect need = converter.source_footprint();
  // The output and maps, counted with the source's needed part when it is read (from its header,
  // before any pixel is decoded; a forged header is refused by the file's size first).
  const int out_channels = channels + (options.add_alpha ? 1 : 0);
  const uint64_t job_bytes =
      add_bytes(add_bytes(cache ? map_bytes : 0, written), image_bytes(out_size, out_channels, bytes_of(type)));
  const double map_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_map).count();
  // A frame: its source (a file's window, or the face set), its output's encoded files, its report.
  struct Frame {
    std::optional<RegionRead> file;
    Image face_set;
    EncodedOutput encoded;
    ConvertReport report;
  };
  // (spare: a source buffer the frame before is done with)
  auto open = [&](size_t n, Frame& f, uint64_t other_bytes, Image spare) {
    if (in_faces) f.face_set = std::move(*faces);
    else f.file.emplace(job.inputs[n], need.x0, need.y0, need.x1, need.y1, options.memory_limit, other_bytes, scale, std::move(spare));
  };
  // Converts frame n into out and encodes it; `reading`: decodes the file meanwhile, the tiles
  // taking its rows as they come (else it has been read).
  auto convert = [&](size_t n, Frame& f, Image& out, bool reading) {
    // The rows are waited for unless an alpha channel is first added to a copy of the source.
    if (reading && f.file && options.add_alpha && f.file->image().alpha_channel() < 0) f.file->read(), reading = false;
    Image with_alpha;
    const Image& source = source_for(f.file ? f.file->image() : f.face_set, options, with_alpha);
    const auto t0 = std::chrono::steady_clock::now();
    const double frames = static_cast<double>(job.inputs.size());
    const auto report = [&](double x) {
      if (progress) progress((static_cast<double>(n) + x) / frames);
    };
    WriteOptions write = job.write;
    write.threads = options.threads;
    if (job.keep_metadata && !in_faces) carry_metadata(job.inputs[n], infos[n].format, write);
    // Equirect outputs say where they sit in the sphere (Photo Sphere XMP, read by viewers).
    // (A stereo frame: one eye's fields and GSpherical:StereoMode.)
    if (const auto* e = std::get_if<Equirect>(&geometry.target); e && job.keep_metadata) {
      PhotoSphere ps = photo_sphere_of(*e);
      if (geometry.stereo.target != StereoLayout::Mono)
        ps.stereo_mode = geometry.stereo.target == StereoLayout::TopBottom ? "top-bottom" : "left-right";
      write.xmp = photo_sphere_xmp(ps);
    }
    // A single JPEG output encodes its parts as they are done (while the source is still read).
    std::optional<StreamedOutput> single;
    if (!out_faces) single.emplace(outputs[n], write, out_size, out_channels, type);
    std::function<void(const PixelRect&)> finished;
    if (single && single->streams()) finished = [&](const PixelRect& r) { single->done(out, r); };
    if (reading) converter.run_reading(source, out, [&](const RowsArrived& arrived) { f.file->read(arrived); }, nullptr, report, finished);
    else converter.run(source, out, nullptr, report, finished);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() +
                           (n == 0 ? map_seconds : 0.0);  // the map is built once, for the first
    f.encoded = single ? single->finish(out) : encode_cube_faces(out, outputs[n], write, out_order);
    auto face_size = [](Size strip) { return Size{strip.height, strip.height}; };
    const double read = static_cast<double>(source.width() * source.height()) /
                        static_cast<double>(source.frame_size().width * source.frame_size().height);
    f.report = {job.inputs[n], outputs[n], from_text, to.str(),
                in_faces ? face_size(source.size()) : frame,
                out_faces ? face_size(out.size()) : out.size(), in_faces, out_faces, seconds, read,
                in_faces ? "" : infos[n].format, scale, stereo_note(geometry)};
  };
  auto done = [&](Frame& f) {
    reports.push_back(std::move(f.report));
    if (on_frame) on_frame(reports.back());
  };

  // A batch of files goes through a pipeline (frame_pipeline.hpp) where its memory allows: two
  // frames decode at once, each on one thread, while the one before converts (on every thread)
  // and the one before that is written; so 3 source windows, 2 outputs and 3 encoded outputs
  // (counted at their decoded size) at most. Otherwise one frame after another, each decoded
  // while it converts.
  const int readers = std::min(2, resolve_threads(options.threads));
  const uint64_t window_bytes = image_bytes({need.x1 - need.x0, need.y1 - need.y0}, channels, bytes_of(type));
  const uint64_t out_bytes = image_bytes(out_size, out_channels, bytes_of(out_type));
  uint64_t pipeline_bytes = job_bytes;
  for (int i = 0; i < readers; ++i) pipeline_bytes = add_bytes(pipeline_bytes, window_bytes);
  for (int i = 0; i < 4; ++i) pipeline_bytes = add_bytes(pipeline_bytes, out_bytes);
  const uint64_t budget = memory_budget(options.memory_limit), counted = add_bytes(pipeline_bytes, window_bytes);
  const bool pipelined = batch && readers > 1 && counted <= budget;
  if (!pipelined) {
    Image out, source;  // one buffer each for every frame
    for (size_t n = 0; n < job.inputs.size(); ++n) {
      Frame f;
      open(n, f, job_bytes, std::move(source));
      convert(n, f, out, f.file.has_value());
      if (f.file) source = std::move(f.file->image());
      f.encoded.write();
      done(f);
    }
    return reports;
  }
  // The encoders' buffers freed with each frame serve the next ones, within the budget's rest.
  const ReuseFreedBuffers reuse(static_cast<size_t>(budget - counted));  // (at most kMostBytes)
  std::vector<Frame> frames(job.inputs.size());
  std::vector<Image> outs(2);  // frame n's in outs[n % 2]
  std::mutex spare_mutex;
  std::vector<Image> spare;  // source buffers converted frames are done with
  run_frame_pipeline(job.inputs.size(), readers,
                     {.read =
                          [&](size_t n) {
                            Image buffer;
                            {
                              std::lock_guard<std::mutex> lock(spare_mutex);
                              if (!spare.empty()) buffer = std::move(spare.back()), spare.pop_back();
                            }
                            open(n, frames[n], pipeline_bytes, std::move(buffer));
                            // (no arrived: one decoder a frame; a second for its lower band would
                            // decode the rows it skips again, and the readers fill the cores)
                            frames[n].file->read([](int64_t) {});
                          },
                      .convert =
                          [&](size_t n) {
                            convert(n, frames[n], outs[n % 2], false);
                            std::lock_guard<std::mutex> lock(spare_mutex);
                            spare.push_back(std::move(frames[n].file->image()));
                            frames[n].file.reset();
                          },
                      .write =
                          [&](size_t n) {
                            frames[n].encoded.write();
                            frames[n].encoded = {};
                          },
                      .written = [&](size_t n) { done(frames[n]); }});
  return reports;
}

Size run_maps(const MapsJob& job) {
  if (!format_of_path(job.output).float_channels) {
    std::string holding;
    for (const ImageFormat* f : image_formats())
      if (f->float_channels)
        holding += (holding.empty() ? "" : " or ") + std::string(f->extensions[0]);
    throw Error("output " + job.output + " cannot hold float maps (use " + holding + ")");
  }
  check_output_path(job.output, job.write.overwrite);
  const ConversionGeometry geometry =
      make_geometry(job.source_size, parse_spec(job.from), parse_spec(job.to), job.options);
  require_mono(geometry, "maps");
  // The map (2 floats a pixel) and its encoded copy.
  const Size out = size_of(geometry.target);
  check_writable_size(job.output, out);
  require_memory("map " + size_text(out), image_bytes(out, 4, sizeof(float)), job.options.memory_limit);
  const Image map = build_map(geometry.source, geometry.target, geometry.rotation, job.convention, job.options.threads);
  WriteOptions w = job.write;
  w.channel_names = {"x", "y"};
  write_image(map, job.output, w);
  return map.size();
}

}  // namespace panoproj
