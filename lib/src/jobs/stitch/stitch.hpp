#pragma once
// The stitch job's plan (every input, spec and output checked before any pixel is made) and the
// rendering of one layer; shared by the job (stitch_job.cpp) and Python's arrays.
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/tiff_layer.hpp"
#include "jobs/stitch/pto_project.hpp"
#include "panoproj/image.hpp"
#include "panoproj/io.hpp"
#include "panoproj/jobs.hpp"
#include "panoproj/options.hpp"
#include "panoproj/spec.hpp"
#include "photometry/photometric.hpp"

namespace panoproj {

struct StitchLayer {
  int index = 0;                       // the project's image
  std::string file;                    // its file
  ImageInfo info;                      // the file's (a video's frames')
  std::shared_ptr<const Image> frame;  // in memory in place of the file (a video's frame)
  int input = -1;    // its in-memory input (plan.videos' index, or the arrays'): frames in place of
                     // the file
  Size size;         // the image's size (the file's, or its region's)
  int channels = 0;  // the file's channels
  double sx = 1, sy = 1;               // the file's size over the project's
  std::optional<ProjectionSpec> spec;  // its lens at the file's size
  std::optional<ProjectionSpec> lens;  // its lens at the project's size (extent, margins)
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // the panorama's rays to the image's
  std::optional<PixelRect> region;  // the rectangle of the file that is the image (a rig's frame)
  std::string output;               // its layer's path
  std::string weights;              // HDR: its weights' path (nona's PREFIX0000_gray.pgm)
  Photometry model;                 // its photometric model (the project's, or its lens spec's)
  Size model_size;                  // the image the model's positions are in (vignetting)
  std::string model_of;             // the model's place, named in its errors
  std::optional<PhotometricStep> photometry;  // its samples' correction (photometric.hpp)
};

// The blended panorama's blend (panorama.hpp).
struct BlendSettings {
  bool multiband = false;     // else the feather
  double feather = INFINITY;  // the feather's ramp (radians): the whole overlap
  int levels = 0;             // multiband's; 0: from the overlaps' width
};

struct StitchPlan {
  PtoProject project;
  std::optional<ProjectionSpec> pano;
  Size canvas;
  std::vector<StitchLayer> layers;  // the images rendered, in the project's order
  ConvertOptions options;           // interp, antialias (off unless given), engine, threads, memory
  std::optional<PixelType> depth;   // none: each image's own (as nona, without -p or T)
  TiffCompression compression = TiffCompression::Deflate;
  bool cropped = true;  // layers cut to their extent (n"... r:CROP"), else the whole canvas
  bool overwrite = false;
  bool hdr = false;      // linear layers (the project's R1 or output_mode hdr), with weights
  std::string panorama;  // the blended panorama's file, "(array)" for an array; empty: layers
  BlendSettings blend;
  std::vector<std::string> videos;  // the inputs that are videos (stitch_video.hpp), in order
  PhotometricOutput output;         // the layers' (each layer's exposure its own with
  bool ignore_exposure = false;     // ignore_exposure)
  bool exposure_layers = false;     // one blended layer per exposure group (exposure_groups)
};

// Each layer's correction (layer.photometry) from its model to `output` (its exposure the
// layer's own with plan.ignore_exposure); throws Error naming the layer's model.
void correct_layers(StitchPlan& plan, const PhotometricOutput& output);

// nona's exposure layers (--create-exposure-layers): the layers in groups, each the first layer
// not yet taken and every later one whose exposure is within kExposureLayerStep (exclusive) of
// it; each group blended at its first layer's exposure.
inline constexpr double kExposureLayerStep = 0.5;
std::vector<std::vector<size_t>> exposure_groups(const StitchPlan& plan);

// What is made: files (the output: a panorama where it names an image format, else the layers'
// prefix; paths checked), or arrays (Python's: the layers, or the blended panorama).
enum class StitchMade { Files, LayerArrays, PanoramaArray };
// arrays: the inputs are in memory (Python's arrays, given to each call of blend_panorama as the
// layers' frames): their infos, one per input (a rig's in the order first named; a project's per
// image), in place of the files'.
StitchPlan plan_stitch(const Arguments& args, StitchMade made = StitchMade::Files,
                       const std::vector<ImageInfo>* arrays = nullptr);

// The part of the canvas nona gives the layer's image (layer_extent.cpp); empty if none.
PixelRect layer_extent(const StitchPlan& plan, const StitchLayer& layer);

// A layer: RGBA (gray + alpha for a gray image) of plan.depth (else the image's), alpha 0 or full
// (nona's rule: a pixel is kept where its kernel's taps with alpha hold over 0.2 of its weight)
// within its extent, cut to the extent where plan.cropped, at (x, y) on the canvas; empty if no
// extent. Its samples are corrected (layer.photometry) in float from the interpolated code values
// unless the correction keeps them. weights: HDR layers' (photometric.hpp), the layer's size.
struct RenderedLayer {
  Image image;
  int64_t x = 0, y = 0;
  Image weights;
};
RenderedLayer render_layer(const StitchPlan& plan, const StitchLayer& layer);

// render_layer's steps, for the blended panorama (panorama.cpp). The samples a layer is made in
// (float where it is corrected or float); the image's file as its source (alpha added, its crop
// and masks in it, in `type`); its pixels in `window` of the canvas (the whole canvas where the
// panorama has no windows), its alpha as render_layer's and 0 outside `extent`, corrected where
// float (weights: as render_layer's).
PixelType layer_work_type(const StitchPlan& plan, const StitchLayer& layer, const ImageInfo& info);
Image layer_source(const StitchPlan& plan, const StitchLayer& layer, PixelType type);
Image render_window(const StitchPlan& plan, const StitchLayer& layer, const Image& source,
                    const PixelRect& window, const PixelRect& extent, Image* weights);

}  // namespace panoproj
