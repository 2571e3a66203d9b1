#pragma once
// The photometric keys every projection spec takes (projection_catalog appends them to each
// entry): a source image's photometric model by Hugin's per-image values (photometric.hpp), so
// that convert, views, tiles and a rig's lenses correct it as stitch corrects a project's images:
//   response=emor | linear | Ra/Rb/Rc/Rd/Re   the camera's response: EMoR's mean curve f0
//                     (Hugin's default), linear, or the EMoR coefficients; default emor for
//                     integer images, linear for float ones
//   ev=EV             the image's exposure value (Hugin's Eev)
//   wb=R/B            white balance (Er Eb): red divided by R, blue by B
//   vignetting=a/b/c/d   V = a + b r^2 + c r^4 + d r^6 (Va..Vd; 1 to 4 terms, the rest 0), r
//                     from the lens image's centre over its half diagonal
//   vignetting_centre=X/Y   that centre's shift from the image's (Vx Vy, pixels)
// (A flat field is a file: specs reach layers that read none; a rig's lens takes one.)
// A two-lens frame (dual-fisheye, gopro-max) takes lens 1's as ev2 ... vignetting_centre2, each
// defaulting to lens 0's (one response: the camera's). On a target, ev= is the output's exposure
// (default: the mean of the source lenses'); the other keys describe a source.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "panoproj/spec.hpp"

namespace panoproj {

std::vector<ParamDef> photometric_key_defs(bool two_lenses);
// Whether the spec gives any photometric key.
bool gives_photometry(const ProjectionSpec& s);

// Lens k's keys (k = 1: those ending in 2, else lens 0's), parsed; throws Error naming the spec
// and the key for a value that does not parse (not a number, the wrong count, non-finite).
struct PhotometricKeys {
  std::optional<std::array<double, 5>> emor;  // given coefficients; none: f0 or linear
  std::optional<bool> linear;                 // response=linear (true) or emor/coefficients
  double ev = 0;
  double red = 1, blue = 1;
  std::array<double, 4> vignetting{1, 0, 0, 0};
  double shift_x = 0, shift_y = 0;
};
PhotometricKeys photometric_keys(const ProjectionSpec& s, int lens);

}  // namespace panoproj
