#pragma once
// What of each image a layer keeps, as Hugin decides it (Panorama::updateMasks): its crop (S: a
// rectangle, or for circular crops the circle inscribed in it), its exclude masks (k t0),
// its stack's (t2) and its lens's (t4, every image of that lens); and in the panorama, other
// images' include masks (t1: excluded from every other image there; t3: from the images outside
// its stack) and its stack's exclude masks (t2, through the panorama). Points are in Hugin's
// pixel coordinates (pixel centres at integers: panoproj's position - 0.5).
#include <optional>
#include <vector>

#include "jobs/stitch/pto_project.hpp"
#include "panoproj/image.hpp"

namespace panoproj {

// The image's crop circle in Hugin's positions: a rig's, or the one inscribed in the S rectangle
// of a circular crop (circular fisheyes f2, Thoby's f20 and orthographic f8, as
// SrcPanoImage::isCircularCrop says); none for a rectangle or no crop.
struct CropCircle {
  double cx, cy, radius;
};
std::optional<CropCircle> crop_circle(const PtoImage& image);
// Whether Hugin position (x, y) of the image is inside its crop (true without one).
bool inside_crop(const PtoImage& image, double x, double y);
// Whether Hugin position (x, y) is inside the region an include mask of the image counts in
// (Panorama::transferMask): its crop rectangle (the frame without one), or its crop circle, 2 px
// inside where that is over 10 px.
bool inside_include_clip(const PtoImage& image, double x, double y);
// Where the polygon x0 y0 x1 y1 ... crosses the line at y, sorted; (x, y) is inside it (the
// even-odd rule) where an odd number of them lie right of x.
std::vector<double> crossings(const std::vector<double>& xy, double y);
bool inside_polygon(const std::vector<double>& xy, double x, double y);

// The image-space masks of image `index`: its exclude masks (t0, t2) and its lens's (t4).
std::vector<const PtoMask*> image_masks(const PtoProject& project, int index);

// Clears the alpha (the last channel) of `source`, the file of image `index` at (sx, sy) times
// the project's size, outside its crop and inside its image-space masks.
void mask_source(const PtoProject& project, int index, double sx, double sy, Image& source);

// A mask of another image that removes what it covers from image `index`'s layer (found through
// the panorama), and whether it counts only within inside_include_clip (include masks).
struct PanoExclusion {
  int image;
  const PtoMask* mask;
  bool within_crop;
};
std::vector<PanoExclusion> pano_exclusions(const PtoProject& project, int index);

}  // namespace panoproj
