#pragma once
// The conversion options: their values (the kernel, the engine, antialiasing, edges), the
// ConvertOptions that carry them, and the table that declares them once (lib/src/engine/
// options.cpp): the command adds a flag per row to each subcommand that takes it, Python's
// convert/build_map/Plan take a keyword per row (their signatures and docstrings are made from
// it), and both set ConvertOptions through the row's setter. A new option is a ConvertOptions
// field, a row, and the code that uses it.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "panoproj/image.hpp"

namespace panoproj {

// Interpolation kernels (lib/src/sampling/interpolator.hpp has their taps and weights):
//   nearest   1 tap: the pixel containing the sample; pixels are copied untouched.
//   bilinear  2 taps, tent.
//   bicubic   4 taps, Keys cubic convolution with a = -0.5 (Catmull-Rom), Keys, "Cubic
//             convolution interpolation for digital image processing", IEEE TASSP 29(6), 1981.
//   lanczos3  6 taps, sinc(t) sinc(t/3), weights normalized to sum 1.
//   bicubic-dering, lanczos3-dering: the same, each channel clamped to the range of the 2x2 taps
//             around the sample (with alpha: premultiplied). Their negative lobes over- and
//             undershoot at sharp edges (dark rings around an HDR sun, negative values); the
//             clamp removes that and leaves samples inside the local range (most of a smooth
//             image) untouched.
enum class Interp { Nearest, Bilinear, Bicubic, Lanczos3, BicubicDering, Lanczos3Dering };
const char* name_of(Interp k);
Interp parse_interp(std::string_view name);  // throws panoproj::Error

enum class Engine {
  Simd,       // tiles; fused SIMD geometry for the common pairs (else interpolated coordinates);
              // SIMD sampling where no edge is touched (default)
  Scalar,     // the same tiles, interpolated coordinates, reference sampling everywhere
  Reference,  // exact per-pixel double geometry and sampling (lib/src/sampling/resample.hpp)
};

Engine parse_engine(std::string_view name);  // throws panoproj::Error
const char* name_of(Engine e);

// Antialiasing where a conversion shrinks. An output pixel whose footprint in the source spans
// more than a source pixel averages over it instead of interpolating at its centre alone:
//   auto        per 64x64 tile, s = the median over 3 x 3 points (corners, edge middles, centre)
//               of the footprint's side: the geometric mean of the map's steps to the next pixel
//               along x and along y, in source pixels (each the shorter of the steps before and
//               after it, so that a seam or face edge does not count). Tiles with s <= 2 are
//               sampled as without antialiasing, bit for bit. The others take the footprint
//               kernel (footprint_kernel.hpp): each pixel the mean of the source pixels under its
//               footprint, weighted by their overlap with a box of the footprint's widths along
//               x and y (up to 5 source pixels, 6 taps), whatever the interpolator; where the
//               footprint is wider than that (s > 5, with x steps on an equirect counted at
//               cos(latitude): its rows near the poles hold far more samples than detail), n x n
//               sub-pixels, n = ceil(s / 5) up to 4, each through the kernel (chosen by
//               measurement: docs/decisions.md).
//   N (2..16)   N x N sub-pixels everywhere: the area average as N grows, at N^2 times the
//               sampling.
//   mip         mip levels (pyramid.hpp: level k is the source shrunk 2^k times by 2x2 box
//               means). rho, the side of a pixel's footprint in source pixels, is the geometric
//               mean of the map's steps to the next pixel along x and along y (each the smaller
//               of the forward and backward step, so that a seam or face edge between
//               neighbours does not count); the pixel samples with the chosen kernel the two
//               levels around r = rho / 2, 2^k <= r < 2^(k+1), blended linearly in r. Bilinear at
//               level log2(rho / 2) spans rho source pixels: for a uniform shrink by 2^(k+1) it is
//               exactly the area average (docs/decisions.md: the alternatives measured). Pixels
//               with r <= 1 (rho <= 2) are sampled as without antialiasing, bit for bit.
//   off         one sample at the pixel centre.
struct Antialias {
  enum class Mode { Off, Auto, Supersample, Mip };
  Mode mode = Mode::Off;
  int n = 1;  // sub-pixels per axis (Supersample)
  static constexpr int kMaxAuto = 4;  // auto's largest n
};

// "off", "auto", "mip" or a sub-pixel count 2..16; throws panoproj::Error naming the text.
Antialias parse_antialias(std::string_view text);
std::string name_of(const Antialias& a);

// Edges: what output pixels without a source, or only partly covered by one, get (the
// converter's finishing pass, off by default: such pixels are 0, alpha 0, decided at their
// centres).
//   soft:   a pixel on the field's edge (its 3x3 neighbourhood has pixels with and without a
//           source) is the mean of its 4x4 sub-positions that have one, and its coverage c (their
//           share) scales its alpha: antialiased edges instead of stairs.
//   colour: the uncovered share gets this colour (unit range: 1 is 255 for uint8; opaque), so an
//           edge pixel is c x its mean + (1 - c) x colour and a pixel without a source is colour.
struct EdgeFill {
  bool soft = false;
  std::optional<std::array<double, 4>> colour;  // r, g, b, a: channels beyond the image's are ignored
  bool active() const { return soft || colour.has_value(); }
};

// "R,G,B" or "R,G,B,A" (unit range; any finite value for float images) or "#rrggbb" /
// "#rrggbbaa" (hex bytes / 255). Throws panoproj::Error naming the text and the forms.
std::array<double, 4> parse_fill_colour(std::string_view text);

struct ConvertOptions {
  double yaw = 0, pitch = 0, roll = 0;  // degrees, see rotation.hpp
  Interp interp = Interp::Bicubic;
  int threads = 0;                      // 0: all cores
  Engine engine = Engine::Simd;         // see Engine above
  std::optional<Antialias> antialias;   // see Antialias above; default: auto, off for the
                                        // reference engine (which has none)
  std::optional<Size> size;             // output size; default: default_size() at the source's
                                        // centre density (square pixels)
  std::optional<int64_t> face_size;     // a cube target's faces, N x N (its spec's face=N)
  EdgeFill edges;                       // EdgeFill above: pixels without a (whole) source
  bool add_alpha = false;               // give a source without alpha an opaque one first, so
                                        // the output has alpha (0 where it has no source)
  int64_t memory_limit = 0;             // bytes a job may allocate; 0: the memory available
                                        // (limits.hpp)
  int decode_scale = 0;                 // file jobs: decode a JPEG source at 1/decode_scale (1,
                                        // 2, 4, 8); 0 (auto): coarsest_decode_scale (convert.hpp)
};

// How front ends hand a value over: a number of degrees, an integer, a flag, text the row's
// setter or job parses (sizes "WxH", choices, colours, byte counts), a path, or several paths.
enum class OptionType { Angle, Integer, Flag, Text, Path, Paths };
using OptionValue = std::variant<double, int64_t, bool, std::string, std::vector<std::string>>;

// Which calls take a conversion option (bits).
// kUseFiles: only conversions between files (the command's convert), e.g. how a file is decoded.
// kUseTiles: tile pyramids, which render from a file too.
// kUseViews: perspective views with cameras; size is each view's.
// kUseStitch: a project's layers (its own interp row: the project's by default).
enum OptionUse : unsigned {
  kUseConvert = 1,
  kUseMaps = 2,
  kUseAccuracy = 4,
  kUseFiles = 8,
  kUseTiles = 16,
  kUseViews = 32,
  kUseStitch = 64
};

// How a front end shows a row (bits): positional (the command's positional, Python's positional
// argument), required, and rows only one front end has.
enum OptionTrait : unsigned {
  kPositional = 1,
  kRequired = 2,
  kCommandOnly = 4,
  kPythonOnly = 8,
  kNeither = 16
};

// One row type for the conversion options and every job's parameters (jobs.hpp).
struct OptionDef {
  const char* name;          // Python's keyword; the command's flag is --name with '-' for '_'
  OptionType type;
  unsigned use;              // OptionUse bits (conversion options; 0 for a job's own rows)
  const char* default_text;  // the default as Python writes it ("None": derived or unset)
  const char* help;          // one line, for --help and docstrings
  // A conversion option stores the value; throws Error naming the option and what it expects. A
  // value of the wrong alternative is an InternalError (the front ends convert by `type`). A
  // job's own rows have none: the job reads them (Arguments).
  void (*set)(ConvertOptions& options, const OptionValue& value) = nullptr;
  const char* choices = nullptr;  // "a|b|c" for a Text option that takes names (Python's Literal)
  const char* flag = nullptr;     // the command's spelling where not from the name ("from",
                                  // "-q,--quiet"; a positional's name)
  unsigned traits = 0;            // OptionTrait bits
};

const std::vector<OptionDef>& conversion_options();
// The row named `name` (Python's spelling); throws Error listing the names `use` allows.
const OptionDef& conversion_option(std::string_view name, unsigned use);
// "--memory-limit" for "memory_limit", "--from" for src (its flag); a positional's name.
std::string flag_of(const OptionDef& option);
// The command's text of a value option as its type's value ("nan" and "inf" pass as numbers: the
// plan names them); throws Error naming the flag for text that is not one. (Flags have no text.)
OptionValue option_value(const OptionDef& option, const std::string& text);

// "WxH", both positive integers; throws Error naming `what`.
Size parse_size(std::string_view text, std::string_view what = "size");

}  // namespace panoproj
