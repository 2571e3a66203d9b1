// The undistort job: a COLMAP model and its images into pinhole images and a new model
// (undistort.hpp), as COLMAP's image_undistorter, with fisheyes of any field split into views.
//
// Output folder (lands whole):
//   images/<name>            each pinhole camera's image, under its name in the model
//   images/{view}/<name>     each view of a wide camera's image (COLMAP's rig layout)
//   masks/<image's name>.png views: 255 where the view sees the source, else 0
//   sparse/                  the new model, as the input's (.bin or .txt)
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <unordered_map>

#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "jobs/file_source.hpp"
#include "jobs/list.hpp"
#include "jobs/rendered_parts.hpp"
#include "jobs/undistort/undistort.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/limits.hpp"

namespace panoproj {
namespace {

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows = job_rows(
      {
          {"model", OptionType::Path, 0, "None",
           "the COLMAP model folder (e.g. sparse/0; .bin or .txt, COLMAP 3.x or 4.x)", nullptr,
           nullptr, nullptr, kPositional | kRequired},
          {"image_path", OptionType::Path, 0, "None", "the folder its images' names are in",
           nullptr, nullptr, nullptr, kPositional | kRequired},
          {"out_dir", OptionType::Path, 0, "None", "the folder to make", nullptr, nullptr, nullptr,
           kPositional | kRequired},
          {"max_fov", OptionType::Angle, 0, "120.0",
           "degrees: a camera whose field is at most this becomes one pinhole, a wider one views"},
          {"rig", OptionType::Text, 0, "'cube'",
           "a wide camera's views around its axis: cube (default) | ring:n=8,fov=90,pitch=0 | A+B "
           "| @rig.yaml (as views)"},
          {"blank_pixels", OptionType::Angle, 0, "0.0",
           "0 (default): no blank pixel (cropped, as COLMAP) .. 1: every source pixel kept"},
          {"min_scale", OptionType::Angle, 0, "0.2", "the pinhole frame's least scale (COLMAP's)"},
          {"max_scale", OptionType::Angle, 0, "2.0",
           "the pinhole frame's largest scale (COLMAP's)"},
          {"max_image_size", OptionType::Integer, 0, "0",
           "a pinhole image's longest side at most this (0: no limit)"},
          {"roi", OptionType::Text, 0, "'0,0,1,1'",
           "x0,y0,x1,y1: the pinhole's region of the source frame, fractions (COLMAP's roi_*)"},
          {"max_cam_point_norm", OptionType::Angle, 0, "0.0",
           "frame edge points past this tan(angle off axis) ignored for the pinhole's frame (0: "
           "none)"},
          {"format", OptionType::Text, 0, "'same'",
           "same (default: each name's, JPEG, PNG or PNM) | jpg | png (names change with it)",
           nullptr, "same|jpg|png"},
          with_help(write_option("quality"), "JPEG quality, 1 to 100 (default 95)"),
      },
      kUseViews,
      {with_help(write_option("overwrite"),
                 "replace an existing output folder (one panoproj made)"),
       command_option("quiet")});
  return rows;
}

struct UndistortJob {
  std::string model, images, output;
  UndistortOptions undistort;
  ConvertOptions options;  // size (views'), interp, antialias, engine, threads, decode, memory
  WriteOptions write;
  bool binary = false;  // the model's files
};

double number(const Arguments& a, const char* name, double lo, double hi) {
  const double v = a.angle(name);
  if (!(v >= lo && v <= hi)) {
    char b[160];
    std::snprintf(b, sizeof b, "%s: %g (expected %g to %g)", name, v, lo, hi);
    throw Error(b);
  }
  return v;
}

// "x0,y0,x1,y1", each in [0, 1], x0 < x1 and y0 < y1.
std::array<double, 4> roi_of(const std::string& text) {
  std::array<double, 4> r{};
  const char* at = text.c_str();
  for (size_t i = 0; i < 4; ++i) {
    char* end = nullptr;
    r[i] = std::strtod(at, &end);
    const bool more = i < 3 ? *end == ',' : *end == '\0';
    if (end == at || !more || !(r[i] >= 0 && r[i] <= 1))
      throw Error("roi: '" + text.substr(0, 80) +
                  "' (expected x0,y0,x1,y1: four fractions of the frame from 0 to 1)");
    at = end + 1;
  }
  if (!(r[0] < r[2] && r[1] < r[3]))
    throw Error("roi: '" + text + "' (expected x0 < x1 and y0 < y1)");
  return r;
}

UndistortJob job_of(const Arguments& a) {
  UndistortJob job{a.text("model"), a.text("image_path"), a.text("out_dir"), {}, a.options(),
                   a.write()};
  UndistortOptions& u = job.undistort;
  u.max_fov = number(a, "max_fov", 1, 360);
  u.blank_pixels = number(a, "blank_pixels", 0, 1);
  u.min_scale = number(a, "min_scale", 1e-3, 1e3);
  u.max_scale = number(a, "max_scale", u.min_scale, 1e3);
  u.max_image_size = a.integer("max_image_size");
  if (u.max_image_size < 0 || u.max_image_size > 65536)
    throw Error("max_image_size: " + std::to_string(u.max_image_size) + " (expected 0 to 65536)");
  u.roi = roi_of(a.text("roi"));
  u.max_cam_point_norm = number(a, "max_cam_point_norm", 0, 1e12);
  u.rig = parse_rig(a.text("rig"));
  u.size = job.options.size;
  const std::string format = a.text("format");
  if (format != "same") u.extension = std::string(web_format(format, "format").extensions[0]);
  job.binary = std::filesystem::exists(job.model + "/cameras.bin");
  return job;
}

const colmap::Model& model_of(const UndistortJob& job, std::optional<colmap::Model>& kept) {
  if (!kept)
    kept = colmap::read_model(job.model,
                              static_cast<int64_t>(memory_budget(job.options.memory_limit) / 4));
  return *kept;
}

std::string image_file(const UndistortJob& job, const colmap::Image& im) {
  return job.images + "/" + im.name;
}

const ImageFormat& output_format(const OutputImage& o) {
  const size_t dot = o.name.rfind('.');
  const ImageFormat* f = dot == std::string::npos
                             ? nullptr
                             : format_of_extension(std::string_view(o.name).substr(dot));
  if (!f || !f->built_in() || !f->encode)
    throw Error("image " + o.name +
                ": undistorted images are written as JPEG, PNG or PNM (give "
                "--format jpg or png: the names change with it)");
  return *f;
}

// Everything checked before any image: the plan, each image there, of its camera's size, and a
// format it can be written in.
UndistortPlan plan_of(const UndistortJob& job, const colmap::Model& m) {
  UndistortPlan plan = plan_undistort(m, job.undistort, job.model);
  for (size_t i = 0; i < m.images.size(); ++i) {
    const colmap::Image& im = m.images[i];
    const ImageInfo info = read_image_info(image_file(job, im));
    const colmap::Camera& c = *m.camera(im.camera);
    if (info.size.width != static_cast<int64_t>(c.width) ||
        info.size.height != static_cast<int64_t>(c.height))
      throw Error("image " + image_file(job, im) + " is " + size_text(info.size) + ", its camera " +
                  std::to_string(c.id) + " (" + c.model + ") " + std::to_string(c.width) + "x" +
                  std::to_string(c.height) + " (expected the camera's size)");
    uint64_t out = 0;
    for (const OutputImage& o : plan.images[i]) {
      output_format(o);
      out = std::max(out, image_bytes(o.size, info.channels + 1, 2 * bytes_of(info.type)));
    }
    require_memory("image " + im.name + " and its largest output",
                   add_bytes(image_bytes(info.size, info.channels, bytes_of(info.type)), out),
                   job.options.memory_limit);
  }
  return plan;
}

// Renders an image's outputs (its camera's plan `cp`) into the folder; returns {written, empty}.
PartCounts render_image(const UndistortJob& job, const colmap::Image& im, const CameraPlan& cp,
                        const std::vector<OutputImage>& outs, const FolderWriter& folder) {
  const std::string path = image_file(job, im);
  ConvertOptions base = job.options;
  base.size.reset();
  const FileSource src = open_file_source(path, cp.spec, base, "undistort");
  std::vector<ConversionGeometry> gs;
  int scale = job.options.decode_scale > 0 ? job.options.decode_scale : 8;
  for (const OutputImage& o : outs) {
    ConversionGeometry g = src.base;
    g.target = Pinhole(o.size, o.fx, o.fy, o.cx, o.cy);
    g.rotation = src.base.rotation * o.camera_from_view;
    if (job.options.decode_scale == 0)
      scale = std::min(scale,
                       src.info.scalable ? coarsest_decode_scale(g, finest_source_step(g, 4)) : 1);
    gs.push_back(std::move(g));
  }
  if (!src.info.scalable) scale = 1;
  const Size at{src.info.size.width / scale, src.info.size.height / scale};
  if (scale > 1)
    for (ConversionGeometry& g : gs) g.source = rescaled(g.source, at);
  const Image source =
      read_image_region(path, 0, 0, at.width, at.height, job.options.memory_limit, 0, scale);
  PartCounts counts;
  for (size_t v = 0; v < gs.size(); ++v) {
    check_interrupt();
    const OutputImage& o = outs[v];
    ConvertOptions opt = job.options;
    if (o.view) opt.add_alpha = true, opt.edges.soft = true;
    Image with_alpha, out;
    Converter(gs[v], opt).run(source_for(source, opt, with_alpha), out);
    Flat flat;
    if (o.view) flat = flatten(out, 0, 0, out.width(), out.height(), true);
    if (flat.empty) flat.image = Image(out.size(), out.channels() - 1, out.type());
    const std::string name = "images/" + o.name;
    folder.write(name, encoded(o.view ? flat.image : out, output_format(o), job.write,
                               job.output + "/" + name));
    if (o.view) {
      const std::string mask = "masks/" + o.name + std::string(kPngFormat.extensions[0]);
      folder.write(mask, encoded(mask_of(out), kPngFormat, job.write, job.output + "/" + mask));
    }
    ++counts.written;
    counts.empty += flat.empty ? 1 : 0;
  }
  return counts;
}

Report finish(const UndistortJob& job, const UndistortPlan& plan, OutputFolder& folder,
              PartCounts counts) {
  for (const colmap::File& f : colmap::model_files(plan.model, job.binary, "sparse/"))
    folder.writer().write(f.path, f.bytes);
  folder.commit();
  std::vector<ReportValue> cameras;
  for (const CameraPlan& cp : plan.cameras) {
    std::vector<ReportValue> ids, views;
    for (const colmap::Camera& c : cp.cameras) ids.push_back({static_cast<int64_t>(c.id)});
    for (const ViewCamera& v : cp.views) views.push_back({v.name});
    cameras.push_back({Report{{"id", {static_cast<int64_t>(cp.camera.id)}},
                              {"model", {cp.camera.model}},
                              {"field", {cp.field}},
                              {"pinhole", {cp.pinhole}},
                              {"cameras", {ids}},
                              {"views", {views}}}});
  }
  return {{"cameras", {cameras}},
          {"images", {counts.written}},
          {"empty", {counts.empty}},
          {"points3D", {static_cast<int64_t>(plan.model.points.size())}},
          {"rigs_and_frames", {plan.model.rigs_and_frames}},
          {"seconds", {0.0}}};
}

std::string summary(const UndistortJob& job, const UndistortPlan& plan, PartCounts counts,
                    double seconds) {
  int64_t pinholes = 0, split = 0;
  for (const CameraPlan& cp : plan.cameras) (cp.pinhole ? pinholes : split) += 1;
  auto count = [](int64_t n, const char* what) {
    return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
  };
  std::string line = job.model + " (" + count(static_cast<int64_t>(plan.images.size()), "image") +
                     ") -> " + job.output + ": " + count(pinholes, "camera") + " as pinholes, " +
                     count(split, "camera") + " as views, " + count(counts.written, "image") +
                     " written, COLMAP model in sparse/";
  char b[32];
  std::snprintf(b, sizeof b, ", %.3f s", seconds);
  line += b;
  if (counts.empty)
    line += "\n  " + std::to_string(counts.empty) + " views see no part of their image";
  return line;
}

Report run(const Arguments& args, const JobEvents& events) {
  const auto t0 = std::chrono::steady_clock::now();
  const UndistortJob job = job_of(args);
  std::optional<colmap::Model> kept;
  const colmap::Model& m = model_of(job, kept);
  const UndistortPlan plan = plan_of(job, m);
  OutputFolder folder(job.output, job.write.overwrite, {job.model, job.images}, "undistort");
  PartCounts counts;
  for (size_t k = 0; k < m.images.size(); ++k) {
    const CameraPlan& cp =
        *std::find_if(plan.cameras.begin(), plan.cameras.end(),
                      [&](const CameraPlan& p) { return p.camera.id == m.images[k].camera; });
    const PartCounts c = render_image(job, m.images[k], cp, plan.images[k], folder.writer());
    counts.written += c.written, counts.empty += c.empty;
    if (events.progress)
      events.progress(static_cast<double>(k + 1) / static_cast<double>(m.images.size()));
  }
  Report r = finish(job, plan, folder, counts);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report_set(r, "seconds", {seconds});
  if (events.line) events.line(summary(job, plan, counts, seconds));
  return r;
}

Staged begin(const Arguments& args) {
  const UndistortJob job = job_of(args);
  std::optional<colmap::Model> kept;
  const colmap::Model& m = model_of(job, kept);
  plan_of(job, m);
  OutputFolder folder(job.output, job.write.overwrite, {job.model, job.images}, "undistort");
  folder.keep();
  return {folder.staged(), static_cast<int64_t>(m.images.size())};
}

PartCounts render(const Arguments& args, const StagedFolder& staged,
                  const std::vector<int64_t>& parts) {
  const UndistortJob job = job_of(args);
  std::optional<colmap::Model> kept;
  const colmap::Model& m = model_of(job, kept);
  const FolderWriter folder(staged, job.output);
  // Only the cameras these images need are planned (a model may hold a camera per image).
  const LastIds last = last_ids(m);
  std::unordered_map<uint32_t, size_t> index;  // camera id -> its place in the model
  for (size_t i = 0; i < m.cameras.size(); ++i) index[m.cameras[i].id] = i;
  std::unordered_map<uint32_t, CameraPlan> plans;
  PartCounts counts;
  for (int64_t k : parts) {
    if (k < 0 || k >= static_cast<int64_t>(m.images.size()))
      throw Error("image " + std::to_string(k) + " is not in the job (" +
                  std::to_string(m.images.size()) + " images)");
    const colmap::Image& im = m.images[static_cast<size_t>(k)];
    auto at = plans.find(im.camera);
    if (at == plans.end())
      at = plans
               .emplace(im.camera, plan_camera(m.cameras[index.at(im.camera)], job.undistort,
                                               index.at(im.camera), last, job.model))
               .first;
    const std::vector<OutputImage> outs =
        image_outputs(im, static_cast<size_t>(k), at->second, job.undistort, last, job.model);
    const PartCounts c = render_image(job, im, at->second, outs, folder);
    counts.written += c.written, counts.empty += c.empty;
  }
  return counts;
}

Report finish_staged(const Arguments& args, const StagedFolder& staged, PartCounts counts) {
  const UndistortJob job = job_of(args);
  std::optional<colmap::Model> kept;
  const colmap::Model& m = model_of(job, kept);
  OutputFolder folder(job.output, job.write.overwrite, staged, "undistort");
  return finish(job, plan_undistort(m, job.undistort, job.model), folder, counts);
}

}  // namespace

const JobDef undistort_job{
    .name = "undistort",
    .summary = "undistort a COLMAP model's images into pinholes (wide fisheyes into views)",
    .python =
        R"(Undistorts the images of the COLMAP model in ``model`` (their names relative to
``image_path``) into the new folder ``out_dir`` (as ``panoproj undistort``; COLMAP's
image_undistorter): a camera whose field is at most ``max_fov`` degrees becomes one PINHOLE
camera (COLMAP's choice of frame: ``blank_pixels`` 0 crops to no blank pixel, 1 keeps every
source pixel; ``min_scale``, ``max_scale``, ``max_image_size``, ``roi``, ``max_cam_point_norm``;
a SIMPLE_PINHOLE or PINHOLE camera is kept unless ``max_image_size`` shrinks it); a wider one, a
fisheye past 180 degrees too, becomes a rig of pinhole views around its axis (``rig``: as
``views``; ``size``: each view's), written ``images/{view}/<name>`` with ``masks/``.
``sparse/`` holds the new model (cameras, images with their observations moved, points3D, rigs
and frames; the input's format).
``client``: a ``dask.distributed`` Client; each image is then a task, with the same bytes as a
local run. Returns a report: each camera's field and what it became, the images written.)",
    .rows = rows,
    .run = run,
    .begin = begin,
    .render = render,
    .finish = finish_staged,
};

}  // namespace panoproj
