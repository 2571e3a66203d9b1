// Fuzzes COLMAP's model readers (io/colmap/model.hpp) and the undistort job's plan of what they
// accept. The input: one byte (bit 0: binary files; bit 1: with rigs and frames), then the files'
// contents separated by "@@@@": cameras, images, points3D, rigs, frames. Only panoproj::Error may
// leave them; a model accepted is written back (text and binary), read again and written again:
// the same bytes, or the run aborts.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "io/colmap/model.hpp"
#include "jobs/undistort/undistort.hpp"
#include "panoproj/error.hpp"

namespace {

using namespace panoproj;

colmap::ModelFiles files_of(std::string_view s, bool binary, bool rigs) {
  colmap::ModelFiles f;
  f.binary = binary;
  f.rigs_and_frames = rigs;
  std::string* parts[] = {&f.cameras, &f.images, &f.points, &f.rigs, &f.frames};
  for (std::string* p : parts) {
    const size_t cut = s.find("@@@@");
    *p = std::string(s.substr(0, cut));
    s = cut == std::string_view::npos ? std::string_view() : s.substr(cut + 4);
  }
  return f;
}

// The model's files in one format, as read again.
colmap::ModelFiles written(const colmap::Model& m, bool binary) {
  colmap::ModelFiles f;
  f.binary = binary;
  f.rigs_and_frames = m.rigs_and_frames;
  for (const colmap::File& file : colmap::model_files(m, binary, "")) {
    const std::string name = file.path.substr(0, file.path.find('.'));
    (name == "cameras"    ? f.cameras
     : name == "images"   ? f.images
     : name == "points3D" ? f.points
     : name == "rigs"     ? f.rigs
                          : f.frames) = file.bytes;
  }
  return f;
}

bool same(const colmap::ModelFiles& a, const colmap::ModelFiles& b) {
  return a.cameras == b.cameras && a.images == b.images && a.points == b.points &&
         a.rigs == b.rigs && a.frames == b.frames;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string_view s(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const colmap::Model m = colmap::parse_model(files_of(s, data[0] & 1, data[0] & 2), "fuzz");
    for (bool binary : {false, true}) {
      const colmap::ModelFiles once = written(m, binary);
      if (!same(written(colmap::parse_model(once, "again"), binary), once)) std::abort();
    }
    // The undistort job's plan (no image is read): small models only, to keep runs short.
    if (m.cameras.size() <= 4 && m.images.size() <= 16) {
      UndistortOptions o;
      o.rig = parse_rig("cube");
      const UndistortPlan plan = plan_undistort(m, o, "fuzz");
      colmap::check_model(plan.model, "plan", ".txt");
    }
  } catch (const Error&) {
  }
  return 0;
}
