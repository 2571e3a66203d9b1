// The cubemap module (module.hpp): six 90-degree faces in one image (a strip, a 3x2 grid, a
// cross, YouTube's EAC) or six files; face order, turns and padding; the layouts' cells.
#include <sstream>

#include "panoproj/error.hpp"
#include "projections/module.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {

const char* const kFaceNames[6] = {"front", "right", "back", "left", "up", "down"};
const char* const kAxisNames[6] = {"px", "nx", "py", "ny", "pz", "nz"};

namespace {

constexpr const char* kFaceLetters = "frblud";

// The face seen in a cell turned q quarter turns clockwise: the cell's own tangent axes (A right,
// B down) from the face's (a, b): q = 1: (A, B) = (-b, a) (vf_v360.c rotate_cube_face).
CubeFace turned(const CubeFace& f, int q) {
  switch (q & 3) {
    case 1: return {f.fwd, -f.down, f.right};
    case 2: return {f.fwd, -f.right, -f.down};
    case 3: return {f.fwd, f.down, -f.right};
    default: return f;
  }
}

CubeAxis uniform_axis(int n, int64_t f, double pad) {
  CubeAxis a;
  a.n = n;
  const double fd = static_cast<double>(f);
  for (int k = 0; k <= n; ++k) a.edge[k] = k * f;
  for (int k = 0; k < n; ++k) a.center[k] = (k + 0.5) * fd, a.half[k] = 0.5 * fd * (1 - pad);
  return a;
}

// FFmpeg's EAC frame along one axis (vf_v360.c eac_to_xyz): across, three faces (W - 4) / 3
// wide from x = 2; down, rows of H / 2 with faces H / 2 - 4 high from 2 px below the row's top.
// Pixel i belongs to the cell holding its centre i + 0.5.
CubeAxis ffmpeg_axis(int64_t extent, int n) {
  CubeAxis a;
  a.n = n;
  const double e = static_cast<double>(extent);
  if (n == 3) {
    const double fw = (e - 4) / 3;
    a.edge = {0, static_cast<int64_t>(std::ceil(1.5 + fw)), static_cast<int64_t>(std::ceil(1.5 + 2 * fw)), extent};
    for (int k = 0; k < 3; ++k) a.center[k] = 2 + (k + 0.5) * fw, a.half[k] = 0.5 * fw;
  } else {
    const double r = e / 2;
    a.edge = {0, extent / 2, extent};
    for (int k = 0; k < 2; ++k) a.center[k] = (k + 0.5) * r, a.half[k] = 0.5 * r - 2;
  }
  return a;
}

}  // namespace

CubeFormat CubeFormat::eac() {
  CubeFormat f;
  f.order = {3, 0, 1, 5, 2, 4};  // l f r / d b u
  f.rot = {0, 0, 0, 3, 1, 3};
  f.angular = true;
  return f;
}

CubeAxis CubeAxis::scaled(double s) const {
  CubeAxis a = *this;
  for (int k = 0; k <= n; ++k) {
    const double e = static_cast<double>(edge[k]) * s;
    if (e != std::floor(e)) throw Error("a cubemap cell edge at " + std::to_string(edge[k]) + " px does not scale to a whole pixel");
    a.edge[k] = static_cast<int64_t>(e);
  }
  for (int k = 0; k < n; ++k) a.center[k] *= s, a.half[k] *= s;
  return a;
}

std::array<int, 2> Cubemap::grid(CubeLayout layout) {
  switch (layout) {
    case CubeLayout::Files:
    case CubeLayout::Row6x1: return {6, 1};
    case CubeLayout::Column1x6: return {1, 6};
    case CubeLayout::Grid3x2:
    case CubeLayout::Eac: return {3, 2};
    case CubeLayout::Cross4x3: return {4, 3};
    case CubeLayout::Cells:
      break;  // (its own grid)
  }
  return {6, 1};
}

std::array<int, 2> Cubemap::slot_cell(CubeLayout layout, int k) {
  switch (layout) {
    case CubeLayout::Files:
    case CubeLayout::Row6x1: return {k, 0};
    case CubeLayout::Column1x6: return {0, k};
    case CubeLayout::Grid3x2:
    case CubeLayout::Eac: return {k % 3, k / 3};
    case CubeLayout::Cross4x3: {
      static constexpr std::array<std::array<int, 2>, 6> cells = {{{1, 1}, {2, 1}, {3, 1}, {0, 1}, {1, 0}, {1, 2}}};
      return cells[k];
    }
    case CubeLayout::Cells:
      break;
  }
  return {k, 0};
}

std::array<FaceCell, 6> Cubemap::layout_cells(CubeLayout layout, const CubeFormat& format) {
  std::array<FaceCell, 6> cells{};
  for (int k = 0; k < 6; ++k) {
    const auto c = slot_cell(layout, k);
    cells[format.order[k]] = {c[0], c[1], format.rot[k]};
  }
  return cells;
}

Cubemap::Cubemap(CubeLayout layout, const CubeFormat& format, const CubeAxis& ax,
                 const CubeAxis& ay, const std::array<FaceCell, 6>& cells)
    : layout_(layout), format_(format), ax_(ax), ay_(ay), size_{ax.edge[ax.n], ay.edge[ay.n]} {
  const int64_t f = ax.edge[1];
  uniform_ = !format.ffmpeg_border && layout != CubeLayout::Cells;
  partial_ = layout == CubeLayout::Cells;
  for (int k = 0; k < ax.n; ++k) uniform_ = uniform_ && ax.edge[k + 1] - ax.edge[k] == f;
  for (int k = 0; k < ay.n; ++k) uniform_ = uniform_ && ay.edge[k + 1] - ay.edge[k] == f;
  cells_ = cells;
  cell_face_.fill(-1);
  for (int face = 0; face < 6; ++face) {
    const FaceCell& c = cells[face];
    if (c.col < 0) continue;
    slots_[face] = {c.col, c.row, turned(cube_faces()[face], c.rot)};
    cell_face_[c.row * ax_.n + c.col] = face;
  }
}

Cubemap::Cubemap(int64_t face_size, CubeLayout layout, const CubeFormat& format)
    : Cubemap(layout, format, uniform_axis(grid(layout)[0], face_size, format.pad),
              uniform_axis(grid(layout)[1], face_size, format.pad), layout_cells(layout, format)) {}

Cubemap::Cubemap(Size size, const CubeFormat& format)
    : Cubemap(CubeLayout::Eac, format, ffmpeg_axis(size.width, 3), ffmpeg_axis(size.height, 2),
              layout_cells(CubeLayout::Eac, format)) {}

Cubemap::Cubemap(const CubeAxis& ax, const CubeAxis& ay, const std::array<FaceCell, 6>& cells,
                 bool angular)
    : Cubemap(
          CubeLayout::Cells,
          [&] {
            CubeFormat f;
            f.angular = angular;
            for (int face = 0; face < 6; ++face)
              f.order[face] = face, f.rot[face] = cells[face].rot;
            return f;
          }(),
          ax, ay, cells) {}

Cubemap Cubemap::scaled(double sx, double sy) const {
  return Cubemap(layout_, format_, ax_.scaled(sx), ay_.scaled(sy), cells_);
}

std::array<int, 2> Cubemap::other_faces_of(const Ray& d) {
  std::array<int, 3> axis = {0, 1, 2};
  std::stable_sort(axis.begin(), axis.end(), [&](int i, int j) { return std::fabs(d[i]) > std::fabs(d[j]); });
  static constexpr int pos[3] = {1, 5, 0}, neg[3] = {3, 4, 2};
  auto face = [&](int i) { return d[i] >= 0 ? pos[i] : neg[i]; };
  return {face(axis[1]), face(axis[2])};
}

namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"cubemap", "six 90-degree faces: front right back left up down",
           {choice("layout", "6x1", "files|6x1|1x6|3x2|cross|eac",
                   "files: six images (path pattern with {face}, {index} and/or {axis}); cross is 4x3; eac: YouTube's "
                   "equi-angular 3x2 (equal angles per pixel; order lfrdbu, rot 000313)"),
            {"face", ParamType::Integer, "", 1, 1 << 30, false, false, "", "face size in pixels; default: from the source's resolution"},
            {"order", ParamType::Text, "", 0, 0, false, false, "",
             "the faces in the layout's slots, six letters of f r b l u d (FFmpeg's forder); default frblud, eac lfrdbu"},
            {"rot", ParamType::Text, "", 0, 0, false, false, "",
             "each slot's face turned 0-3 quarter turns clockwise, six digits (FFmpeg's frot); default 000000, eac 000313"},
            number("pad", "0", 0, 0.4, false, false,
                   "extra field per face: a cell spans 1 / (1 - pad) of the face's 90 degrees (FFmpeg's in_pad)"),
            {"pad_px", ParamType::Integer, "", 0, 1 << 30, false, false, "",
             "the same in pixels of a cell (FFmpeg's fin_pad): pad = pad_px / cell size"},
            choice("border", "none", "none|ffmpeg",
                   "eac only: ffmpeg = FFmpeg's EAC frame, a 2-px border around each row of faces"),
            choice("preset", "none", "none|threejs|unity",
                   "an engine's cube map: slots in its targets' order +X -X +Y -Y +Z -Z ({axis} px..nz), each "
                   "face turned as it shows them, front where its equirect texture's centre is")}}};
}

CubeLayout cube_layout(const std::string& l) {
  if (l == "files") return CubeLayout::Files;
  if (l == "1x6") return CubeLayout::Column1x6;
  if (l == "3x2") return CubeLayout::Grid3x2;
  if (l == "cross") return CubeLayout::Cross4x3;
  if (l == "eac") return CubeLayout::Eac;
  return CubeLayout::Row6x1;
}

// An engine's cube map (slots +X -X +Y -Y +Z -Z) in panoproj's faces, derived from the cube-map
// face table (OpenGL 4.6 table 8.19, D3D the same) and, for the front, the engine's equirect
// lookup, which centres the image on +X in both:
//   three.js: right-handed, y up; a CubeTexture is looked up at (-x, y, z) (flipEnvMap, "px is
//     the face towards -X"); equirectUv: u = atan2(z, x) / 2pi + 1/2.
//   unity: left-handed, y up; looked up as is; Skybox/Panoramic: u = 1/2 - atan2(z, x) / 2pi.
// Checked by python/tests/test_cube_presets.py against that table and those lookups.
CubeFormat cube_preset(const std::string& name) {
  CubeFormat f;
  if (name == "threejs") f.order = {2, 0, 4, 5, 1, 3}, f.rot = {0, 0, 1, 3, 0, 0};  // b f u d r l
  if (name == "unity") f.order = {0, 2, 4, 5, 3, 1}, f.rot = {0, 0, 3, 1, 0, 0};    // f b u d l r
  return f;
}

// The format the keys give (pad_px needs the cell size).
CubeFormat cube_format(const ProjectionSpec& s, int64_t cell) {
  CubeFormat f = s.choice("layout") == "eac" ? CubeFormat::eac() : cube_preset(s.choice("preset"));
  if (s.given("order")) {
    const std::string o = s.choice("order");
    for (int k = 0; k < 6; ++k) f.order[k] = static_cast<int>(std::string(kFaceLetters).find(o[k]));
  }
  if (s.given("rot"))
    for (int k = 0; k < 6; ++k) f.rot[k] = s.choice("rot")[k] - '0';
  f.pad = s.given("pad_px") ? *s.number("pad_px") / static_cast<double>(cell) : *s.number("pad");
  f.ffmpeg_border = s.choice("border") == "ffmpeg";
  return f;
}

void check(const ProjectionSpec& s) {
  if (s.given("order")) {
    const std::string o = s.choice("order");
    bool ok = o.size() == 6;
    for (char c : std::string(kFaceLetters)) ok = ok && std::count(o.begin(), o.end(), c) == 1;
    if (!ok) fail(s, "order=" + o + " is not six distinct letters of f r b l u d (front right back left up down), e.g. rludfb");
  }
  if (s.given("rot")) {
    const std::string r = s.choice("rot");
    if (r.size() != 6 || r.find_first_not_of("0123") != std::string::npos)
      fail(s, "rot=" + r + " is not six digits 0-3 (quarter turns clockwise per slot), e.g. 000313");
  }
  if (s.given("pad") && s.given("pad_px")) fail(s, "pad and pad_px both given (give one: pad_px = pad x cell size)");
  if (s.choice("border") == "ffmpeg" && s.choice("layout") != "eac") fail(s, "border=ffmpeg needs layout=eac");
  if (s.choice("preset") != "none" && (s.given("order") || s.given("rot") || s.choice("layout") == "eac"))
    fail(s, "preset=" + s.choice("preset") + " sets the order and turns (drop " +
                (s.choice("layout") == "eac" ? std::string("layout=eac") : std::string("order and rot")) + ")");
  if (s.choice("border") == "ffmpeg" && (s.given("pad") || s.given("pad_px")))
    fail(s, "border=ffmpeg has FFmpeg's own 2-px border (drop pad or pad_px)");
}

}  // namespace

FaceOrder cube_face_order(const ProjectionSpec& s) {
  FaceOrder o;
  o.face = cube_format(s, 1).order;
  for (int k = 0; k < 6; ++k) o.axis[k] = s.choice("preset") != "none" ? k : kDefaultFaceOrder.axis[o.face[k]];
  return o;
}

namespace {

Projection make(const ProjectionSpec& s, Size size) {
  const auto layout = cube_layout(s.choice("layout"));
  const auto g = Cubemap::grid(layout);
  const int64_t f = size.width / g[0];
  if (f * g[0] != size.width || f * g[1] != size.height) {
    std::ostringstream o;
    o << "layout=" << s.choice("layout") << " needs a " << g[0] << "F x " << g[1]
      << "F image with square faces; got " << size.width << "x" << size.height
      << " (check the size or the layout; a target's " << option_text("face-size")
      << " N gives N x N faces)";
    fail(s, o.str());
  }
  if (s.given("face") && static_cast<int64_t>(*s.number("face")) != f) {
    std::ostringstream o;
    o << "face=" << *s.number("face") << " does not match the image (faces of " << f << " px)";
    fail(s, o.str());
  }
  const CubeFormat format = cube_format(s, f);
  if (format.pad > 0.4)
    fail(s, "pad_px=" + std::to_string(static_cast<int64_t>(*s.number("pad_px"))) + " is over 0.4 of a " +
                std::to_string(f) + "-px cell (expected at most " + std::to_string(static_cast<int64_t>(0.4 * f)) + ")");
  if (format.ffmpeg_border) {
    if (f < 5) fail(s, "border=ffmpeg needs cells of at least 5 px (its 2-px border); got " + std::to_string(f));
    return Cubemap(size, format);
  }
  return Cubemap(f, layout, format);
}

// Faces of `density` pixels per radian at their centres, or as given.
Size size_for(const ProjectionSpec& s, double density) {
  const auto g = Cubemap::grid(cube_layout(s.choice("layout")));
  const double law = s.choice("layout") == "eac" ? kPi / 4 : 1.0;  // da/ds at the centre
  const double pad = s.given("pad") ? *s.number("pad") : 0.0;
  const int64_t f = s.given("face") ? static_cast<int64_t>(*s.number("face"))
                                    : std::max<int64_t>(s.choice("border") == "ffmpeg" ? 5 : 1,
                                                        std::llround(2 * density * law / (1 - pad)));
  return {f * g[0], f * g[1]};
}

Projection rescale(const Projection& p, Size size, double sx, double sy) {
  const auto& q = std::get<Cubemap>(p);
  // (Unequal factors: cells of whole pixels, not square; a 4:2:2 frame's chroma plane.)
  if (!q.uniform() || sx != sy) return q.scaled(sx, sy);
  const auto g = Cubemap::grid(q.layout());
  if (size.width % g[0] != 0 || size.width / g[0] * g[1] != size.height || size.width < g[0])
    throw Error("a cubemap of " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                " px does not hold whole square faces in its layout");
  return Cubemap(size.width / g[0], q.layout(), q.format());
}

// Faces of 1 to 40000 px, every layout; orders, turns, padding, presets, EAC and FFmpeg's EAC frame.
std::vector<ProjectionCase> cases() {
  std::vector<ProjectionCase> rows = {{"cubemap", {{6, 1}, {12, 2}, {6 * 256, 256}, {6 * 512, 512}, {6 * 1024, 1024}, {6 * 40000, 40000}}},
          {"cubemap:layout=1x6", {{512, 6 * 512}}},
          {"cubemap:layout=3x2", {{3 * 512, 2 * 512}}},
          {"cubemap:layout=cross", {{4 * 512, 3 * 512}, {4 * 1024, 3 * 1024}}},
          {"cubemap:layout=3x2,order=rludfb,rot=123012", {{3, 2}, {3 * 512, 2 * 512}}},
          {"cubemap:layout=6x1,order=udfblr,rot=302103,pad=0.1", {{6 * 256, 256}, {6 * 40000, 40000}}},
          {"cubemap:layout=cross,pad_px=3", {{4 * 512, 3 * 512}}},
          {"cubemap:preset=threejs", {{6 * 256, 256}}},
          {"cubemap:layout=3x2,preset=unity", {{3 * 256, 2 * 256}}},
          {"cubemap:layout=eac", {{3, 2}, {3 * 512, 2 * 512}, {3 * 40000, 2 * 40000}}},
          {"cubemap:layout=eac,pad=0.05", {{3 * 512, 2 * 512}}},
          {"cubemap:layout=eac,border=ffmpeg", {{15, 10}, {3 * 512, 2 * 512}, {3072, 2048}, {3 * 40000, 2 * 40000}}}};
  for (auto& row : rows) row.bound_px = 1e-9;  // measured: at most 3e-11 px
  return rows;
}

SamplingFacts sampling(const Projection& p) {
  SamplingFacts f = framed_facts(p);
  f.cube = &std::get<Cubemap>(p);
  return f;
}

}  // namespace

const ProjectionModule kCubemapModule{catalog, check, make,   size_for,
                                      rescale, cases, always, sampling};

}  // namespace panoproj
