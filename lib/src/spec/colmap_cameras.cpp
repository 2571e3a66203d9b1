// COLMAP's cameras as specs (colmap_cameras.hpp).
#include "spec/colmap_cameras.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

struct Camera {
  std::string id, model;
  uint64_t width = 0, height = 0;
  std::vector<double> params;
};

// COLMAP's models: name (its id is the index), parameter count.
struct Model {
  const char* name;
  size_t params;
};
constexpr Model kModels[] = {{"SIMPLE_PINHOLE", 3},
                             {"PINHOLE", 4},
                             {"SIMPLE_RADIAL", 4},
                             {"RADIAL", 5},
                             {"OPENCV", 8},
                             {"OPENCV_FISHEYE", 8},
                             {"FULL_OPENCV", 12},
                             {"FOV", 5},
                             {"SIMPLE_RADIAL_FISHEYE", 4},
                             {"RADIAL_FISHEYE", 5},
                             {"THIN_PRISM_FISHEYE", 12},
                             {"RAD_TAN_THIN_PRISM_FISHEYE", 16},
                             {"SIMPLE_DIVISION", 4},
                             {"DIVISION", 5},
                             {"SIMPLE_FISHEYE", 3},
                             {"FISHEYE", 4},
                             {"EUCM", 6},
                             {"EQUIRECTANGULAR", 2}};

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// "name:fx=..,fy=..,cx=..,cy=..": one focal length or two first, then the principal point.
std::string intrinsics(const char* name, const std::vector<double>& p, bool one_focal) {
  const size_t c = one_focal ? 1 : 2;
  return std::string(name) + ":fx=" + num(p[0]) + ",fy=" + num(one_focal ? p[0] : p[1]) +
         ",cx=" + num(p[c] - 0.5) + ",cy=" + num(p[c + 1] - 0.5);
}

std::string keys(const std::vector<double>& p, size_t from,
                 std::initializer_list<const char*> names) {
  std::string s;
  size_t i = from;
  for (const char* n : names) s += std::string(",") + n + "=" + num(p[i++]);
  return s;
}

std::string lens_spec(const Camera& c) {
  const auto& p = c.params;
  const std::string& m = c.model;
  if (m == "SIMPLE_PINHOLE") return intrinsics("brown-conrady", p, true);
  if (m == "PINHOLE") return intrinsics("brown-conrady", p, false);
  if (m == "SIMPLE_RADIAL") return intrinsics("brown-conrady", p, true) + keys(p, 3, {"k1"});
  if (m == "RADIAL") return intrinsics("brown-conrady", p, true) + keys(p, 3, {"k1", "k2"});
  if (m == "OPENCV")
    return intrinsics("brown-conrady", p, false) + keys(p, 4, {"k1", "k2", "p1", "p2"});
  if (m == "FULL_OPENCV")
    return intrinsics("brown-conrady", p, false) +
           keys(p, 4, {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"});
  if (m == "OPENCV_FISHEYE")
    return intrinsics("kannala-brandt", p, false) + keys(p, 4, {"k1", "k2", "k3", "k4"});
  if (m == "SIMPLE_RADIAL_FISHEYE")
    return intrinsics("kannala-brandt", p, true) + keys(p, 3, {"k1"});
  if (m == "RADIAL_FISHEYE")
    return intrinsics("kannala-brandt", p, true) + keys(p, 3, {"k1", "k2"});
  if (m == "SIMPLE_FISHEYE") return intrinsics("kannala-brandt", p, true);
  if (m == "FISHEYE") return intrinsics("kannala-brandt", p, false);
  if (m == "THIN_PRISM_FISHEYE")
    return intrinsics("thin-prism-fisheye", p, false) +
           keys(p, 4, {"k1", "k2", "p1", "p2", "k3", "k4", "sx1", "sy1"});
  if (m == "RAD_TAN_THIN_PRISM_FISHEYE")
    return intrinsics("rad-tan-thin-prism-fisheye", p, false) +
           keys(p, 4, {"k0", "k1", "k2", "k3", "k4", "k5", "p0", "p1", "s0", "s1", "s2", "s3"});
  // FOV at omega = 0 is COLMAP's pinhole limit.
  if (m == "FOV")
    return p[4] == 0 ? intrinsics("brown-conrady", p, false)
                     : intrinsics("devernay-faugeras", p, false) + keys(p, 4, {"omega"});
  if (m == "SIMPLE_DIVISION") return intrinsics("division", p, true) + keys(p, 3, {"k"});
  if (m == "DIVISION") return intrinsics("division", p, false) + keys(p, 4, {"k"});
  if (m == "EUCM") return intrinsics("extended-unified", p, false) + keys(p, 4, {"alpha", "beta"});
  return "";
}

// The lens's spec with the camera's size (a frame of another size is refused), or equirect for
// EQUIRECTANGULAR (the whole sphere on its frame, COLMAP's axes: tested).
std::string spec_of(const Camera& c) {
  if (c.model == "EQUIRECTANGULAR") return "equirect";
  return lens_spec(c) + ",width=" + std::to_string(c.width) + ",height=" + std::to_string(c.height);
}

const Model* model_named(const std::string& name) {
  for (const Model& m : kModels)
    if (name == m.name) return &m;
  return nullptr;
}

std::string model_names() {
  std::string s;
  for (const Model& m : kModels) s += std::string(s.empty() ? "" : ", ") + m.name;
  return s;
}

void check(const Camera& c, const std::string& path) {
  const Model* m = model_named(c.model);
  const std::string where = path + ": camera " + c.id + " ";
  if (!m)
    throw Error(where + "has the model " + c.model +
                " (expected one of COLMAP's: " + model_names() + ")");
  if (c.params.size() != m->params)
    throw Error(where + "(" + c.model + ") has " + std::to_string(c.params.size()) +
                " parameters (expected " + std::to_string(m->params) + ")");
  for (double v : c.params)
    if (!std::isfinite(v))
      throw Error(where + "has a parameter " + num(v) + " (expected finite numbers)");
  constexpr uint64_t kMaxSide = uint64_t{1} << 20;
  if (c.width < 1 || c.height < 1 || c.width > kMaxSide || c.height > kMaxSide)
    throw Error(where + "is " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                " pixels (expected 1 to " + std::to_string(kMaxSide) + " each way)");
}

std::vector<Camera> read_text(const std::string& text, const std::string& path) {
  std::vector<Camera> cams;
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string t; words >> t;) w.push_back(t);
    if (w.empty()) continue;
    if (w.size() < 4)
      throw Error(path + ": line " + std::to_string(n) + " has " + std::to_string(w.size()) +
                  " fields (expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[])");
    Camera c;
    c.id = w[0], c.model = w[1];
    auto whole = [&](const std::string& t) {
      char* end = nullptr;
      const unsigned long long v = std::strtoull(t.c_str(), &end, 10);
      if (t.empty() || *end || t[0] == '-')
        throw Error(path + ": line " + std::to_string(n) + " has the size '" + t +
                    "' (expected a whole number)");
      return static_cast<uint64_t>(v);
    };
    c.width = whole(w[2]), c.height = whole(w[3]);
    for (size_t i = 4; i < w.size(); ++i) {
      char* end = nullptr;
      const double v = std::strtod(w[i].c_str(), &end);
      if (*end)
        throw Error(path + ": line " + std::to_string(n) + " has the parameter '" + w[i] +
                    "' (expected a number)");
      c.params.push_back(v);
    }
    cams.push_back(std::move(c));
  }
  return cams;
}

// cameras.bin: uint64 count, then per camera uint32 id, int32 model id, uint64 width, uint64
// height, its model's doubles (little-endian, COLMAP's WriteCamerasBinary).
std::vector<Camera> read_binary(const std::string& data, const std::string& path) {
  size_t at = 0;
  auto take = [&](void* out, size_t n, const char* what) {
    if (data.size() - at < n)
      throw Error(path + ": cut short in " + what + " at byte " + std::to_string(at));
    std::memcpy(out, data.data() + at, n);
    at += n;
  };
  uint64_t count = 0;
  take(&count, 8, "the camera count");
  constexpr size_t kLeast = 4 + 4 + 8 + 8 + 8 * 2;  // the smallest camera (EQUIRECTANGULAR)
  if (count > (data.size() - at) / kLeast)
    throw Error(path + ": says it holds " + std::to_string(count) + " cameras, more than its " +
                std::to_string(data.size()) + " bytes can (expected COLMAP's cameras.bin)");
  std::vector<Camera> cams;
  for (uint64_t i = 0; i < count; ++i) {
    uint32_t id;
    int32_t model;
    Camera c;
    take(&id, 4, "a camera id");
    take(&model, 4, "a model id");
    take(&c.width, 8, "a width");
    take(&c.height, 8, "a height");
    c.id = std::to_string(id);
    if (model < 0 || static_cast<size_t>(model) >= std::size(kModels))
      throw Error(path + ": camera " + c.id + " has the model id " + std::to_string(model) +
                  " (expected 0 to " + std::to_string(std::size(kModels) - 1) + ")");
    c.model = kModels[model].name;
    c.params.resize(kModels[model].params);
    take(c.params.data(), 8 * c.params.size(), "the parameters");
    cams.push_back(std::move(c));
  }
  if (at != data.size())
    throw Error(path + ": " + std::to_string(data.size() - at) + " bytes after its cameras");
  return cams;
}

}  // namespace

bool is_colmap_cameras(const std::string& text, const std::string& path) {
  const std::string name = base_name(path);
  return name == "cameras.txt" || name == "cameras.bin" ||
         text.find("# Camera list with one line of data per camera:") != std::string::npos;
}

std::string colmap_camera_spec(const std::string& text, const std::string& path,
                               const std::string& id) {
  const bool binary = base_name(path) == "cameras.bin";
  const std::vector<Camera> cams = binary ? read_binary(text, path) : read_text(text, path);
  std::string ids;
  for (size_t i = 0; i < cams.size(); ++i) {
    for (size_t j = 0; j < i; ++j)
      if (cams[j].id == cams[i].id)
        throw Error(path + ": camera " + cams[i].id + " is listed twice");
    if (i < 8) ids += (ids.empty() ? "" : ", ") + cams[i].id;
  }
  if (cams.size() > 8) ids += ", ...";
  if (cams.empty()) throw Error(path + ": no cameras (expected COLMAP's cameras file)");
  const Camera* cam = nullptr;
  for (const Camera& c : cams)
    if (c.id == id || (id.empty() && cams.size() == 1)) cam = &c;
  if (!cam)
    throw Error(path + (id.empty() ? ": holds cameras " + ids + " (name one: @" + path + "#" +
                                         cams[0].id + ")"
                                   : ": no camera " + id + " (it holds " + ids + ")"));
  check(*cam, path);
  return spec_of(*cam);
}

}  // namespace panoproj
