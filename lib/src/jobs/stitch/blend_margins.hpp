#pragma once
// How far inside its image a panorama pixel lies, for the blended panorama's weights: the image's
// valid edge is its frame and crop (the S rectangle, or its circle for circular crops); the
// distance to it, in the image's pixels, over its lens's pixels per radian at the centre, is the
// margin (radians, as a dual fisheye's lens margin: negative outside). A fisheye lens is bounded
// by its field too, where its pixels end inside the frame: its margin is at most the field's half
// angle less the ray's angle from its axis (a rig's fisheye spec: psi_max, a dual fisheye's lens
// margin exactly; a project's fisheye types: where their law ends, an orthographic's 90 degrees).
// Geometry alone: the same for every frame of a template. Masks are not edges here: they cut the
// layer's alpha.
#include <Eigen/Core>
#include <vector>

#include "jobs/stitch/stitch.hpp"
#include "panoproj/image.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

// A margin where the image has no pixel for the ray (behind a lens).
inline constexpr float kNoMargin = -10.0f;

class LayerMargin {
 public:
  LayerMargin(const StitchPlan& plan, const StitchLayer& layer);
  // At panorama ray d.
  double at(const Ray& d) const;
  // Over `rect` of the panorama `pano` (the canvas), row-major: exact at the nodes every kStep
  // pixels of the canvas, bilinear between them where a cell's four nodes have pixels, else exact
  // at every pixel (none where no node has one). The same at a pixel whatever the rectangle.
  static constexpr int64_t kStep = 8;
  void over(const Projection& pano, const PixelRect& rect, float* out, int threads) const;

 private:
  const PtoImage* image_;
  Projection lens_;
  Eigen::Matrix3d rotation_;
  double per_radian_;  // the lens's pixels per radian at its centre
  double field_ = 0;   // a fisheye's half field (radians); 0: none
};

}  // namespace panoproj
