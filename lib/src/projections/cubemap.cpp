// The cubemap module (module.hpp): six 90-degree faces in one image (a strip, a 3x2 grid or a
// cross) or six files, and the layouts' cells.
#include <sstream>

#include "projections/module.hpp"
#include "panoproj/error.hpp"
#include "projections/spec_support.hpp"

namespace panoproj {

std::array<int, 2> Cubemap::grid(CubeLayout layout) {
  switch (layout) {
    case CubeLayout::Files:
    case CubeLayout::Row6x1: return {6, 1};
    case CubeLayout::Column1x6: return {1, 6};
    case CubeLayout::Grid3x2: return {3, 2};
    case CubeLayout::Cross4x3: return {4, 3};
  }
  return {6, 1};
}

Cubemap::Cubemap(int64_t face_size, CubeLayout layout)
    : f_(face_size), fd_(static_cast<double>(face_size)), layout_(layout) {
  const auto g = grid(layout);
  cols_ = g[0];
  rows_ = g[1];
  size_ = {cols_ * f_, rows_ * f_};
  // Cell (column, row) of each face.
  std::array<std::array<int, 2>, 6> cells{};
  switch (layout) {
    case CubeLayout::Files:
    case CubeLayout::Row6x1:
      for (int i = 0; i < 6; ++i) cells[i] = {i, 0};
      break;
    case CubeLayout::Column1x6:
      for (int i = 0; i < 6; ++i) cells[i] = {0, i};
      break;
    case CubeLayout::Grid3x2:
      for (int i = 0; i < 6; ++i) cells[i] = {i % 3, i / 3};
      break;
    case CubeLayout::Cross4x3:
      cells = {{{1, 1}, {2, 1}, {3, 1}, {0, 1}, {1, 0}, {1, 2}}};
      break;
  }
  cell_face_.fill(-1);
  for (int i = 0; i < 6; ++i) {
    origin_[i] = {cells[i][0] * f_, cells[i][1] * f_};
    cell_face_[cells[i][1] * cols_ + cells[i][0]] = i;
  }
}

namespace {
using namespace spec_support;

std::vector<ProjectionDef> catalog() {
  return {{"cubemap", "six 90-degree faces: front right back left up down",
           {choice("layout", "6x1", "files|6x1|1x6|3x2|cross", "files: six images (path pattern with {face} and/or {index}); cross is 4x3"),
            {"face", ParamType::Integer, "", 1, 1 << 30, false, false, "", "face size in pixels; default: from the source's resolution"}}}};
}

CubeLayout cube_layout(const std::string& l) {
  if (l == "files") return CubeLayout::Files;
  if (l == "1x6") return CubeLayout::Column1x6;
  if (l == "3x2") return CubeLayout::Grid3x2;
  if (l == "cross") return CubeLayout::Cross4x3;
  return CubeLayout::Row6x1;
}

Projection make(const ProjectionSpec& s, Size size) {
  const auto layout = cube_layout(s.choice("layout"));
  const auto g = Cubemap::grid(layout);
  const int64_t f = size.width / g[0];
  if (f * g[0] != size.width || f * g[1] != size.height) {
    std::ostringstream o;
    o << "layout=" << s.choice("layout") << " needs a " << g[0] << "F x " << g[1] << "F image with square faces; got "
      << size.width << "x" << size.height << " (check the size or the layout)";
    fail(s, o.str());
  }
  if (s.given("face") && static_cast<int64_t>(*s.number("face")) != f) {
    std::ostringstream o;
    o << "face=" << *s.number("face") << " does not match the image (faces of " << f << " px)";
    fail(s, o.str());
  }
  return Cubemap(f, layout);
}

// Faces of 2 density pixels (90 degrees at `density` pixels per radian at their centres), or as
// given.
Size size_for(const ProjectionSpec& s, double density) {
  const auto g = Cubemap::grid(cube_layout(s.choice("layout")));
  const int64_t f = s.given("face") ? static_cast<int64_t>(*s.number("face")) : std::max<int64_t>(1, std::llround(2 * density));
  return {f * g[0], f * g[1]};
}

Projection rescale(const Projection& p, Size size, double, double) {
  const auto& q = std::get<Cubemap>(p);
  const auto g = Cubemap::grid(q.layout());
  if (size.width % g[0] != 0 || size.width / g[0] * g[1] != size.height || size.width < g[0])
    throw Error("a cubemap of " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                " px does not hold whole square faces in its layout");
  return Cubemap(size.width / g[0], q.layout());
}

// Faces of 1 to 40000 px, every layout.
std::vector<ProjectionCase> cases() {
  return {{"cubemap", {{6, 1}, {12, 2}, {6 * 256, 256}, {6 * 512, 512}, {6 * 1024, 1024}, {6 * 40000, 40000}}},
          {"cubemap:layout=1x6", {{512, 6 * 512}}},
          {"cubemap:layout=3x2", {{3 * 512, 2 * 512}}},
          {"cubemap:layout=cross", {{4 * 512, 3 * 512}, {4 * 1024, 3 * 1024}}}};
}

}  // namespace

const ProjectionModule kCubemapModule{catalog, nullptr, make, size_for, rescale, cases, always};

}  // namespace panoproj
