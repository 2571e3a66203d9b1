#pragma once
// A Hugin / Panorama Tools project (.pto): the p (panorama), m (options), i (image) and k (mask)
// lines and Hugin's `#-hugin` image comments; v (optimizer variables) and c (control points)
// lines are read past. Links (`v=0`: image 0's value) are resolved; every number is checked
// finite and in range. Errors name the file, line and token ("a.pto:7: i line: token ...").
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace panoproj {

struct PtoRect {
  int64_t left = 0, right = 0, top = 0, bottom = 0;  // right and bottom exclusive
};

struct PtoImage {
  int line = 0;
  std::string name;  // as written (relative to the .pto's folder)
  int64_t width = 0, height = 0;
  int lens_type = 0;  // f
  double hfov = 0, yaw = 0, pitch = 0, roll = 0;
  double a = 0, b = 0, c = 0, d = 0, e = 0, g = 0, t = 0;
  int stack = 0;  // the image its stack number (j) links to, itself if none
  int lens = 0;   // the image its field of view (v: the lens) links to, itself if none
  std::optional<PtoRect> crop;  // S
  bool disabled = false;        // #-hugin disabled
  // A rig's crop circle (not a .pto's: Hugin's circles are its S rectangle's): centre x, y and
  // radius in Hugin's positions (pixel centres at integers).
  std::optional<std::array<double, 3>> circle;
  // Photometry (Hugin's defaults where not given).
  int response_type = 0;                         // Rt: 0 EMoR, 1 linear
  std::array<double, 5> emor{};                  // Ra..Re
  double exposure = 0;                           // Eev
  double red = 1, blue = 1;                      // Er Eb
  std::array<double, 4> vignetting{1, 0, 0, 0};  // Va..Vd, as Hugin reads them (below)
  double vignetting_x = 0, vignetting_y = 0;     // Vx Vy
  int vignetting_mode = 0;                       // Vm as written (0 if not)
  std::string flat_field;                        // Vf as written
};

struct PtoMask {
  int line = 0;
  int image = 0;
  int type = 0;            // 0 exclude, 1 include, 2 exclude stack, 3 include stack, 4 exclude lens
  std::vector<double> xy;  // x0 y0 x1 y1 ... (image pixels)
};

struct PtoPanorama {
  int line = 0;
  int projection = 0;  // f
  int64_t width = 0, height = 0;
  double hfov = 0;
  std::optional<PtoRect> crop;  // S
  std::vector<double> params;   // P"..."
  std::string depth;            // T"UINT8" | "UINT16" | "FLOAT" ("": the images' own)
  std::string output;           // n"TIFF_m c:LZW ..."
  double exposure = 0;          // E: the output's exposure value
  bool hdr = false;             // R1 (R0: LDR)
};

struct PtoProject {
  std::string path;
  PtoPanorama pano;
  int interpolator = 0;  // m i
  std::vector<PtoImage> images;
  std::vector<PtoMask> masks;
};

// Projects are at most this many bytes and images (a line each).
inline constexpr int64_t kMaxPtoBytes = int64_t{64} << 20;
inline constexpr int kMaxPtoImages = 65536;

// Parses `text` (the file at `path`, named in errors); throws Error.
PtoProject parse_pto(std::string_view text, const std::string& path);
// Reads and parses the file (a regular file of at most kMaxPtoBytes).
PtoProject read_pto(const std::string& path);

}  // namespace panoproj
