#pragma once
// What output pixels without a source, or only partly covered by one, get (the converter's
// finishing pass, off by default: such pixels are 0, alpha 0, decided at their centres).
//   soft:   a pixel on the field's edge (its 3x3 neighbourhood has pixels with and without a
//           source) is the mean of its 4x4 sub-positions that have one, and its coverage c (their
//           share) scales its alpha: antialiased edges instead of stairs.
//   colour: the uncovered share gets this colour (unit range: 1 is 255 for uint8; opaque), so an
//           edge pixel is c x its mean + (1 - c) x colour and a pixel without a source is colour.
#include <array>
#include <optional>
#include <string_view>

namespace panoproj {

struct EdgeFill {
  bool soft = false;
  std::optional<std::array<double, 4>> colour;  // r, g, b, a: channels beyond the image's are ignored
  bool active() const { return soft || colour.has_value(); }
};

// "R,G,B" or "R,G,B,A" (unit range; any finite value for float images) or "#rrggbb" /
// "#rrggbbaa" (hex bytes / 255). Throws panoproj::Error naming the text and the forms.
std::array<double, 4> parse_fill_colour(std::string_view text);

}  // namespace panoproj
