// COLMAP's text model files (model.hpp): one record per line (images: two lines, the second its
// points2D, possibly empty), fields separated by spaces, lines starting with '#' comments
// (COLMAP's reconstruction_io_text layout).
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "base/text.hpp"
#include "io/colmap/model.hpp"
#include "panoproj/error.hpp"

namespace panoproj::colmap {
namespace {

bool whole_number(const std::string& w, uint64_t most, uint64_t& v) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long n = std::strtoull(w.c_str(), &end, 10);
  if (w.empty() || *end || w[0] == '-' || w[0] == '+' || errno == ERANGE || n > most) return false;
  v = n;
  return true;
}

// The fields of one line, read in order.
class Fields {
 public:
  Fields(std::string_view line, int number, const std::string& path)
      : number_(number), path_(path) {
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      const size_t b = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
      if (i > b) words_.emplace_back(line.substr(b, i - b));
    }
  }
  bool done() const { return at_ == words_.size(); }
  size_t left() const { return words_.size() - at_; }
  std::string word(const char* what) {
    if (done()) fail(std::string("ends before ") + what);
    return words_[at_++];
  }
  double number(const char* what) {
    const std::string w = word(what);
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (*end) fail("has " + shown(w) + " for " + what + " (expected a number)");
    return v;
  }
  uint64_t whole(const char* what, uint64_t most) {
    const std::string w = word(what);
    uint64_t v;
    if (!whole_number(w, most, v))
      fail("has " + shown(w) + " for " + what + " (expected a whole number, 0 to " +
           std::to_string(most) + ")");
    return v;
  }
  // A point2D's point3D id: a whole number, or -1 for none.
  uint64_t point_id() {
    const std::string w = word("a point2D's point3D id");
    uint64_t v = kNoPoint3D;
    if (w != "-1" && !whole_number(w, kNoPoint3D - 1, v))
      fail("has the point3D id " + shown(w) + " (expected a whole number, or -1 for none)");
    return v;
  }
  uint32_t id(const char* what) {
    return static_cast<uint32_t>(whole(what, std::numeric_limits<uint32_t>::max()));
  }
  Pose pose(const char* what) {
    Pose p;
    for (double& v : p) v = number(what);
    return p;
  }
  SensorType sensor(const char* what) {
    const std::string w = word(what);
    if (w == "CAMERA") return SensorType::Camera;
    if (w == "IMU") return SensorType::Imu;
    if (w == "INVALID") return SensorType::Invalid;
    fail("has the sensor type " + shown(w) + " (expected CAMERA or IMU)");
  }
  void end() {
    if (!done()) fail("has " + std::to_string(left()) + " fields more than expected");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(path_ + ": line " + std::to_string(number_) + " " + what);
  }

 private:
  static std::string shown(const std::string& w) {
    return "'" + (w.size() > 40 ? w.substr(0, 40) + "..." : w) + "'";
  }
  std::vector<std::string> words_;
  size_t at_ = 0;
  int number_;
  const std::string& path_;
};

// Lines in order with their numbers; data() skips comments and blank lines.
class Lines {
 public:
  Lines(std::string_view s, const std::string& path) : s_(s), path_(path) {}
  // The next line that is not a comment or blank; false at the end.
  bool data(std::string_view& line) {
    while (next(line)) {
      const size_t b = line.find_first_not_of(" \t\r");
      if (b != std::string_view::npos && line[b] != '#') return true;
    }
    return false;
  }
  // The next line whatever it holds; false at the end.
  bool next(std::string_view& line) {
    if (at_ >= s_.size()) return false;
    size_t e = s_.find('\n', at_);
    if (e == std::string_view::npos) e = s_.size();
    line = s_.substr(at_, e - at_);
    at_ = e + 1;
    ++number_;
    return true;
  }
  Fields fields(std::string_view line) const { return Fields(line, number_, path_); }

 private:
  std::string_view s_;
  const std::string& path_;
  size_t at_ = 0;
  int number_ = 0;
};

std::string text(const Pose& p) {
  std::string s;
  for (double v : p) s += (s.empty() ? "" : " ") + number_text(v);
  return s;
}

const char* sensor_name(SensorType t) {
  switch (t) {
    case SensorType::Camera:
      return "CAMERA";
    case SensorType::Imu:
      return "IMU";
    default:
      return "INVALID";
  }
}

}  // namespace

std::vector<Camera> cameras_text(std::string_view s, const std::string& path) {
  std::vector<Camera> out;
  Lines lines(s, path);
  for (std::string_view line; lines.data(line);) {
    Fields f = lines.fields(line);
    Camera c;
    if (f.left() < 4)
      f.fail("has " + std::to_string(f.left()) +
             " fields (expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[])");
    c.id = f.id("the camera id");
    c.model = f.word("the model");
    c.width = f.whole("the width", std::numeric_limits<uint64_t>::max());
    c.height = f.whole("the height", std::numeric_limits<uint64_t>::max());
    while (!f.done()) c.params.push_back(f.number("a parameter"));
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<Image> images_text(std::string_view s, const std::string& path) {
  std::vector<Image> out;
  Lines lines(s, path);
  for (std::string_view line; lines.data(line);) {
    Fields f = lines.fields(line);
    Image im;
    im.id = f.id("the image id");
    im.cam_from_world = f.pose("the pose (QW QX QY QZ TX TY TZ)");
    im.camera = f.id("the camera id");
    im.name = f.word("the name");
    f.end();
    // The next line is its points2D (X Y POINT3D_ID ..., -1: none), empty when it has none.
    if (lines.next(line)) {
      Fields p = lines.fields(line);
      if (p.left() % 3)
        p.fail("has " + std::to_string(p.left()) +
               " fields (expected X Y POINT3D_ID for each point2D of image " +
               std::to_string(im.id) + ")");
      while (!p.done()) {
        Point2D q;
        q.x = p.number("a point2D's x");
        q.y = p.number("a point2D's y");
        q.point3d = p.point_id();
        im.points.push_back(q);
      }
    }
    out.push_back(std::move(im));
  }
  return out;
}

std::vector<Point3D> points_text(std::string_view s, const std::string& path) {
  std::vector<Point3D> out;
  Lines lines(s, path);
  for (std::string_view line; lines.data(line);) {
    Fields f = lines.fields(line);
    Point3D p;
    p.id = f.whole("the point3D id", kNoPoint3D - 1);
    for (double& v : p.xyz) v = f.number("the position");
    for (uint8_t& c : p.rgb) c = static_cast<uint8_t>(f.whole("a colour", 255));
    p.error = f.number("the error");
    if (f.left() % 2)
      f.fail("has an odd number of track fields (expected IMAGE_ID POINT2D_IDX pairs)");
    while (!f.done()) {
      TrackElement e;
      e.image = f.id("a track's image id");
      e.point2d = f.id("a track's point2D index");
      p.track.push_back(e);
    }
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<Rig> rigs_text(std::string_view s, const std::string& path) {
  std::vector<Rig> out;
  Lines lines(s, path);
  for (std::string_view line; lines.data(line);) {
    Fields f = lines.fields(line);
    Rig rig;
    rig.id = f.id("the rig id");
    const uint64_t n = f.whole("the sensor count", f.left());
    for (uint64_t k = 0; k < n; ++k) {
      Sensor sensor;
      sensor.type = f.sensor("a sensor type");
      sensor.id = f.id("a sensor id");
      if (k > 0) {
        const uint64_t has = f.whole("a sensor's HAS_POSE", 1);
        if (has) sensor.from_rig = f.pose("a sensor's pose (QW QX QY QZ TX TY TZ)");
      }
      rig.sensors.push_back(sensor);
    }
    f.end();
    out.push_back(std::move(rig));
  }
  return out;
}

std::vector<Frame> frames_text(std::string_view s, const std::string& path) {
  std::vector<Frame> out;
  Lines lines(s, path);
  for (std::string_view line; lines.data(line);) {
    Fields f = lines.fields(line);
    Frame fr;
    fr.id = f.id("the frame id");
    fr.rig = f.id("the rig id");
    fr.rig_from_world = f.pose("the pose (QW QX QY QZ TX TY TZ)");
    const uint64_t n = f.whole("the data count", f.left() / 3);
    for (uint64_t k = 0; k < n; ++k) {
      Data d;
      d.type = f.sensor("a data id's sensor type");
      d.sensor = f.id("a data id's sensor id");
      d.id = f.whole("a data id", std::numeric_limits<uint64_t>::max());
      fr.data.push_back(d);
    }
    f.end();
    out.push_back(std::move(fr));
  }
  return out;
}

std::string write_text(const std::vector<Camera>& v) {
  std::string s =
      "# Camera list with one line of data per camera:\n"
      "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      "# Number of cameras: " +
      std::to_string(v.size()) + "\n";
  for (const Camera& c : v) {
    s += std::to_string(c.id) + " " + c.model + " " + std::to_string(c.width) + " " +
         std::to_string(c.height);
    for (double p : c.params) s += " " + number_text(p);
    s += "\n";
  }
  return s;
}

std::string write_text(const std::vector<Image>& v) {
  size_t seen = 0;
  for (const Image& im : v)
    for (const Point2D& p : im.points) seen += p.point3d != kNoPoint3D;
  std::string s =
      "# Image list with two lines of data per image:\n"
      "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      "# Number of images: " +
      std::to_string(v.size()) + ", mean observations per image: " +
      number_text(v.empty() ? 0.0 : static_cast<double>(seen) / static_cast<double>(v.size())) +
      "\n";
  for (const Image& im : v) {
    s += std::to_string(im.id) + " " + text(im.cam_from_world) + " " + std::to_string(im.camera) +
         " " + im.name + "\n";
    for (size_t k = 0; k < im.points.size(); ++k) {
      const Point2D& p = im.points[k];
      s += (k ? " " : "") + number_text(p.x) + " " + number_text(p.y) + " " +
           (p.point3d == kNoPoint3D ? std::string("-1") : std::to_string(p.point3d));
    }
    s += "\n";
  }
  return s;
}

std::string write_text(const std::vector<Point3D>& v) {
  size_t elements = 0;
  for (const Point3D& p : v) elements += p.track.size();
  std::string s =
      "# 3D point list with one line of data per point:\n"
      "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
      "# Number of points: " +
      std::to_string(v.size()) + ", mean track length: " +
      number_text(v.empty() ? 0.0 : static_cast<double>(elements) / static_cast<double>(v.size())) +
      "\n";
  for (const Point3D& p : v) {
    s += std::to_string(p.id);
    for (double x : p.xyz) s += " " + number_text(x);
    for (uint8_t c : p.rgb) s += " " + std::to_string(c);
    s += " " + number_text(p.error);
    for (const TrackElement& e : p.track)
      s += " " + std::to_string(e.image) + " " + std::to_string(e.point2d);
    s += "\n";
  }
  return s;
}

std::string write_text(const std::vector<Rig>& v) {
  std::string s =
      "# Rig calib list with one line of data per calib:\n"
      "#   RIG_ID, NUM_SENSORS, REF_SENSOR_TYPE, REF_SENSOR_ID, SENSORS[] as (SENSOR_TYPE, "
      "SENSOR_ID, HAS_POSE, [QW, QX, QY, QZ, TX, TY, TZ])\n"
      "# Number of rigs: " +
      std::to_string(v.size()) + "\n";
  for (const Rig& rig : v) {
    s += std::to_string(rig.id) + " " + std::to_string(rig.sensors.size());
    for (size_t k = 0; k < rig.sensors.size(); ++k) {
      const Sensor& sensor = rig.sensors[k];
      s += std::string(" ") + sensor_name(sensor.type) + " " + std::to_string(sensor.id);
      if (k > 0) s += sensor.from_rig ? " 1 " + text(*sensor.from_rig) : " 0";
    }
    s += "\n";
  }
  return s;
}

std::string write_text(const std::vector<Frame>& v) {
  std::string s =
      "# Frame list with one line of data per frame:\n"
      "#   FRAME_ID, RIG_ID, RIG_FROM_WORLD[QW, QX, QY, QZ, TX, TY, TZ], NUM_DATA_IDS, "
      "DATA_IDS[] as (SENSOR_TYPE, SENSOR_ID, DATA_ID)\n"
      "# Number of frames: " +
      std::to_string(v.size()) + "\n";
  for (const Frame& f : v) {
    s += std::to_string(f.id) + " " + std::to_string(f.rig) + " " + text(f.rig_from_world) + " " +
         std::to_string(f.data.size());
    for (const Data& d : f.data)
      s += std::string(" ") + sensor_name(d.type) + " " + std::to_string(d.sensor) + " " +
           std::to_string(d.id);
    s += "\n";
  }
  return s;
}

}  // namespace panoproj::colmap
