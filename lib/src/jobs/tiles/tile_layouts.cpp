#include "jobs/tiles/tile_layouts.hpp"

#include <charconv>
#include <cmath>
#include <string_view>

#include "base/json_text.hpp"
#include "io/formats.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

constexpr int64_t kMaxCube = 65536;  // 6 faces of 2^32 px: a panorama 200k px wide
constexpr int kMaxTile = 8192;
constexpr int64_t kMaxTiles = int64_t{1} << 22;  // files in one pyramid

// Degrees to a micro-degree (the range's last digits are rounding), as Python prints a float.
std::string num(double v) {
  char b[32];
  auto r = std::to_chars(b, b + sizeof b, std::round(v * 1e6) / 1e6 + 0.0);
  std::string s(b, r.ptr);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";  // as Python prints a float
  return s;
}

// Pannellum's multires settings and, for a partial panorama, its limits (generate.py's keys).
std::string pannellum_config(const TilePyramid& p, const ViewRange& r, double hfov) {
  std::string s = "{\n    \"hfov\": " + num(hfov) + ",\n";
  if (!r.full_yaw) {
    s += "    \"haov\": " + num(r.yaw1 - r.yaw0) + ",\n";
    s += "    \"minYaw\": " + num(r.yaw0) + ",\n";
    s += "    \"yaw\": " + num(0.5 * (r.yaw0 + r.yaw1)) + ",\n";
    s += "    \"maxYaw\": " + num(r.yaw1) + ",\n";
  }
  if (r.pitch0 > -90 || r.pitch1 < 90) {
    s += "    \"vaov\": " + num(r.pitch1 - r.pitch0) + ",\n";
    s += "    \"vOffset\": " + num(0.5 * (r.pitch0 + r.pitch1)) + ",\n";
    s += "    \"minPitch\": " + num(r.pitch0) + ",\n";
    s += "    \"pitch\": " + num(0.5 * (r.pitch0 + r.pitch1)) + ",\n";
    s += "    \"maxPitch\": " + num(r.pitch1) + ",\n";
  }
  if (r.partial()) s += "    \"avoidShowingBackground\": true,\n";
  s += "    \"type\": \"multires\",\n    \"multiRes\": {\n";
  s += "        \"path\": \"/%l/%s%y_%x\",\n";
  s += "        \"fallbackPath\": \"/fallback/%s\",\n";
  s += "        \"extension\": " + json_string(p.extension) + ",\n";
  s += "        \"tileResolution\": " + std::to_string(p.tile) + ",\n";
  s += "        \"maxLevel\": " + std::to_string(p.levels.size()) + ",\n";
  s += "        \"cubeResolution\": " + std::to_string(p.levels.back().size) + "\n    }\n}\n";
  return s;
}

// Marzipano's scene data: levels (the preview's first, fallbackOnly), URLs, limits in degrees
// (pitch positive up, as in Pannellum and panoproj: the page negates it for Marzipano).
std::string marzipano_config(const TilePyramid& p, const ViewRange& r, double hfov) {
  std::string s =
      "{\n  \"faceSize\": " + std::to_string(p.levels.back().size) + ",\n  \"levels\": [\n";
  s += "    {\"tileSize\": " + std::to_string(p.preview) +
       ", \"size\": " + std::to_string(p.preview) + ", \"fallbackOnly\": true}";
  for (const TileLevel& l : p.levels)
    s += ",\n    {\"tileSize\": " + std::to_string(std::min(p.tile, l.size)) +
         ", \"size\": " + std::to_string(l.size) + "}";
  s += "\n  ],\n  \"tileUrl\": \"tiles/{z}/{f}/{y}/{x}." + p.extension + "\",\n";
  s += "  \"previewUrl\": \"tiles/preview." + p.extension + "\",\n";
  s += "  \"previewFaceOrder\": \"" + std::string(kMarzipanoPreviewOrder) + "\",\n";
  s += "  \"yawRange\": " +
       (r.full_yaw ? std::string("null") : "[" + num(r.yaw0) + ", " + num(r.yaw1) + "]") + ",\n";
  s += "  \"pitchRange\": [" + num(r.pitch0) + ", " + num(r.pitch1) + "],\n";
  s += "  \"initialView\": {\"yaw\": " + num(r.full_yaw ? 0.0 : 0.5 * (r.yaw0 + r.yaw1)) +
       ", \"pitch\": " + num(r.partial() ? 0.5 * (r.pitch0 + r.pitch1) : 0.0) +
       ", \"hfov\": " + num(hfov) + "}\n}\n";
  return s;
}

// index.html: the viewer's script from script_url, the config inlined (a page opened from disk
// may not fetch it), the view from the query: ?yaw=&pitch=&hfov= (degrees, pitch positive up as
// in Pannellum; Marzipano's pitch is positive down, so its page negates it), controls=0.
const char* const kQuery = R"(var q = new URLSearchParams(location.search);
function param(name, fallback) { var v = parseFloat(q.get(name)); return isFinite(v) ? v : fallback; }
)";

// Why a page stays blank, said on it: opened from disk (browsers refuse file:// tiles as textures)
// or without its viewer's script (offline, or a wrong --script-url). `viewer`: the script's global;
// `package`: the npm package and the folder of its files in it.
std::string blank_page_notice(const std::string& script, const char* viewer, const char* package,
                              const char* folder) {
  return std::string(
             R"(<div id="why" style="display: none; position: absolute; top: 0; left: 0; right: 0; z-index: 9; padding: 1em; font: 16px/1.4 sans-serif; background: #fff3cd; color: #222"></div>
<script>
function why(text) { var d = document.getElementById("why"); d.textContent = text; d.style.display = "block"; }
var serve = "serve this folder over HTTP: run python3 -m http.server in it and open http://localhost:8000/";
if (location.protocol === "file:")
  why("This page is blank when opened from a file: browsers do not load its tiles from file:// addresses. To view it, " + serve + " (any web server does).");
else if (typeof )") +
         viewer + R"( === "undefined")
  why("The viewer's script did not load from )" +
         script +
         R"( (offline, or a wrong address). Run panoproj tiles with --script-url naming a folder that holds the viewer's files (e.g. node_modules/)" +
         package + "/" + folder + R"(/ after npm install )" + package +
         R"( here, for a page that works offline), then " + serve + ".");
</script>
)";
}

std::string pannellum_page(const std::string& script, const std::string& config) {
  return "<!DOCTYPE html>\n<html>\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, "
         "initial-scale=1\">\n<title>panorama</title>\n"
         "<link rel=\"stylesheet\" href=\"" +
         script + "pannellum.css\">\n<script src=\"" + script +
         "pannellum.js\"></script>\n<style>html, body, #panorama { margin: 0; width: 100%; height: "
         "100%; }</style>\n"
         "</head>\n<body>\n<div id=\"panorama\"></div>\n" +
         blank_page_notice(script, "pannellum", "pannellum", "build") + "<script>\n" + kQuery +
         "var config = " + config +
         ";\n"
         "config.basePath = \".\";\nconfig.autoLoad = true;\n"
         "config.yaw = param(\"yaw\", config.yaw || 0);\nconfig.pitch = param(\"pitch\", "
         "config.pitch || 0);\n"
         "config.hfov = param(\"hfov\", config.hfov);\n"
         "if (q.get(\"controls\") === \"0\") { config.showControls = false; config.compass = "
         "false; }\n"
         "window.viewer = pannellum.viewer(\"panorama\", config);\n</script>\n</body>\n</html>\n";
}

std::string marzipano_page(const std::string& script, const std::string& config) {
  return "<!DOCTYPE html>\n<html>\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, "
         "initial-scale=1\">\n<title>panorama</title>\n"
         "<script src=\"" +
         script +
         "marzipano.js\"></script>\n"
         "<style>html, body, #pano { margin: 0; width: 100%; height: 100%; overflow: hidden; "
         "}</style>\n"
         "</head>\n<body>\n<div id=\"pano\"></div>\n" +
         blank_page_notice(script, "Marzipano", "marzipano", "dist") + "<script>\n" + kQuery +
         "var data = " + config +
         ";\n"
         "var deg = Math.PI / 180, element = document.getElementById(\"pano\");\n"
         "var viewer = new Marzipano.Viewer(element, {controls: {mouseViewMode: \"drag\"}});\n"
         "if (q.get(\"controls\") === \"0\") viewer.controls().disable();\n"
         "var source = Marzipano.ImageUrlSource.fromString(data.tileUrl,\n"
         "    {cubeMapPreviewUrl: data.previewUrl, cubeMapPreviewFaceOrder: "
         "data.previewFaceOrder});\n"
         "var geometry = new Marzipano.CubeGeometry(data.levels);\n"
         "var limits = [Marzipano.RectilinearView.limit.traditional(data.faceSize, 120 * deg, 120 "
         "* deg)];\n"
         "if (data.yawRange) limits.push(Marzipano.RectilinearView.limit.yaw(data.yawRange[0] * "
         "deg, data.yawRange[1] * deg));\n"
         "limits.push(Marzipano.RectilinearView.limit.pitch(-data.pitchRange[1] * deg, "
         "-data.pitchRange[0] * deg));\n"
         "var hfov = param(\"hfov\", data.initialView.hfov) * deg;\n"
         "var vfov = 2 * Math.atan(Math.tan(hfov / 2) * element.clientHeight / "
         "element.clientWidth);\n"
         "var view = new Marzipano.RectilinearView({yaw: param(\"yaw\", data.initialView.yaw) * "
         "deg,\n"
         "    pitch: -param(\"pitch\", data.initialView.pitch) * deg, fov: vfov},\n"
         "    Marzipano.util.compose.apply(null, limits));\n"
         "var scene = viewer.createScene({source: source, geometry: geometry, view: view, "
         "pinFirstLevel: true});\n"
         "scene.switchTo({transitionDuration: 0});\nwindow.viewer = "
         "viewer;\n</script>\n</body>\n</html>\n";
}

}  // namespace

Viewer parse_viewer(std::string_view name) {
  if (name == "pannellum") return Viewer::Pannellum;
  if (name == "marzipano") return Viewer::Marzipano;
  throw Error("viewer " + std::string(name) + " is not known (use pannellum or marzipano)");
}

const char* name_of(Viewer v) {
  return v == Viewer::Pannellum ? "pannellum" : "marzipano";
}

int64_t TilePyramid::tile_count() const {
  int64_t n = 0;
  for (const TileLevel& l : levels) n += 6 * l.tiles * l.tiles;
  return n;
}

std::string TilePyramid::tile_path(size_t level, int face, int64_t row, int64_t col) const {
  const std::string f(1, kFaceLetters[face]), name = std::to_string(levels[level].name);
  if (viewer == Viewer::Pannellum)
    return name + "/" + f + std::to_string(row) + "_" + std::to_string(col) + "." + extension;
  return "tiles/" + name + "/" + f + "/" + std::to_string(row) + "/" + std::to_string(col) + "." +
         extension;
}

std::string preview_path(const TilePyramid& p, int face) {
  if (p.viewer == Viewer::Pannellum)
    return "fallback/" + std::string(1, kFaceLetters[face]) + "." + p.extension;
  return "tiles/preview." + p.extension;
}

namespace {

// The settings' own ranges, before any layout.
void check_settings(const TileSettings& job, double density) {
  for (unsigned char c : job.script_url)
    if (c < 0x21 || c == '"' || c == '<' || c == '>' || c == '\'' || c == '\\' || c == 0x7f)
      throw Error(option_text("script-url", job.script_url) +
                  " has a character a page cannot hold in an attribute "
                  "(quote, angle bracket, space or control: percent-encode it)");
  web_format(job.format, "format");
  if (job.tile < 16 || job.tile > kMaxTile)
    throw Error(option_text("tile", std::to_string(job.tile)) + " is out of range (16 to " +
                std::to_string(kMaxTile) + " px)");
  if (job.levels < 0 || job.levels > 32)
    throw Error(option_text("levels", std::to_string(job.levels)) +
                " is out of range (1 to 32, or 0 for all)");
  if (job.cube_size < 0 || job.cube_size > kMaxCube)
    throw Error(option_text("cube-size", std::to_string(job.cube_size)) +
                " is out of range (1 to " + std::to_string(kMaxCube) +
                " px, or 0 for the source's resolution)");
  if (job.preview < 0 || job.preview > 4096)
    throw Error(option_text("preview", std::to_string(job.preview)) +
                " is out of range (16 to 4096 px, or 0 for the default)");
  if (!(density > 0) || !std::isfinite(density))
    throw Error("the source has no resolution at its centre");
}

}  // namespace

TilePyramid make_pyramid(const TileSettings& job, double density) {
  check_settings(job, density);
  TilePyramid p;
  p.viewer = job.viewer;
  p.extension = job.format;
  const double natural =
      std::min(2 * density, static_cast<double>(kMaxCube));  // 90 degrees at the source's density
  std::vector<int64_t> sizes;                                // coarsest first
  if (job.viewer == Viewer::Pannellum) {
    // generate.py: cube = 8 floor(W / pi / 8), tile = min(tile, cube), levels to one tile a face,
    // each level int(size / 2) of the one above.
    const int64_t cube =
        job.cube_size ? job.cube_size : std::max<int64_t>(8, 8 * static_cast<int64_t>(natural / 8));
    p.tile = std::min<int64_t>(job.tile, cube);
    const int all =
        static_cast<int>(
            std::ceil(std::log2(static_cast<double>(cube) / static_cast<double>(p.tile)) - 1e-12)) +
        1;
    if (job.levels > all)
      throw Error(option_text("levels", std::to_string(job.levels)) + ": a " +
                  std::to_string(cube) + " px face in " + std::to_string(p.tile) +
                  " px tiles has " + std::to_string(all) + (all == 1 ? " level" : " levels") +
                  " (use at most that)");
    const int n = job.levels ? job.levels : all;
    for (int l = 1; l <= n; ++l) sizes.push_back(cube >> (n - l));
    p.preview = job.preview ? job.preview : std::min<int64_t>(1024, cube);
  } else {
    // Marzipano: sizes tile * 2^k (each a multiple of its tile size and of its parent's).
    const int64_t t = job.tile;
    int64_t cube = job.cube_size;
    if (cube) {
      int64_t s = t;
      while (s < cube) s *= 2;
      if (s != cube)
        throw Error(option_text("cube-size", std::to_string(cube)) + " is not " +
                    std::to_string(t) +
                    " x 2^k (Marzipano needs each level's size a multiple of its tile size and of "
                    "its parent's)");
    } else {
      const int k =
          std::max(0, static_cast<int>(std::lround(std::log2(natural / static_cast<double>(t)))));
      cube = t << k;
      while (cube > kMaxCube) cube /= 2;
      cube = std::max<int64_t>(cube, t);
    }
    p.tile = t;
    int all = 1;
    while ((t << (all - 1)) < cube) ++all;
    if (job.levels > all)
      throw Error(option_text("levels", std::to_string(job.levels)) + ": a " +
                  std::to_string(cube) + " px face in " + std::to_string(t) + " px tiles has " +
                  std::to_string(all) + (all == 1 ? " level" : " levels") + " (use at most that)");
    const int n = job.levels ? job.levels : all;
    for (int l = 0; l < n; ++l) sizes.push_back(cube >> (n - 1 - l));
    int64_t pv = sizes.front();
    while (pv > 256 && pv % 2 == 0) pv /= 2;
    if (job.preview && sizes.front() % job.preview != 0)
      throw Error(option_text("preview", std::to_string(job.preview)) +
                  " does not divide the first level's " + std::to_string(sizes.front()) +
                  " px (Marzipano needs each level a multiple of the one below)");
    p.preview = job.preview ? job.preview : pv;
  }
  if (p.preview < 16 && job.preview)
    throw Error(option_text("preview", std::to_string(job.preview)) +
                " is out of range (16 to 4096 px)");
  // A top level far past the source's detail, or millions of files, is a mistake to refuse
  // before hours of work: at most 4x the source's resolution, at most kMaxTiles tiles.
  const int64_t top = sizes.back();
  if (job.cube_size && static_cast<double>(top) > 4 * natural && top > p.tile)
    throw Error(option_text("cube-size", std::to_string(top)) +
                " is over 4x the source's resolution (" +
                std::to_string(static_cast<int64_t>(natural)) +
                " px a face): its tiles would hold no more detail");
  for (size_t i = 0; i < sizes.size(); ++i) {
    const int64_t s = sizes[i];
    if (s < 1)
      throw Error("level " + std::to_string(i + 1) + " would be empty (use fewer " +
                  option_text("levels") + ")");
    p.levels.push_back({static_cast<int>(i) + 1, s, (s + p.tile - 1) / p.tile});
  }
  if (p.tile_count() > kMaxTiles)
    throw Error(option_text("tile", std::to_string(job.tile)) + " makes " +
                std::to_string(p.tile_count()) + " tiles (over " + std::to_string(kMaxTiles) +
                " files: use larger tiles or fewer " + option_text("levels") + ")");
  return p;
}

std::vector<TextFile> viewer_files(const TileSettings& job, const TilePyramid& pyramid,
                                   const ViewRange& range) {
  std::string script = job.script_url;
  if (script.empty())
    script = pyramid.viewer == Viewer::Pannellum
                 ? "https://cdn.jsdelivr.net/npm/pannellum@2.5.7/build/"
                 : "https://cdn.jsdelivr.net/npm/marzipano@0.10.2/dist/";
  if (script.back() != '/') script += '/';
  const double hfov = 100;  // generate.py's starting field of view
  const std::string config = pyramid.viewer == Viewer::Pannellum
                                 ? pannellum_config(pyramid, range, hfov)
                                 : marzipano_config(pyramid, range, hfov);
  return {{"config.json", config},
          {"index.html", pyramid.viewer == Viewer::Pannellum ? pannellum_page(script, config)
                                                             : marzipano_page(script, config)}};
}

}  // namespace panoproj
