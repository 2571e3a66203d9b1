// COLMAP's binary model files (model.hpp): little-endian, each file a uint64 count then its
// records (COLMAP's reconstruction_io_binary layout).
#include <bit>
#include <cstring>

#include "io/colmap/model.hpp"
#include "panoproj/error.hpp"

static_assert(std::endian::native == std::endian::little, "COLMAP's files are little-endian");

namespace panoproj::colmap {
namespace {

class Reader {
 public:
  Reader(std::string_view s, const std::string& path) : s_(s), path_(path) {}
  template <typename T>
  T take(const char* what) {
    T v;
    if (s_.size() - at_ < sizeof v)
      throw Error(path_ + ": cut short in " + what + " at byte " + std::to_string(at_));
    std::memcpy(&v, s_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  Pose pose(const char* what) {
    Pose p;
    for (double& v : p) v = take<double>(what);
    return p;
  }
  // A count of records of at least `least` bytes each, refused if the rest cannot hold them.
  uint64_t count(const char* what, size_t least) {
    const uint64_t n = take<uint64_t>(what);
    if (n > (s_.size() - at_) / least)
      throw Error(path_ + ": says it holds " + std::to_string(n) + " " + what + " at byte " +
                  std::to_string(at_ - 8) + ", more than its last " +
                  std::to_string(s_.size() - at_) + " bytes can (cut short, or not COLMAP's)");
    return n;
  }
  // A string ending with a NUL.
  std::string name() {
    const size_t end = s_.find('\0', at_);
    if (end == std::string_view::npos)
      throw Error(path_ + ": cut short in an image name at byte " + std::to_string(at_));
    std::string n(s_.substr(at_, end - at_));
    at_ = end + 1;
    return n;
  }
  void end(const char* what) const {
    if (at_ != s_.size())
      throw Error(path_ + ": " + std::to_string(s_.size() - at_) + " bytes after its " + what);
  }

 private:
  std::string_view s_;
  const std::string& path_;
  size_t at_ = 0;
};

class Writer {
 public:
  template <typename T>
  void put(T v) {
    s_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put(const Pose& p) {
    for (double v : p) put(v);
  }
  std::string& str() { return s_; }

 private:
  std::string s_;
};

SensorType sensor_type(int32_t v) {
  return static_cast<SensorType>(v);
}

}  // namespace

std::vector<Camera> cameras_binary(std::string_view s, const std::string& path) {
  Reader r(s, path);
  std::vector<Camera> out(r.count("cameras", 4 + 4 + 8 + 8 + 8 * 2));
  for (Camera& c : out) {
    c.id = r.take<uint32_t>("a camera id");
    const int32_t model = r.take<int32_t>("a model id");
    c.width = r.take<uint64_t>("a width");
    c.height = r.take<uint64_t>("a height");
    if (model < 0 || static_cast<size_t>(model) >= camera_models().size())
      throw Error(path + ": camera " + std::to_string(c.id) + " has the model id " +
                  std::to_string(model) + " (expected 0 to " +
                  std::to_string(camera_models().size() - 1) + ")");
    c.model = camera_models()[static_cast<size_t>(model)].name;
    c.params.resize(camera_models()[static_cast<size_t>(model)].params);
    for (double& p : c.params) p = r.take<double>("the parameters");
  }
  r.end("cameras");
  return out;
}

std::vector<Image> images_binary(std::string_view s, const std::string& path) {
  Reader r(s, path);
  std::vector<Image> out(r.count("images", 4 + 7 * 8 + 4 + 1 + 8));
  for (Image& im : out) {
    im.id = r.take<uint32_t>("an image id");
    im.cam_from_world = r.pose("an image's pose");
    im.camera = r.take<uint32_t>("an image's camera id");
    im.name = r.name();
    im.points.resize(r.count("points2D", 8 + 8 + 8));
    for (Point2D& p : im.points) {
      p.x = r.take<double>("a point2D");
      p.y = r.take<double>("a point2D");
      p.point3d = r.take<uint64_t>("a point2D's point3D id");
    }
  }
  r.end("images");
  return out;
}

std::vector<Point3D> points_binary(std::string_view s, const std::string& path) {
  Reader r(s, path);
  std::vector<Point3D> out(r.count("points3D", 8 + 3 * 8 + 3 + 8 + 8));
  for (Point3D& p : out) {
    p.id = r.take<uint64_t>("a point3D id");
    for (double& v : p.xyz) v = r.take<double>("a point3D's position");
    for (uint8_t& v : p.rgb) v = r.take<uint8_t>("a point3D's colour");
    p.error = r.take<double>("a point3D's error");
    p.track.resize(r.count("track elements", 4 + 4));
    for (TrackElement& e : p.track) {
      e.image = r.take<uint32_t>("a track element");
      e.point2d = r.take<uint32_t>("a track element");
    }
  }
  r.end("points3D");
  return out;
}

std::vector<Rig> rigs_binary(std::string_view s, const std::string& path) {
  Reader r(s, path);
  std::vector<Rig> out(r.count("rigs", 4 + 4));
  for (Rig& rig : out) {
    rig.id = r.take<uint32_t>("a rig id");
    const uint32_t n = r.take<uint32_t>("a rig's sensor count");
    for (uint32_t k = 0; k < n; ++k) {
      Sensor sensor;
      sensor.type = sensor_type(r.take<int32_t>("a sensor type"));
      sensor.id = r.take<uint32_t>("a sensor id");
      if (k > 0 && r.take<uint8_t>("a sensor's has_pose"))
        sensor.from_rig = r.pose("a sensor's pose");
      rig.sensors.push_back(sensor);  // (each read before it is kept: bounded by the file)
    }
  }
  r.end("rigs");
  return out;
}

std::vector<Frame> frames_binary(std::string_view s, const std::string& path) {
  Reader r(s, path);
  std::vector<Frame> out(r.count("frames", 4 + 4 + 7 * 8 + 4));
  for (Frame& f : out) {
    f.id = r.take<uint32_t>("a frame id");
    f.rig = r.take<uint32_t>("a frame's rig id");
    f.rig_from_world = r.pose("a frame's pose");
    const uint32_t n = r.take<uint32_t>("a frame's data count");
    for (uint32_t k = 0; k < n; ++k) {
      Data d;
      d.type = sensor_type(r.take<int32_t>("a data id's sensor type"));
      d.sensor = r.take<uint32_t>("a data id's sensor id");
      d.id = r.take<uint64_t>("a data id");
      f.data.push_back(d);
    }
  }
  r.end("frames");
  return out;
}

std::string write_binary(const std::vector<Camera>& v) {
  Writer w;
  w.put(uint64_t{v.size()});
  for (const Camera& c : v) {
    w.put(c.id);
    w.put(static_cast<int32_t>(camera_model(c.model) - camera_models().data()));
    w.put(c.width);
    w.put(c.height);
    for (double p : c.params) w.put(p);
  }
  return std::move(w.str());
}

std::string write_binary(const std::vector<Image>& v) {
  Writer w;
  w.put(uint64_t{v.size()});
  for (const Image& im : v) {
    w.put(im.id);
    w.put(im.cam_from_world);
    w.put(im.camera);
    w.str().append(im.name).push_back('\0');
    w.put(uint64_t{im.points.size()});
    for (const Point2D& p : im.points) {
      w.put(p.x);
      w.put(p.y);
      w.put(p.point3d);
    }
  }
  return std::move(w.str());
}

std::string write_binary(const std::vector<Point3D>& v) {
  Writer w;
  w.put(uint64_t{v.size()});
  for (const Point3D& p : v) {
    w.put(p.id);
    for (double x : p.xyz) w.put(x);
    for (uint8_t c : p.rgb) w.put(c);
    w.put(p.error);
    w.put(uint64_t{p.track.size()});
    for (const TrackElement& e : p.track) {
      w.put(e.image);
      w.put(e.point2d);
    }
  }
  return std::move(w.str());
}

std::string write_binary(const std::vector<Rig>& v) {
  Writer w;
  w.put(uint64_t{v.size()});
  for (const Rig& rig : v) {
    w.put(rig.id);
    w.put(static_cast<uint32_t>(rig.sensors.size()));
    for (size_t k = 0; k < rig.sensors.size(); ++k) {
      const Sensor& s = rig.sensors[k];
      w.put(static_cast<int32_t>(s.type));
      w.put(s.id);
      if (k == 0) continue;
      w.put(static_cast<uint8_t>(s.from_rig ? 1 : 0));
      if (s.from_rig) w.put(*s.from_rig);
    }
  }
  return std::move(w.str());
}

std::string write_binary(const std::vector<Frame>& v) {
  Writer w;
  w.put(uint64_t{v.size()});
  for (const Frame& f : v) {
    w.put(f.id);
    w.put(f.rig);
    w.put(f.rig_from_world);
    w.put(static_cast<uint32_t>(f.data.size()));
    for (const Data& d : f.data) {
      w.put(static_cast<int32_t>(d.type));
      w.put(d.sensor);
      w.put(d.id);
    }
  }
  return std::move(w.str());
}

}  // namespace panoproj::colmap
