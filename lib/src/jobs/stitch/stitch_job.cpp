// The stitch job: a Hugin project's images remapped onto its panorama as nona -m TIFF_m does,
// one layer TIFF each (io/tiff_layer.hpp) for enblend: crops and masks as alpha (layer_masks),
// the panorama and lenses as specs (pano_spec), the photometry as nona's (pto_photometry; HDR
// layers with nona's weights beside them), every layer landed together or none.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "io/atomic_output.hpp"
#include "io/codec.hpp"
#include "io/formats.hpp"
#include "io/streamed_output.hpp"
#include "io/tiff_layer.hpp"
#include "io/video_formats.hpp"
#include "jobs/list.hpp"
#include "jobs/stitch/layer_masks.hpp"
#include "jobs/stitch/lens_rig.hpp"
#include "jobs/stitch/pano_spec.hpp"
#include "jobs/stitch/panorama.hpp"
#include "jobs/stitch/pto_photometry.hpp"
#include "jobs/stitch/pto_project.hpp"
#include "jobs/stitch/stitch.hpp"
#include "jobs/stitch/stitch_video.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/error.hpp"
#include "panoproj/interrupt.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/photo_sphere.hpp"
#include "panoproj/projection.hpp"
#include "panoproj/rotation.hpp"
#include "photometry/source_correction.hpp"
#include "spec/photometric_keys.hpp"

namespace panoproj {
namespace {

OptionDef interp_row() {
  OptionDef r = conversion_option("interp", kUseConvert);
  r.use = kUseStitch;
  r.default_text = "None";
  r.help =
      "nearest|bilinear|bicubic|lanczos3|bicubic-dering|lanczos3-dering; default: the project's m "
      "line (i5 "
      "bilinear, i6 nearest, i3 and i7 lanczos3, others bicubic)";
  return r;
}

OptionDef depth_row() {
  OptionDef r = with_help(write_option("depth"),
                          "layer samples: uint8|uint16|float; default: the project's T, else each "
                          "image's own (as nona)");
  r.choices = "uint8|uint16|float";
  return r;
}

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows = job_rows(
      {
          {"project", OptionType::Path, 0, "None",
           "the Hugin project (.pto), or a rig of lenses (.yaml, .yml, .json)", nullptr, nullptr,
           nullptr, kPositional | kRequired},
          {"output", OptionType::Path, 0, "None",
           "the blended panorama (a file of an image format: pano.jpg, pano.tif, ...), or the "
           "layers' prefix: PREFIX0000.tif, PREFIX0001.tif, ... (a number per image, as nona's -o)",
           nullptr, nullptr, nullptr, kPositional | kRequired},
          {"images", OptionType::Paths, 0, "None",
           "image files in place of the project's, in its order (a template project), or of a "
           "rig's inputs, in the order it first names them"},
          {"to", OptionType::Text, 0, "None",
           "a rig's panorama: a projection spec (default: equirect); a project's is its p line"},
          {"image", OptionType::Integer, 0, "None", "render only this image (nona's -i)"},
          {"compression", OptionType::Text, 0, "None",
           "the layers' and a TIFF panorama's: none | deflate; default: the project's n\"TIFF_m "
           "c:...\" (c:NONE: none; LZW, PACKBITS, DEFLATE: deflate)",
           nullptr, "none|deflate"},
          {"extent", OptionType::Text, 0, "None",
           "crop (each layer its part of the canvas) | canvas (each the whole canvas); default: "
           "the project's "
           "n\"TIFF_m r:CROP\" (crop), else canvas, as nona",
           nullptr, "crop|canvas"},
          depth_row(),
          interp_row(),
          {"exposure", OptionType::Angle, 0, "None",
           "the layers' exposure value (EV), in place of the project's p line E (nona's -e)"},
          {"ignore_exposure", OptionType::Flag, 0, "False",
           "each layer at its image's own exposure (Eev): no exposure correction (nona's "
           "--ignore-exposure)"},
          {"output_mode", OptionType::Text, 0, "None",
           "ldr (codes of Hugin's output response) | hdr (linear, with nona's weights "
           "PREFIX0000_gray.pgm); default: the project's p line R (R0 ldr, R1 hdr), as nona's -r",
           nullptr, "ldr|hdr"},
          {"create_exposure_layers", OptionType::Flag, 0, "False",
           "one blended layer per exposure (for enfuse, as nona's): PREFIX0000.tif, ... each "
           "the images within 0.5 EV of the group's first, blended at its exposure"},
          {"blend", OptionType::Text, 0, "None",
           "the panorama's blend: feather (default: weights from each image's distance to its "
           "edge) | multiband (Burt-Adelson)",
           nullptr, "feather|multiband"},
          {"feather", OptionType::Angle, 0, "None",
           "the feather's ramp (deg, across the midline between two images); default: the whole "
           "overlap; 0: a hard cut"},
          {"levels", OptionType::Integer, 0, "None",
           "multiband's levels, 1 to 12; default: from the overlaps' width"},
          write_option("quality"),
          write_option("subsampling"),
      },
      kUseStitch,
      {with_help(write_option("overwrite"), "replace existing layers"), command_option("quiet")});
  return rows;
}

// The conversion rows as stitch reads them: antialiasing off unless asked for (as nona).
const std::vector<OptionDef>& stitch_rows() {
  static const std::vector<OptionDef> out = [] {
    std::vector<OptionDef> r = rows();
    for (OptionDef& d : r)
      if (std::string_view(d.name) == "antialias")
        d.help =
            "off (default, as nona) | auto (where the panorama shrinks an image, each pixel the "
            "area-weighted "
            "mean of the pixels under its footprint) | mip | N (N x N sub-pixels, 2..16)";
    return r;
  }();
  return out;
}

Interp project_interp(int i) {
  switch (i) {
    case 5:
      return Interp::Bilinear;
    case 6:
      return Interp::Nearest;
    case 3:
    case 7:
      return Interp::Lanczos3;
    default:
      return Interp::Bicubic;
  }
}

std::optional<PixelType> depth_of(const Arguments& args, const PtoProject& p) {
  const std::string given = args.optional_text("depth").value_or("");
  const std::string d = given.empty() ? p.pano.depth : given;
  if (d.empty()) return std::nullopt;
  if (d == "UINT8" || d == "uint8") return PixelType::U8;
  if (d == "UINT16" || d == "uint16") return PixelType::U16;
  if (d == "FLOAT" || d == "float") return PixelType::F32;
  throw Error("depth: " + d + " (a layer holds uint8, uint16 or float)");
}

TiffCompression compression_of(const Arguments& args, const PtoProject& p) {
  if (const auto c = args.optional_text("compression")) {
    if (*c == "none") return TiffCompression::None;
    if (*c == "deflate") return TiffCompression::Deflate;
    throw Error("compression: " + *c + " (expected none or deflate)");
  }
  const size_t at = p.pano.output.find("c:");
  if (at == std::string::npos) return TiffCompression::Deflate;
  const std::string c = p.pano.output.substr(at + 2, p.pano.output.find(' ', at) - at - 2);
  return c == "NONE" ? TiffCompression::None : TiffCompression::Deflate;
}

std::string layer_path(const std::string& prefix, size_t index, std::string_view suffix) {
  char number[24];
  std::snprintf(number, sizeof number, "%04zu", index);
  return prefix + number + std::string(suffix);
}

// The layers' output: the project's p line (a rig's: LDR), as the rows change it; a rig's exposure
// is set with its lenses' (rig_output).
PhotometricOutput output_of(const Arguments& args, const std::optional<PtoProject>& p) {
  PhotometricOutput o = p ? pano_output(*p) : PhotometricOutput{};
  if (const auto m = args.optional_text("output_mode")) {
    if (*m != "ldr" && *m != "hdr") throw Error("output_mode: " + *m + " (expected ldr or hdr)");
    o.hdr = *m != "ldr";
  }
  if (const auto e = args.optional_angle("exposure")) {
    if (args.flag("ignore_exposure"))
      throw Error(
          "exposure and ignore_exposure: give one (an exposure for every layer, or each "
          "its own)");
    if (!std::isfinite(*e) || std::fabs(*e) > 64)
      throw Error("exposure: " + std::to_string(*e) + " (expected an EV within -64..64)");
    o.exposure = *e;
  }
  return o;
}

// A rig's output: lens 0's response, at --exposure or else the mean of its lenses' exposures.
void rig_output(const Arguments& args, StitchPlan& s) {
  s.output.response = s.layers.at(0).model.response;
  if (args.optional_angle("exposure")) return;
  double sum = 0;
  for (const StitchLayer& l : s.layers) sum += l.model.exposure;
  s.output.exposure = sum / static_cast<double>(s.layers.size());
}

// The blend rows: a panorama's only; the layer rows (extent, compression): layers' only.
void blend_of(const Arguments& args, StitchPlan& s) {
  const bool panorama = !s.panorama.empty();
  const bool blend_given = args.optional_text("blend") || args.optional_angle("feather") ||
                           args.optional_integer("levels");
  if (!panorama && blend_given)
    throw Error("blend, feather and levels: blend a panorama; " + args.text("output") +
                " is a layers' prefix (give a file such as pano.jpg to blend)");
  const bool tiff =
      panorama &&
      format_of_extension(std::filesystem::path(s.panorama).extension().string()) == &kTiffFormat;
  for (const char* row : {"extent", "compression"})
    if (panorama && args.optional_text(row) && (row != std::string_view("compression") || !tiff))
      throw Error(std::string(row) + ": shapes layers" +
                  (row == std::string_view("compression") ? " and TIFF panoramas; " : "; ") +
                  s.panorama + " is a blended panorama (give a prefix such as layer_ for layers)");
  if (const auto b = args.optional_text("blend")) {
    if (*b != "feather" && *b != "multiband")
      throw Error("blend: " + *b + " (expected feather or multiband)");
    s.blend.multiband = *b == "multiband";
  }
  if (const auto f = args.optional_angle("feather")) {
    if (s.blend.multiband)
      throw Error("feather: the feather's width; multiband blends by its levels (--levels)");
    if (!(*f >= 0 && *f <= 360))
      throw Error("feather: " + std::to_string(*f) + " (expected 0 to 360 degrees)");
    s.blend.feather = *f * kPi / 180;
  }
  if (const auto l = args.optional_integer("levels")) {
    if (!s.blend.multiband) throw Error("levels: multiband's (give --blend multiband)");
    if (*l < 1 || *l > kMaxBlendLevels)
      throw Error("levels: " + std::to_string(*l) + " (expected 1 to " +
                  std::to_string(kMaxBlendLevels) + ")");
    s.blend.levels = static_cast<int>(*l);
  }
}

// Whether a row was given (a flag: set).
bool given(const Arguments& args, const char* row) {
  switch (args.row(row).type) {
    case OptionType::Flag:
      return args.flag(row);
    case OptionType::Angle:
      return args.optional_angle(row).has_value();
    case OptionType::Integer:
      return args.optional_integer(row).has_value();
    default:
      return args.optional_text(row).has_value();
  }
}

std::string rect_text(const PixelRect& r) {
  return size_text(r.size()) + "+" + std::to_string(r.x0) + "+" + std::to_string(r.y0);
}

// Input k's samples: an array's (arrays: the in-memory inputs), an image file's, or a video's
// frames' (the video noted in the plan); `input`: its in-memory index (-1: a file's).
ImageInfo input_info(const std::string& path, size_t k, const std::vector<ImageInfo>* arrays,
                     StitchPlan& s, int& input) {
  input = -1;
  if (arrays) {
    if (k >= arrays->size())
      throw Error("arrays: " + std::to_string(arrays->size()) + " given for " + s.project.path +
                  ", which has more inputs (one array per input, in order)");
    input = static_cast<int>(k);
    return (*arrays)[k];
  }
  if (!is_video_file(path)) return read_image_info(path);
  const auto at = std::find(s.videos.begin(), s.videos.end(), path);
  input = static_cast<int>(at - s.videos.begin());
  if (at == s.videos.end()) s.videos.push_back(path);
  return video_frames_info(path);
}

// A rig's lens as a project's image: its size, and its crop (a rectangle, or a circle).
PtoImage rig_image(const RigLens& lens, Size size, const std::string& of) {
  PtoImage im;
  im.line = lens.line;
  im.name = lens.input;
  im.width = size.width, im.height = size.height;
  if (lens.crop) {
    const PixelRect& c = *lens.crop;
    if (c.x1 > size.width || c.y1 > size.height)
      throw Error(of + ": crop " + rect_text(c) + " reaches outside its image (" + size_text(size) +
                  ")");
    im.crop = PtoRect{c.x0, c.x1, c.y0, c.y1};
  }
  if (lens.circle) {
    const auto [cx, cy, r] = *lens.circle;
    if (!(cx > 0 && cy > 0 && cx < static_cast<double>(size.width) &&
          cy < static_cast<double>(size.height)))
      throw Error(of + ": circle centre " + std::to_string(cx) + " " + std::to_string(cy) +
                  " outside its image (" + size_text(size) + ")");
    im.circle = {cx - 0.5, cy - 0.5, r};  // (Hugin's positions)
  }
  return im;
}

// A rig lens's photometric model: its spec's keys (one lens's).
Photometry lens_model(const ProjectionSpec& spec, const ImageInfo& info, const std::string& of) {
  const std::vector<ParamDef> keys = photometric_key_defs(true);
  for (size_t k = photometric_key_defs(false).size(); k < keys.size(); ++k)
    if (spec.given(keys[k].key))
      throw Error(of + ": spec " + spec.str() + ": " + keys[k].key +
                  "= is a second lens's: a rig's lens is one lens (give each its own entry)");
  const bool samples_float = info.type == PixelType::F16 || info.type == PixelType::F32;
  return lens_photometry(spec, 0, samples_float, of + ": spec");
}

// A rig's lenses as the plan's images and layers (lens_rig.hpp), and its panorama: `to` (default
// equirect) at `size` (default: the finest lens's resolution at its centre).
void rig_layers(const Arguments& args, const LensRig& rig, bool files, const std::string& prefix,
                const std::vector<ImageInfo>* arrays, StitchPlan& s) {
  const std::filesystem::path folder = std::filesystem::path(rig.path).parent_path();
  // The inputs in the order first named; --images gives files in their place, one each.
  std::vector<std::string> inputs;
  for (const RigLens& lens : rig.lenses)
    if (std::find(inputs.begin(), inputs.end(), lens.input) == inputs.end())
      inputs.push_back(lens.input);
  const std::vector<std::string> given_files = args.paths("images");
  if (arrays && arrays->size() != inputs.size())
    throw Error("arrays: " + std::to_string(arrays->size()) + " for a rig of " +
                std::to_string(inputs.size()) + " inputs (one per input it names, in order)");
  if (!given_files.empty() && given_files.size() != inputs.size())
    throw Error("images: " + std::to_string(given_files.size()) + " files for a rig of " +
                std::to_string(inputs.size()) + " inputs (one per input it names, in order)");
  std::vector<std::string> paths;
  std::vector<ImageInfo> infos;
  std::vector<int> videos;
  for (size_t k = 0; k < inputs.size(); ++k) {
    paths.push_back(given_files.empty() ? (folder / inputs[k]).string() : given_files[k]);
    infos.push_back(input_info(paths.back(), k, arrays, s, videos.emplace_back()));
  }
  const auto rect_of = [&](const RigLens& lens, size_t in) {
    return lens.rect.value_or(PixelRect{0, 0, infos[in].size.width, infos[in].size.height});
  };
  const auto input_of = [&](const RigLens& lens) {
    return static_cast<size_t>(std::find(inputs.begin(), inputs.end(), lens.input) -
                               inputs.begin());
  };
  double density = 0;
  for (size_t k = 0; k < rig.lenses.size(); ++k) {
    const RigLens& lens = rig.lenses[k];
    const std::string of = rig.path + " line " + std::to_string(lens.line) + ": " + lens.name;
    const size_t in = input_of(lens);
    const PixelRect rect = rect_of(lens, in);
    if (rect.x1 > infos[in].size.width || rect.y1 > infos[in].size.height)
      throw Error(of + ": rect " + rect_text(rect) + " reaches outside " + paths[in] + " (" +
                  size_text(infos[in].size) + ")");
    for (size_t j = 0; j < k; ++j) {
      const RigLens& other = rig.lenses[j];
      const PixelRect o = rect_of(other, in);
      if (other.input == lens.input && o.x0 < rect.x1 && rect.x0 < o.x1 && o.y0 < rect.y1 &&
          rect.y0 < o.y1)
        throw Error(of + ": rect " + rect_text(rect) + " overlaps " + other.name + "'s (" +
                    rect_text(o) + ") in " + paths[in] +
                    " (give each lens of a shared frame its own rect)");
    }
    const Size size = rect.size();
    const PtoImage im = rig_image(lens, size, of);
    s.project.images.push_back(im);
    StitchLayer l;
    l.index = static_cast<int>(k);
    l.file = paths[in];
    l.size = size;
    l.info = infos[in];
    l.input = videos[in];
    l.channels = infos[in].channels;
    if (lens.rect) l.region = rect;
    // A calibration file is found beside the rig.
    const std::string spec =
        lens.spec.front() == '@' && std::filesystem::path(lens.spec.substr(1)).is_relative()
            ? "@" + (folder / lens.spec.substr(1)).string()
            : lens.spec;
    try {
      l.spec = parse_spec(spec);
      density = std::max(density, center_density(make_projection(*l.spec, size)));
    } catch (const Error& e) {
      throw Error(of + ": spec " + e.what());
    }
    l.lens = l.spec;
    l.rotation = rotation_from_ypr(lens.yaw, lens.pitch, lens.roll).transpose();
    l.model = lens_model(*l.spec, infos[in], of);
    if (!lens.flat_field.empty())
      l.model.vignetting.flat_field =
          flat_field_of(read_image((folder / lens.flat_field).string(), s.options.memory_limit));
    l.model_size = size;
    l.model_of = of + ": spec";
    l.output = layer_path(prefix, k, kTiffFormat.extensions[0]);
    if (files && s.panorama.empty() && !s.exposure_layers) check_output_path(l.output, s.overwrite);
    s.layers.push_back(std::move(l));
  }
  s.pano = parse_spec(args.optional_text("to").value_or("equirect"));
  if (gives_photometry(*s.pano))
    throw Error("to: " + s.pano->str() +
                ": photometric keys describe a lens (the panorama's exposure is --exposure, its "
                "response lens 0's)");
  s.canvas = s.options.size ? *s.options.size : default_size(*s.pano, density);
  make_projection(*s.pano, s.canvas);
  s.project.pano.width = s.canvas.width, s.project.pano.height = s.canvas.height;
  for (const StitchLayer& l : s.layers)
    if (layer_extent(s, l).width() == 0) {
      const RigLens& lens = rig.lenses[static_cast<size_t>(l.index)];
      throw Error(rig.path + " line " + std::to_string(lens.line) + ": " + lens.name +
                  " has no pixel on the panorama (its image, crop and field, at its pose, see "
                  "none of the canvas)");
    }
}

// The input: a rig (its lenses; the plan's project has its path) or a Hugin project (the plan's),
// and the rows the other kind takes refused.
std::optional<LensRig> read_input(const Arguments& args, StitchPlan& s) {
  if (!is_rig_path(args.text("project"))) {
    s.project = read_pto(args.text("project"));
    for (const char* row : {"size", "to"})
      if (given(args, row))
        throw Error(std::string(row) + ": a rig's panorama; " + s.project.path +
                    "'s is its p line (its projection, w and h)");
    return std::nullopt;
  }
  LensRig rig = read_lens_rig(args.text("project"));
  s.project.path = rig.path;
  s.project.pano.output = "r:CROP";
  if (given(args, "image"))
    throw Error("image: a Hugin project's; " + rig.path + " is a rig (its lenses blend as one)");
  return rig;
}

// nona's exposure layers: layers' files (LDR, each group at its own exposure), their paths free.
void check_exposure_layers(const Arguments& args, const StitchPlan& s) {
  for (const char* row : {"exposure", "ignore_exposure", "image"})
    if (given(args, row))
      throw Error(std::string("create_exposure_layers and ") + row +
                  ": each exposure layer is blended at its group's own exposure (drop " + row +
                  ")");
  if (s.hdr)
    throw Error("create_exposure_layers: the layers are LDR, for enfuse (drop output_mode hdr" +
                std::string(s.project.pano.hdr
                                ? "; the project's p line says R1: give output_mode ldr"
                                : "") +
                ")");
  const std::string prefix = args.text("output");
  for (size_t k = 0; k < exposure_groups(s).size(); ++k)
    check_output_path(layer_path(prefix, k, kTiffFormat.extensions[0]), s.overwrite);
}

// The outputs checked: the panorama's path (a video's for video inputs, and only then), or the
// layers' (distinct).
StitchPlan checked_outputs(const Arguments& args, bool files, StitchPlan& s) {
  if (s.exposure_layers && (!files || !s.panorama.empty() || !s.videos.empty()))
    throw Error("create_exposure_layers: one TIFF per exposure group under a prefix; " +
                (files ? args.text("output") + " is a blended panorama" : std::string("arrays")) +
                " (give a prefix such as layer_)");
  if (!s.videos.empty()) {
    for (const StitchLayer& l : s.layers)
      if (l.input < 0)
        throw Error("input " + l.file + " is an image among videos (" + s.videos[0] +
                    "): give every input as a video, or every one as images");
    check_video_output(args, s);
    check_output_path(s.panorama, s.overwrite);
    for (const std::string& v : s.videos)
      if (same_file(v, s.panorama)) throw Error("output " + s.panorama + " is an input");
    return std::move(s);
  }
  if (video_container_of(s.panorama))
    throw Error("output " + s.panorama +
                " is a video: its inputs are images (give an image "
                "output such as pano.jpg, or videos as the inputs)");
  if (files && !s.panorama.empty()) {
    format_of_path(s.panorama);
    check_output_path(s.panorama, s.overwrite);
  } else if (files && s.exposure_layers) {
    check_exposure_layers(args, s);
  } else if (files) {
    std::vector<std::pair<std::string, std::string>> outputs;
    for (const StitchLayer& l : s.layers) {
      outputs.push_back({"layer", l.output});
      if (s.hdr) outputs.push_back({"weights", l.weights});
    }
    require_distinct_outputs(outputs);
  }
  return std::move(s);
}

}  // namespace

StitchPlan plan_stitch(const Arguments& args, StitchMade made,
                       const std::vector<ImageInfo>* arrays) {
  const bool files = made == StitchMade::Files;
  StitchPlan s;
  const std::optional<LensRig> lenses = read_input(args, s);
  const bool rig = lenses.has_value();
  const PtoProject& p = s.project;
  s.options = args.options();
  if (!args.optional_text("antialias")) s.options.antialias = Antialias{};  // off, as nona
  s.options.interp = args.optional_text("interp") ? parse_interp(*args.optional_text("interp"))
                     : rig                        ? Interp::Bicubic
                                                  : project_interp(p.interpolator);
  s.depth = depth_of(args, p);
  s.output = output_of(args, rig ? std::nullopt : std::optional<PtoProject>(p));
  s.ignore_exposure = args.flag("ignore_exposure");
  s.hdr = s.output.hdr;
  s.exposure_layers = args.flag("create_exposure_layers");
  if (s.hdr && !s.depth) s.depth = PixelType::F32;  // as nona's HDR output
  s.compression = compression_of(args, p);
  s.overwrite = args.flag("overwrite");
  const std::string extent = args.optional_text("extent").value_or(
      p.pano.output.find("r:CROP") != std::string::npos ? "crop" : "canvas");
  if (extent != "crop" && extent != "canvas")
    throw Error("extent: " + extent + " (expected crop or canvas)");
  s.cropped = extent == "crop";
  const std::string prefix = args.text("output");
  if (made == StitchMade::PanoramaArray)
    s.panorama = "(array)";
  else if (files && (format_of_extension(std::filesystem::path(prefix).extension().string()) ||
                     video_container_of(prefix)))
    s.panorama = prefix;
  blend_of(args, s);
  if (rig) {
    rig_layers(args, *lenses, files, prefix, arrays, s);
    rig_output(args, s);
    correct_layers(s, s.output);
    return checked_outputs(args, files, s);
  }
  const std::vector<std::string> given = args.paths("images");
  if (!given.empty() && given.size() != p.images.size())
    throw Error("images: " + std::to_string(given.size()) + " files for a project of " +
                std::to_string(p.images.size()) + " images");
  if (arrays && arrays->size() != p.images.size())
    throw Error("arrays: " + std::to_string(arrays->size()) + " for a project of " +
                std::to_string(p.images.size()) + " images (one per image, in order)");
  const std::filesystem::path folder = std::filesystem::path(p.path).parent_path();
  const std::optional<int64_t> only = args.optional_integer("image");
  if (only && (*only < 0 || *only >= static_cast<int64_t>(p.images.size())))
    throw Error("image: " + std::to_string(*only) + " (the project has images 0 to " +
                std::to_string(p.images.size() - 1) + ")");
  s.pano = parse_spec(pano_spec(p));
  s.canvas = {p.pano.width, p.pano.height};
  make_projection(*s.pano, s.canvas);
  for (size_t i = 0; i < p.images.size(); ++i) {
    const PtoImage& im = p.images[i];
    if (only && static_cast<int64_t>(i) != *only) continue;
    if (im.disabled && only)
      throw Error("image: " + std::to_string(*only) +
                  " is disabled in the project (#-hugin disabled before line " +
                  std::to_string(im.line) + ")");
    if (im.disabled) continue;
    StitchLayer l;
    l.index = static_cast<int>(i);
    l.file = given.empty() ? (folder / im.name).string() : given[i];
    l.output = layer_path(prefix, i, kTiffFormat.extensions[0]);
    // nona's HDR weights: PREFIX0000_gray.pgm.
    if (s.hdr) l.weights = layer_path(prefix, i, "_gray" + std::string(kPnmFormat.extensions[1]));
    s.layers.push_back(std::move(l));
  }
  for (StitchLayer& l : s.layers) {
    const PtoImage& im = p.images[static_cast<size_t>(l.index)];
    const ImageInfo info = l.info =
        input_info(l.file, static_cast<size_t>(l.index), arrays, s, l.input);
    l.size = info.size;
    l.sx = static_cast<double>(info.size.width) / static_cast<double>(im.width);
    l.sy = static_cast<double>(info.size.height) / static_cast<double>(im.height);
    // Another size: scaled as Hugin's "change image" does, where the aspect is the project's (to
    // a pixel); else refused, as nona's remapImage() does.
    if (std::fabs(l.sx * static_cast<double>(im.height) - static_cast<double>(info.size.height)) >
        1.0)
      throw Error(l.file + ": " + size_text(info.size) + " where the project (line " +
                  std::to_string(im.line) + ") says " + size_text({im.width, im.height}) +
                  ": another aspect cannot be scaled to it");
    l.spec = parse_spec(image_spec(p, im, l.sx, l.sy));
    l.lens = parse_spec(image_spec(p, im));
    l.rotation = image_rotation(im);
    make_projection(*l.spec, l.size);
    l.model = image_photometry(p, im);
    l.model_size = {im.width, im.height};
    l.model_of = p.path + ":" + std::to_string(im.line) + ": i line";
    l.channels = info.channels;
    if (files && s.panorama.empty() && !s.exposure_layers) check_output_path(l.output, s.overwrite);
    if (files && s.panorama.empty() && s.hdr) check_output_path(l.weights, s.overwrite);
  }
  if (s.layers.empty()) throw Error(p.path + ": no image to render (all are disabled)");
  correct_layers(s, s.output);
  return checked_outputs(args, files, s);
}

namespace {

Report run_panorama(const Arguments& args, const StitchPlan& plan, const JobEvents& events) {
  WriteOptions write;
  write.overwrite = plan.overwrite;
  write.quality = static_cast<int>(args.integer("quality"));
  if (write.quality < 1 || write.quality > 100)
    throw Error("quality: " + std::to_string(write.quality) + " (expected 1 to 100)");
  write.subsampling = parse_subsampling(args.text("subsampling"));
  write.threads = plan.options.threads;
  // An equirect says where it sits in the sphere (Photo Sphere XMP), as convert's.
  const Projection pano = make_projection(*plan.pano, plan.canvas);
  if (const auto* e = std::get_if<Equirect>(&pano))
    write.xmp = photo_sphere_xmp(photo_sphere_of(*e));
  const PixelType type = panorama_type(plan);
  int colour = 1;
  for (const StitchLayer& l : plan.layers) colour = l.channels >= 3 ? 3 : colour;
  // A TIFF under classic TIFF's 4 GiB is written as the layers are (its strips compressed on
  // every thread); other formats, and larger TIFFs, as convert writes them.
  const bool tiff = &format_of_path(plan.panorama) == &kTiffFormat &&
                    image_bytes(plan.canvas, colour + 1, bytes_of(type)) < (uint64_t{1} << 32) &&
                    type != PixelType::F16;
  std::optional<StreamedOutput> output;
  if (!tiff) output.emplace(plan.panorama, write, plan.canvas, colour + 1, type);
  const BlendedPanorama b = blend_panorama(
      plan, type,
      [&](const Image& image, const PixelRect& rows) {
        if (output && output->streams()) output->done(image, rows);
      },
      events.progress);
  if (output) {
    output->finish(b.image).write();
  } else {
    const TiffLayerFile file =
        encode_tiff_layer(b.image, {0, 0, plan.canvas}, plan.compression, plan.options.threads);
    OutputSet set(plan.overwrite);
    set.add(plan.panorama, file.pieces());
    set.commit();
  }
  if (events.line)
    events.line(plan.panorama + ": " + size_text(plan.canvas) + ", " +
                std::to_string(plan.layers.size()) + " images, " +
                (plan.blend.multiband ? "multiband (" + std::to_string(b.levels) + " levels)"
                                      : std::string("feather")));
  return {{"output", {plan.panorama}},
          {"canvas", report_size(plan.canvas)},
          {"blend", {std::string(plan.blend.multiband ? "multiband" : "feather")}},
          {"levels", {static_cast<int64_t>(b.levels)}}};
}

// nona's exposure layers: each group blended at its first layer's exposure, written as a layer
// TIFF of the whole canvas; all land together or none.
Report run_exposure_layers(const Arguments& args, const StitchPlan& plan, const JobEvents& events) {
  const std::vector<std::vector<size_t>> groups = exposure_groups(plan);
  OutputSet set(plan.overwrite);
  std::vector<ReportValue> layers;
  for (size_t g = 0; g < groups.size(); ++g) {
    StitchPlan group = plan;
    group.layers.clear();
    for (size_t i : groups[g]) group.layers.push_back(plan.layers[i]);
    PhotometricOutput out = plan.output;
    out.exposure = group.layers[0].model.exposure;
    correct_layers(group, out);
    const PixelType type = panorama_type(group);
    const BlendedPanorama b = blend_panorama(group, type, {}, [&](double f) {
      if (events.progress) events.progress((static_cast<double>(g) + f) / groups.size());
    });
    const std::string path = layer_path(args.text("output"), g, kTiffFormat.extensions[0]);
    const TiffLayerFile file =
        encode_tiff_layer(b.image, {0, 0, plan.canvas}, plan.compression, plan.options.threads);
    set.add(path, file.pieces());
    std::vector<ReportValue> images;
    for (const StitchLayer& l : group.layers) images.push_back({static_cast<int64_t>(l.index)});
    if (events.line) {
      std::string list;
      for (const StitchLayer& l : group.layers)
        list += (list.empty() ? "" : ", ") + std::to_string(l.index);
      char ev[32];
      std::snprintf(ev, sizeof ev, "%.3g", out.exposure);
      events.line(path + ": " + size_text(plan.canvas) + ", images " + list + " at " + ev + " EV");
    }
    layers.push_back({std::vector<ReportField>{
        {"output", {path}}, {"images", {images}}, {"exposure", {out.exposure}}}});
  }
  set.commit();
  return {{"layers", {layers}}, {"canvas", report_size(plan.canvas)}};
}

Report run(const Arguments& args, const JobEvents& events) {
  const StitchPlan plan = plan_stitch(args);
  if (events.warning)
    for (const StitchLayer& l : plan.layers)
      if (const std::string why =
              unused_photometry(plan.project, plan.project.images[static_cast<size_t>(l.index)]);
          !why.empty())
        events.warning(why);
  if (!plan.videos.empty()) return run_stitch_video(plan, events);
  if (!plan.panorama.empty()) return run_panorama(args, plan, events);
  if (plan.exposure_layers) return run_exposure_layers(args, plan, events);
  OutputSet set(plan.overwrite);
  std::vector<ReportValue> layers;
  for (size_t k = 0; k < plan.layers.size(); ++k) {
    const StitchLayer& l = plan.layers[k];
    check_interrupt();
    const RenderedLayer r = render_layer(plan, l);
    if (r.image.size().width == 0) {
      if (events.warning)
        events.warning(l.file + ": no pixel on the panorama's canvas (no layer written)");
      continue;
    }
    const TiffLayerFile file =
        encode_tiff_layer(r.image, {r.x, r.y, plan.canvas}, plan.compression, plan.options.threads);
    const std::vector<std::string_view> pieces = file.pieces();
    set.add(l.output, pieces);
    if (plan.hdr) {
      const FileBytes gray = encode_pnm(r.weights, l.weights);
      set.add(l.weights, std::string_view(reinterpret_cast<const char*>(gray.data()), gray.size()));
    }
    if (events.line)
      events.line(l.output + ": " + size_text(r.image.size()) + " at " + std::to_string(r.x) + "," +
                  std::to_string(r.y) + " of " + size_text(plan.canvas));
    if (events.progress)
      events.progress(static_cast<double>(k + 1) / static_cast<double>(plan.layers.size()));
    layers.push_back(
        {std::vector<ReportField>{{"output", {l.output}},
                                  {"image", {static_cast<int64_t>(l.index)}},
                                  {"offset", {std::vector<ReportValue>{{r.x}, {r.y}}, true}},
                                  {"size", report_size(r.image.size())}}});
  }
  set.commit();
  return {{"layers", {layers}}, {"canvas", report_size(plan.canvas)}};
}

}  // namespace

const JobDef stitch_job{
    .name = "stitch",
    .summary =
        "a Hugin project's images or a rig's lenses blended into a panorama, or remapped into "
        "layers for enblend (as nona -m TIFF_m)",
    .python =
        "Blends a Hugin project's (.pto) images, or a rig's lenses (.yaml, .yml, .json), into "
        "one panorama where the output is an image file (pano.jpg), else remaps them onto the "
        "panorama as layer TIFFs for enblend (PREFIX0000.tif, ...: RGBA, unassociated alpha, "
        "placed on the canvas as nona -m TIFF_m writes them).",
    .rows = stitch_rows,
    .run = run,
};

}  // namespace panoproj
