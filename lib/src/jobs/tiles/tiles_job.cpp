// The tiles job: a multires cube tile pyramid for a web viewer (jobs/tiles/tiles.hpp).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "base/parallel.hpp"
#include "base/sample_io.hpp"
#include "geometry/tile_map.hpp"
#include "io/atomic_output.hpp"
#include "io/codec.hpp"
#include "jobs/file_source.hpp"
#include "jobs/list.hpp"
#include "jobs/rendered_parts.hpp"
#include "jobs/tiles/tile_layouts.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/rotation.hpp"

namespace panoproj {
namespace {

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows = job_rows(
      {
          {"image", OptionType::Path, 0, "None",
           "the panorama (default projection as for convert: 2:1 = equirect, Photo Sphere "
           "metadata)",
           nullptr, nullptr, "input", kPositional | kRequired},
          {"out_dir", OptionType::Path, 0, "None",
           "the folder to make (tiles, config.json, index.html, preview)", nullptr, nullptr,
           "output", kPositional | kRequired},
          {"viewer", OptionType::Text, 0, "'pannellum'",
           "pannellum (default) | marzipano: directory layout, names, config and page", nullptr,
           "pannellum|marzipano"},
          {"src", OptionType::Text, 0, "None",
           "source projection spec (default as convert infers it)", nullptr, nullptr, "from"},
          {"tile", OptionType::Integer, 0, "512", "tile size in pixels (default 512)"},
          {"levels", OptionType::Integer, 0, "None",
           "levels to keep from the top (default: all, down to one tile a face)"},
          {"cube_size", OptionType::Integer, 0, "None",
           "the top level's face size (default: the source's resolution; marzipano: tile x 2^k)"},
          web_format_option(),
          with_help(write_option("quality"), "JPEG quality, 1 to 100 (default 95)"),
          {"preview", OptionType::Integer, 0, "None",
           "fallback face size (pannellum, default 1024) or preview face size (marzipano, default "
           "<= 256)"},
          {"script_url", OptionType::Text, 0, "None",
           "folder index.html loads the viewer's script from (default: the npm package on "
           "jsDelivr; a local folder, e.g. node_modules/pannellum/build/, for pages that work "
           "offline)"},
      },
      kUseTiles,
      {with_help(write_option("overwrite"), "replace an existing output folder"),
       command_option("quiet"),
       {"band_pixels", OptionType::Integer, 0, "16777216",
        "a staged part's output pixels at most (bands of whole tile rows, at least one)", nullptr,
        nullptr, nullptr, kNeither}});
  return rows;
}

struct TilesJob {
  std::string input, output;
  std::optional<std::string> from;
  TileSettings layout;
  ConvertOptions options;  // interp, antialias, rotation (which way is front), threads, memory
  WriteOptions write;      // quality, overwrite (the folder)
  int64_t band_pixels = 0;
};

TilesJob job_of(const Arguments& a) {
  TilesJob j;
  j.input = a.text("image");
  j.output = a.text("out_dir");
  j.from = a.optional_text("src");
  j.layout = {parse_viewer(a.text("viewer")),
              a.integer("tile"),
              a.integer("levels"),
              a.integer("cube_size"),
              a.text("format"),
              a.integer("preview"),
              a.text("script_url")};
  j.options = a.options();
  j.write = a.write();
  j.band_pixels = a.integer("band_pixels");
  return j;
}

// The source as every part of the job sees it, with its pyramid.
struct Source : FileSource {
  TilePyramid pyramid;
};

Source open_source(const TilesJob& job) {
  FileSource file = open_file_source(job.input, job.from, job.options, "tiles");
  TilePyramid pyramid = make_pyramid(job.layout, center_density(file.base.source));
  return Source{std::move(file), std::move(pyramid)};
}

// Rows [y0, y1) of face `face` at size s: a pinhole of focal s / 2 centred on the face's centre.
ConversionGeometry face_rows(const Source& src, int face, int64_t s, int64_t y0, int64_t y1) {
  ConversionGeometry g = src.base;
  const double h = 0.5 * static_cast<double>(s);
  g.target = Pinhole(Size{s, y1 - y0}, h, h, h, h - static_cast<double>(y0));
  g.rotation = src.base.rotation * rotation_from_ypr(kFaceAngles[face][0], kFaceAngles[face][1], 0);
  return g;
}

ConvertOptions render_options(const TilesJob& job, const Source& src) {
  ConvertOptions o = job.options;
  if (src.partial)
    o.add_alpha = true, o.edges.soft = true;  // coverage as alpha: empty tiles, soft edges
  return o;
}

// The JPEG decode scale for a whole face at size s (the same for every part of it, so that a
// scheduler's parts equal the local run's).
int face_scale(const TilesJob& job, const Source& src, int face, int64_t s) {
  if (!src.info.scalable || job.options.decode_scale == 1) return 1;
  const ConversionGeometry g = face_rows(src, face, s, 0, s);
  return coarsest_decode_scale(g, finest_source_step(g, 4));
}

ConversionGeometry at_scale(ConversionGeometry g, const Source& src, int scale) {
  if (scale > 1)
    g.source = rescaled(g.source, {src.info.size.width / scale, src.info.size.height / scale});
  return g;
}

// One part to render: rows [y0, y1) of a face at size s, at a decode scale.
struct Part {
  int face;
  int64_t size, y0, y1;
  int scale;
  ConversionGeometry geometry;  // at the scale
};

// Renders parts grouped by decode scale, each group from one read of the source (whole, or the
// union of the parts' footprints), calling done(part index, image) as each is made.
void render_parts(const TilesJob& job, const Source& src, const std::vector<Part>& parts,
                  bool whole, const std::function<void(size_t, const Image&)>& done) {
  const ConvertOptions o = render_options(job, src);
  // In flight besides the source's window: one part's output (and the tiles cut from it).
  uint64_t part_bytes = 0;
  for (const Part& p : parts)
    part_bytes = std::max(part_bytes, image_bytes(size_of(p.geometry.target), src.info.channels + 1,
                                                  2 * bytes_of(src.info.type)));
  require_memory("a band of tiles", part_bytes, job.options.memory_limit);
  std::map<int, std::vector<size_t>> by_scale;
  for (size_t i = 0; i < parts.size(); ++i) by_scale[parts[i].scale].push_back(i);
  for (const auto& [scale, members] : by_scale) {
    const Size frame{src.info.size.width / scale, src.info.size.height / scale};
    PixelRect need{frame.width, frame.height, 0, 0};
    std::vector<Converter> converters;
    // A part of a partial source whose footprint is empty has no pixel with a source (nor,
    // with its margin of rows, one on the field's edge): it is not rendered.
    std::vector<char> seen;
    for (size_t i : members) {
      converters.emplace_back(parts[i].geometry, o);
      seen.push_back(1);
      if (whole && !src.partial) continue;
      const PixelRect r = converters.back().source_footprint();
      if (r.x1 <= r.x0 || r.y1 <= r.y0) {
        seen.back() = 0;
        continue;
      }
      need = {std::min(need.x0, r.x0), std::min(need.y0, r.y0), std::max(need.x1, r.x1),
              std::max(need.y1, r.y1)};
    }
    if (whole) need = {0, 0, frame.width, frame.height};
    const bool any = std::find(seen.begin(), seen.end(), 1) != seen.end();
    Image window, with_alpha;
    if (any)
      window = read_image_region(job.input, need.x0, need.y0, need.x1, need.y1,
                                 job.options.memory_limit, part_bytes, scale);
    const Image& in = any ? source_for(window, o, with_alpha) : window;
    for (size_t k = 0; k < members.size(); ++k) {
      check_interrupt();
      Image out;
      if (seen[k])
        converters[k].run(in, out);
      else {  // as the converter makes it (a partial source: alpha last)
        const int channels = output_channels(src.info.channels, o);
        out = Image(size_of(parts[members[k]].geometry.target), channels, src.info.type,
                    channels - 1);
      }
      done(members[k], out);
    }
  }
}

std::vector<Part> parts_of(const TilesJob& job, const Source& src,
                           const std::vector<TileBand>& rows) {
  std::map<std::pair<size_t, int>, int> scales;
  std::vector<Part> parts;
  const TilePyramid& p = src.pyramid;
  for (const TileBand& r : rows) {
    if (r.level >= p.levels.size() || r.face < 0 || r.face > 5 || r.row0 < 0 || r.row1 <= r.row0 ||
        r.row1 > p.levels[r.level].tiles)
      throw Error("tile rows " + std::to_string(r.row0) + " to " + std::to_string(r.row1) +
                  " of face " + std::to_string(r.face) + " at level index " +
                  std::to_string(r.level) + " are not in the pyramid");
    const int64_t s = p.levels[r.level].size;
    auto [it, fresh] = scales.try_emplace({r.level, r.face}, 1);
    if (fresh) it->second = face_scale(job, src, r.face, s);
    // A partial source's field edge is found from each pixel's neighbours (EdgeFill): its bands
    // take a converter tile's rows more on each side, as in the whole face (the tile grid kept).
    const int64_t pad = src.partial ? kTile : 0;
    const int64_t y0 = std::max<int64_t>(0, r.row0 * p.tile - pad),
                  y1 = std::min(s, r.row1 * p.tile + pad);
    parts.push_back({r.face, s, y0, y1, it->second,
                     at_scale(face_rows(src, r.face, s, y0, y1), src, it->second)});
  }
  return parts;
}

PartCounts render_rows(const TilesJob& job, const Source& src, const FolderWriter& folder,
                       const std::vector<TileBand>& rows, bool whole,
                       const std::function<void(double)>& progress) {
  const std::vector<Part> parts = parts_of(job, src, rows);
  const TilePyramid& p = src.pyramid;
  const ImageFormat& format = web_format(job.layout.format, "format");
  std::atomic<int64_t> written{0}, empty{0};
  size_t finished = 0;
  render_parts(job, src, parts, whole, [&](size_t i, const Image& band) {
    const TileBand& r = rows[i];
    const int64_t s = parts[i].size, across = p.levels[r.level].tiles;
    const int64_t n = (r.row1 - r.row0) * across;
    parallel_tasks(n, job.options.threads, [&](int64_t t, int) {
      const int64_t row = r.row0 + t / across, col = t % across;
      const int64_t x0 = col * p.tile, y0 = row * p.tile - parts[i].y0;
      const int64_t w = std::min(p.tile, s - col * p.tile), h = std::min(p.tile, s - row * p.tile);
      const Flat f = flatten(band, x0, y0, w, h, src.partial);
      if (f.empty) {
        ++empty;
        return;
      }
      const std::string path = p.tile_path(r.level, r.face, row, col);
      folder.write(path, encoded(f.image, format, job.write, job.output + "/" + path));
      ++written;
    });
    if (progress) progress(static_cast<double>(++finished) / static_cast<double>(parts.size()));
  });
  return {written.load(), empty.load()};
}

// Every face's tile rows, in bands of at most band_pixels output pixels (at least one row).
std::vector<TileBand> all_rows(const TilePyramid& p, int64_t band_pixels) {
  std::vector<TileBand> rows;
  for (size_t l = p.levels.size(); l-- > 0;) {
    const TileLevel& level = p.levels[l];
    const int64_t per =
        std::max<int64_t>(1, band_pixels / std::max<int64_t>(1, level.size * p.tile));
    for (int f = 0; f < 6; ++f)
      for (int64_t r = 0; r < level.tiles; r += per)
        rows.push_back({l, f, r, std::min(level.tiles, r + per)});
  }
  return rows;
}

// The yaw and pitch range a partial source covers, from its rays on a grid over its frame (every
// valid pixel's ray is within a grid step of one of them) and the poles.
ViewRange view_range(const Source& src) {
  ViewRange v;
  if (!src.partial) return v;
  const Projection& p = src.base.source;
  const Size size = size_of(p);
  const Eigen::Matrix3d to_view = src.base.rotation.transpose();
  constexpr int kGrid = 512;
  std::vector<double> yaws;
  double pitch0 = 90, pitch1 = -90;
  const double deg = 180 / kPi;
  for (int j = 0; j <= kGrid; ++j)
    for (int i = 0; i <= kGrid; ++i) {
      Ray d;
      const double x = static_cast<double>(size.width) * i / kGrid,
                   y = static_cast<double>(size.height) * j / kGrid;
      if (!to_ray(p, std::min(x, std::nextafter(static_cast<double>(size.width), 0.0)),
                  std::min(y, std::nextafter(static_cast<double>(size.height), 0.0)), d))
        continue;
      const Ray r = to_view * d;
      yaws.push_back(std::atan2(r.x(), r.z()) * deg);
      const double pitch = std::atan2(-r.y(), std::hypot(r.x(), r.z())) * deg;
      pitch0 = std::min(pitch0, pitch), pitch1 = std::max(pitch1, pitch);
    }
  if (yaws.empty()) return v;
  double sx, sy;
  const bool up = to_pixel(p, src.base.rotation * Ray(0, -1, 0), sx, sy),
             down = to_pixel(p, src.base.rotation * Ray(0, 1, 0), sx, sy);
  if (up) pitch1 = 90;
  if (down) pitch0 = -90;
  v.pitch0 = pitch0, v.pitch1 = pitch1;
  std::sort(yaws.begin(), yaws.end());
  double gap = yaws.front() + 360 - yaws.back(), after = yaws.back();
  for (size_t i = 1; i < yaws.size(); ++i)
    if (yaws[i] - yaws[i - 1] > gap) gap = yaws[i] - yaws[i - 1], after = yaws[i - 1];
  // A gap of a few grid steps is sampling, not a border.
  const double step = 360.0 * 4 / kGrid;
  if (up || down || gap < step) return v;
  v.full_yaw = false;
  v.yaw0 = after + gap - 360 < -180 ? after + gap : after + gap - 360;
  v.yaw0 = v.yaw0 >= 180 ? v.yaw0 - 360 : v.yaw0;
  v.yaw1 = v.yaw0 + 360 - gap;
  return v;
}

Report finish(const TilesJob& job, const Source& src, OutputFolder& folder, PartCounts counts) {
  const TilePyramid& p = src.pyramid;
  const ImageFormat& format = web_format(job.layout.format, "format");
  // The preview: Pannellum's fallback faces, Marzipano's faces stacked in its order.
  std::vector<Part> parts;
  for (int f = 0; f < 6; ++f) {
    const int scale = face_scale(job, src, f, p.preview);
    parts.push_back({f, p.preview, 0, p.preview, scale,
                     at_scale(face_rows(src, f, p.preview, 0, p.preview), src, scale)});
  }
  Image strip;
  render_parts(job, src, parts, true, [&](size_t i, const Image& face) {
    Flat flat = flatten(face, 0, 0, p.preview, p.preview, src.partial);
    if (p.viewer == Viewer::Pannellum) {
      if (!flat.empty)
        folder.writer().write(preview_path(p, parts[i].face),
                              encoded(flat.image, format, job.write,
                                      job.output + "/" + preview_path(p, parts[i].face)));
      return;
    }
    if (strip.width() == 0)
      strip = Image(Size{p.preview, 6 * p.preview}, flat.image.channels(), flat.image.type());
    const int64_t slot = std::string_view(kMarzipanoPreviewOrder).find(kFaceLetters[parts[i].face]);
    for (int64_t y = 0; y < p.preview; ++y)
      std::memcpy(strip.row(slot * p.preview + y), flat.image.row(y), flat.image.row_bytes());
  });
  if (p.viewer == Viewer::Marzipano)
    folder.writer().write(preview_path(p, 0),
                          encoded(strip, format, job.write, job.output + "/" + preview_path(p, 0)));
  const ViewRange range = view_range(src);
  for (const TextFile& f : viewer_files(job.layout, p, range))
    folder.writer().write(f.path, f.text);
  folder.commit();
  std::vector<ReportValue> notes;
  if (range.partial()) {
    char b[160];
    char yaws[64] = "all round";
    if (!range.full_yaw) std::snprintf(yaws, sizeof yaws, "%.2f to %.2f", range.yaw0, range.yaw1);
    std::snprintf(b, sizeof b,
                  "partial panorama: the view is limited to yaw %s, pitch %.2f to %.2f", yaws,
                  range.pitch0, range.pitch1);
    notes.push_back({b});
    if (!range.full_yaw && range.yaw1 > 180)
      notes.push_back(
          {"its yaw range crosses the back (180 degrees), which the viewers' yaw limits cannot "
           "hold: "
           "turn its centre to the front with " +
           option_text("yaw")});
  }
  std::vector<ReportValue> levels;
  for (const TileLevel& l : p.levels)
    levels.push_back(
        {Report{{"name", {int64_t{l.name}}}, {"size", {l.size}}, {"tiles", {l.tiles}}}});
  return {{"viewer", {std::string(name_of(p.viewer))}},
          {"tile", {p.tile}},
          {"levels", {levels}},
          {"preview", {p.preview}},
          {"tile_count", {p.tile_count()}},
          {"written", {counts.written}},
          {"empty", {counts.empty}},
          {"src", {src.from_text}},
          {"source_size", report_size(src.info.size)},
          {"seconds", {0.0}},
          {"notes", {notes}}};
}

void check_job(const TilesJob& job) {
  if (job.input.empty()) throw Error("no input given (expected a panorama)");
  if (job.output.empty()) throw Error("no output folder given");
  check_write_options(job.write);
  if (job.options.decode_scale > 1)
    throw Error(option_text("decode-scale") + " " + std::to_string(job.options.decode_scale) +
                ": each level takes its own scale (use auto or 1)");
}

Report run(const Arguments& args, const JobEvents& events) {
  const auto t0 = std::chrono::steady_clock::now();
  const TilesJob job = job_of(args);
  check_job(job);
  const Source src = open_source(job);
  OutputFolder folder(job.output, job.write.overwrite, std::vector<std::string>{job.input},
                      "tiles");
  // One tile row a part: in flight, the source at one scale and one row of tiles.
  const std::vector<TileBand> rows = all_rows(src.pyramid, 1);
  const PartCounts counts = render_rows(job, src, folder.writer(), rows, true, events.progress);
  Report report = finish(job, src, folder, counts);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report_set(report, "seconds", {seconds});
  if (events.line) {
    const TilePyramid& p = src.pyramid;
    std::string sizes;
    for (const TileLevel& l : p.levels)
      sizes += (sizes.empty() ? "" : ", ") + std::to_string(l.size);
    char b[1024];
    std::snprintf(b, sizeof b,
                  "%s (%s, %s) -> %s: %s, %zu levels (faces %s px), %lld tiles of %lld px written",
                  job.input.c_str(), size_text(src.info.size).c_str(), src.from_text.c_str(),
                  job.output.c_str(), name_of(p.viewer), p.levels.size(), sizes.c_str(),
                  static_cast<long long>(counts.written), static_cast<long long>(p.tile));
    std::string line = b;
    if (counts.empty) line += " (" + std::to_string(counts.empty) + " empty, not written)";
    std::snprintf(b, sizeof b, ", %.3f s", seconds);
    line += b;
    for (const ReportValue& n :
         std::get<std::vector<ReportValue>>(report_find(report, "notes")->value))
      line += "\n  " + std::get<std::string>(n.value);
    line +=
        "\n  view it over HTTP (browsers load no tiles from file://): python3 -m http.server -d " +
        job.output + ", then http://localhost:8000/" +
        (job.layout.script_url.empty() ? "; offline: --script-url to the viewer's files" : "");
    events.line(line);
  }
  return report;
}

Staged begin(const Arguments& args) {
  const TilesJob job = job_of(args);
  check_job(job);
  const Source src = open_source(job);
  OutputFolder folder(job.output, job.write.overwrite, std::vector<std::string>{job.input},
                      "tiles");
  folder.keep();
  return {folder.staged(), static_cast<int64_t>(all_rows(src.pyramid, job.band_pixels).size())};
}

PartCounts render(const Arguments& args, const StagedFolder& staged,
                  const std::vector<int64_t>& parts) {
  const TilesJob job = job_of(args);
  const Source src = open_source(job);
  const std::vector<TileBand> all = all_rows(src.pyramid, job.band_pixels);
  std::vector<TileBand> rows;
  for (const int64_t i : parts) {
    if (i < 0 || i >= static_cast<int64_t>(all.size()))
      throw Error("part " + std::to_string(i) + " is not in the job (expected 0 to " +
                  std::to_string(all.size() - 1) + ")");
    rows.push_back(all[static_cast<size_t>(i)]);
  }
  return render_rows(job, src, FolderWriter(staged, job.output), rows, false, {});
}

Report finish_staged(const Arguments& args, const StagedFolder& staged, PartCounts counts) {
  const TilesJob job = job_of(args);
  const Source src = open_source(job);
  OutputFolder folder(job.output, job.write.overwrite, staged, "tiles");
  return finish(job, src, folder, counts);
}

}  // namespace

TilePyramid tile_pyramid(const Arguments& args) {
  return open_source(job_of(args)).pyramid;
}

const JobDef tiles_job{
    .name = "tiles",
    .summary = "write a multires cube tile pyramid for a web viewer (Pannellum, Marzipano)",
    .python =
        R"(Writes a multires cube tile pyramid of the panorama file ``image`` for a web viewer into the
new folder ``out_dir`` (as ``panoproj tiles``): Pannellum's ``<level>/<face><row>_<col>`` with
``config.json`` and fallback faces, or Marzipano's ``tiles/<z>/<face>/<row>/<col>`` with its
preview; ``index.html`` opens it, loading the viewer's script from ``script_url`` (default:
the npm package on jsDelivr). Every tile is rendered from the source, antialiased at its
level; tiles of a partial panorama without any source pixel are not written. The folder lands
whole (replaced only with ``overwrite``).

``client``: a ``dask.distributed`` Client; the tiles are then rendered as tasks (bands of tile
rows, each reading only the source region and scale it needs; the workers must see
``image`` and the output's parent folder at the same paths), with the same bytes as a local
run. Returns a report: levels, tile counts, the source spec, seconds.)",
    .rows = rows,
    .run = run,
    .begin = begin,
    .render = render,
    .finish = finish_staged,
};

}  // namespace panoproj
