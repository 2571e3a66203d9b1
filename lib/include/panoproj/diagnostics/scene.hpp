#pragma once
// Synthetic scenes defined on the sphere of directions: the ground truth of the accuracy
// measurements (`panoproj accuracy`, the tests). Rendered straight into any projection, each
// pixel the mean of s x s rays through its stratified sub-pixel centres (the pixel's area
// average as s grows), so no conversion is involved in the truth.
//   waves     band-limited: a few plane waves of the ray, periods >= 0.055 in the ray's
//             coordinates (>= 3 degrees on the sphere), per channel; every kernel can represent it
//   chart     sharp: a 72-spoke star around the forward axis (0.1 / 0.9 sectors), whose spokes
//             converge at the front and back: aliasing shows at any scale
//   gradient  smooth: colour = (1 + ray) / 2
//   sun       HDR: a sky brightening towards the zenith (0.05 .. 1) and a sun of radius 0.5
//             degree and radiance 20000 at longitude 40, latitude 30 (float images keep it)
// Values are in [0, 1] but the sun's; integer images scale them to the type's range.
#include <array>
#include <string_view>

#include "panoproj/image.hpp"
#include "panoproj/projection.hpp"

namespace panoproj {

enum class Scene { Waves, Chart, Gradient, Sun };

Scene parse_scene(std::string_view name);  // throws panoproj::Error
const char* name_of(Scene s);

// RGB radiance along unit ray d.
std::array<double, 3> scene_radiance(Scene s, const Ray& d);

// The scene in projection p: 3 channels of `type`, each pixel the mean over its s x s sub-pixel
// rays that have a pixel's ray (to_ray); 0 where the pixel centre has none, as the engine's outputs.
Image render_scene(Scene s, const Projection& p, PixelType type, int supersample, int threads);

}  // namespace panoproj
