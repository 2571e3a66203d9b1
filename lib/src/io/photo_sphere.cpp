#include "panoproj/photo_sphere.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <utility>


#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/rotation.hpp"
#include "base/input_check.hpp"

namespace panoproj {
namespace {

constexpr char kXmpHeader[] = "http://ns.adobe.com/xap/1.0/";  // then a NUL, then the packet

// The XMP packet of JPEG bytes, "" for none, or nullopt where the segments (walked from the
// start marker to the scan) run past the bytes.
std::optional<std::string> jpeg_xmp(const std::string& b) {
  if (b.size() < 4 || static_cast<unsigned char>(b[0]) != 0xFF || static_cast<unsigned char>(b[1]) != 0xD8) return "";
  size_t i = 2;
  const size_t header = sizeof kXmpHeader;  // with its NUL
  while (static_cast<unsigned char>(b[i]) == 0xFF) {
    if (i + 4 > b.size()) return std::nullopt;
    const auto marker = static_cast<unsigned char>(b[i + 1]);
    if (marker == 0xDA || marker == 0xD9) break;  // start of scan, end of image
    const size_t len = (static_cast<unsigned char>(b[i + 2]) << 8) | static_cast<unsigned char>(b[i + 3]);
    if (len < 2) break;
    if (i + 2 + len > b.size()) return std::nullopt;
    if (marker == 0xE1 && len - 2 > header && b.compare(i + 4, header, std::string(kXmpHeader, header)) == 0)
      return b.substr(i + 4 + header, len - 2 - header);
    i += 2 + len;
    if (i >= b.size()) return std::nullopt;
  }
  return "";
}

constexpr char kPngSignature[] = "\x89PNG\r\n\x1a\n";       // 8 bytes
constexpr char kPngXmpKeyword[] = "XML:com.adobe.xmp";  // the iTXt chunk holding XMP (with its NUL)

uint32_t be32(const std::string& b, size_t at) {
  return (static_cast<uint32_t>(static_cast<unsigned char>(b[at])) << 24) |
         (static_cast<uint32_t>(static_cast<unsigned char>(b[at + 1])) << 16) |
         (static_cast<uint32_t>(static_cast<unsigned char>(b[at + 2])) << 8) | static_cast<unsigned char>(b[at + 3]);
}

// The XMP packet of PNG bytes, "" for none, or nullopt where the chunks before the image data
// run past the bytes: an uncompressed iTXt chunk "XML:com.adobe.xmp" (keyword NUL, compression
// flag and method, language NUL, translated keyword NUL, text; PNG specification 11.3.4.5).
std::optional<std::string> png_xmp(const std::string& b) {
  if (b.compare(0, 8, std::string(kPngSignature, 8)) != 0) return "";
  for (size_t i = 8;;) {
    if (i + 12 > b.size()) return std::nullopt;
    const size_t len = be32(b, i);
    const std::string type = b.substr(i + 4, 4);
    if (type == "IDAT" || type == "IEND") break;
    if (len > b.size() - i - 12) return std::nullopt;
    const size_t key = sizeof kPngXmpKeyword;  // with its NUL
    if (type == "iTXt" && len > key + 2 && b.compare(i + 8, key, std::string(kPngXmpKeyword, key)) == 0 &&
        b[i + 8 + key] == 0) {
      size_t at = i + 8 + key + 2;  // past the flag and method
      const size_t end = i + 8 + len;
      for (int nul = 0; nul < 2 && at < end; ++at) nul += b[at] == 0;  // language, translated keyword
      return at <= end ? b.substr(at, end - at) : std::string();
    }
    i += 12 + len;
  }
  return "";
}

// CRC-32 of PNG chunks (ISO 3309, the PNG specification's Annex D), over type and data.
uint32_t crc32(const std::string& bytes) {
  static const auto table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (const char ch : bytes) c = table[(c ^ static_cast<unsigned char>(ch)) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

std::string be32_bytes(uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>((v >> 16) & 0xFF), static_cast<char>((v >> 8) & 0xFF),
          static_cast<char>(v & 0xFF)};
}

// ns:name (GPano by default) as an attribute (GPano:name="v") or an element
// (<GPano:name>v</GPano:name>).
std::optional<std::string> field(const std::string& xmp, const std::string& name, const char* ns = "GPano:") {
  const std::string key = ns + name;
  for (size_t at = xmp.find(key); at != std::string::npos; at = xmp.find(key, at + 1)) {
    size_t i = at + key.size();
    if (i < xmp.size() && (xmp[i] == '=' || (i + 1 < xmp.size() && xmp[i] == ' ' && xmp[i + 1] == '='))) {
      while (i < xmp.size() && xmp[i] != '"' && xmp[i] != '\'') ++i;
      if (i >= xmp.size()) return std::nullopt;
      const char q = xmp[i];
      const size_t end = xmp.find(q, i + 1);
      if (end == std::string::npos) return std::nullopt;
      return xmp.substr(i + 1, end - i - 1);
    }
    if (at > 0 && xmp[at - 1] == '<' && i < xmp.size() && xmp[i] == '>') {
      const size_t end = xmp.find('<', i);
      if (end == std::string::npos) return std::nullopt;
      return xmp.substr(i + 1, end - i - 1);
    }
  }
  return std::nullopt;
}

// A field's number; a field present but not a finite number is refused (read as 0 it would place
// the panorama wrongly without a word).
double number(const std::string& xmp, const char* name, double fallback, const std::string& path) {
  const auto v = field(xmp, name);
  if (!v) return fallback;
  char* end = nullptr;
  const double d = std::strtod(v->c_str(), &end);
  if (end == v->c_str() || !std::isfinite(d) || std::fabs(d) > 1e12)
    throw Error("Photo Sphere metadata of " + path + ": GPano:" + name + " is \"" + one_line(v->substr(0, 40)) +
                "\" (expected a finite number; give " + option_text("from") + " SPEC to override it)");
  return d;
}

int64_t integer(const std::string& xmp, const char* name, int64_t fallback, const std::string& path) {
  return std::llround(number(xmp, name, static_cast<double>(fallback), path));
}

// The GPano fields (developers.google.com/streetview/spherical-metadata) and their types.
enum class GPanoType { Boolean, Integer, Real, Text };
constexpr std::pair<const char*, GPanoType> kGPanoFields[] = {
    {"UsePanoramaViewer", GPanoType::Boolean},         {"CaptureSoftware", GPanoType::Text},
    {"StitchingSoftware", GPanoType::Text},            {"ProjectionType", GPanoType::Text},
    {"PoseHeadingDegrees", GPanoType::Real},           {"PosePitchDegrees", GPanoType::Real},
    {"PoseRollDegrees", GPanoType::Real},              {"InitialViewHeadingDegrees", GPanoType::Integer},
    {"InitialViewPitchDegrees", GPanoType::Integer},   {"InitialViewRollDegrees", GPanoType::Integer},
    {"InitialHorizontalFOVDegrees", GPanoType::Real},  {"InitialCameraDolly", GPanoType::Real},
    {"FirstPhotoDate", GPanoType::Text},               {"LastPhotoDate", GPanoType::Text},
    {"SourcePhotosCount", GPanoType::Integer},         {"ExposureLockUsed", GPanoType::Boolean},
    {"CroppedAreaImageWidthPixels", GPanoType::Integer}, {"CroppedAreaImageHeightPixels", GPanoType::Integer},
    {"FullPanoWidthPixels", GPanoType::Integer},       {"FullPanoHeightPixels", GPanoType::Integer},
    {"CroppedAreaLeftPixels", GPanoType::Integer},     {"CroppedAreaTopPixels", GPanoType::Integer}};

}  // namespace

Metadata photo_sphere_attributes(const std::string& xmp) {
  Metadata out;
  for (const auto& [name, type] : kGPanoFields) {
    const auto v = field(xmp, name);
    if (!v) continue;
    const std::string key = std::string("GPano:") + name;
    const char* c = v->c_str();
    char* end = nullptr;
    if (type == GPanoType::Text) {
      out.push_back({key, *v});
    } else if (type == GPanoType::Boolean) {
      if (*v == "True" || *v == "False") out.push_back({key, int64_t{*v == "True"}});
    } else if (type == GPanoType::Integer) {
      const long long i = std::strtoll(c, &end, 10);
      if (end != c && *end == '\0') out.push_back({key, int64_t{i}});
    } else {
      const double d = std::strtod(c, &end);
      if (end != c && *end == '\0' && std::isfinite(d)) out.push_back({key, static_cast<double>(static_cast<float>(d))});
    }
  }
  return out;
}

std::optional<PhotoSphere> read_photo_sphere(const std::string& path) {
  // The segments or chunks before the image data, where the XMP packet comes: 64 kB, or up to
  // 4 MB where EXIF, ICC profiles and thumbnails before it take more.
  std::string head = read_head(path, size_t{64} << 10);
  const bool jpeg = head.compare(0, 2, "\xFF\xD8") == 0, png = head.compare(0, 8, std::string(kPngSignature, 8)) == 0;
  if (!jpeg && !png) return std::nullopt;
  std::optional<std::string> found = jpeg ? jpeg_xmp(head) : png_xmp(head);
  if (!found && head.size() == size_t{64} << 10) {
    head = read_head(path, size_t{4} << 20);
    found = jpeg ? jpeg_xmp(head) : png_xmp(head);
  }
  if (!found || found->empty()) return std::nullopt;
  const std::string& xmp = *found;
  const auto type = field(xmp, "ProjectionType");
  if (!type) return std::nullopt;
  PhotoSphere ps;
  ps.projection_type = *type;
  ps.full_width = integer(xmp, "FullPanoWidthPixels", 0, path);
  ps.full_height = integer(xmp, "FullPanoHeightPixels", ps.full_width / 2, path);
  ps.crop_width = integer(xmp, "CroppedAreaImageWidthPixels", ps.full_width, path);
  ps.crop_height = integer(xmp, "CroppedAreaImageHeightPixels", ps.full_height, path);
  ps.crop_left = integer(xmp, "CroppedAreaLeftPixels", 0, path);
  ps.crop_top = integer(xmp, "CroppedAreaTopPixels", 0, path);
  ps.pose_pitch = number(xmp, "PosePitchDegrees", 0.0, path);
  ps.pose_roll = number(xmp, "PoseRollDegrees", 0.0, path);
  if (const auto mode = field(xmp, "StereoMode", "GSpherical:"); mode && *mode != "mono") {
    if (*mode != "top-bottom" && *mode != "left-right")
      throw Error("Photo Sphere metadata of " + path + ": GSpherical:StereoMode is \"" + one_line(mode->substr(0, 40)) +
                  "\" (expected mono, top-bottom or left-right; give " + option_text("from") + " SPEC to override it)");
    ps.stereo_mode = *mode;
  }
  return ps;
}

Eigen::Matrix3d photo_sphere_pose(const PhotoSphere& ps) {
  if (std::fabs(ps.pose_pitch) > 90 || std::fabs(ps.pose_roll) > 180)
    throw Error("Photo Sphere metadata: GPano:PosePitchDegrees=" + std::to_string(ps.pose_pitch) + ", PoseRollDegrees=" +
                std::to_string(ps.pose_roll) + " out of range (expected |pitch| <= 90, |roll| <= 180; give --from SPEC "
                "to ignore the metadata)");
  return rotation_from_ypr(0, ps.pose_pitch, ps.pose_roll);
}

std::string photo_sphere_spec(const PhotoSphere& ps, Size size) {
  auto fail = [&](const std::string& what) {
    throw Error("Photo Sphere metadata: " + what + " (give --from SPEC to override it)");
  };
  if (ps.projection_type != "equirectangular")
    fail("GPano:ProjectionType=" + ps.projection_type + " is not supported (expected equirectangular)");
  if (ps.full_width <= 0 || ps.full_height <= 0 || ps.crop_width <= 0 || ps.crop_height <= 0)
    fail("FullPano or CroppedAreaImage sizes missing or not positive");
  if (ps.crop_left < 0 || ps.crop_top < 0 || ps.crop_top + ps.crop_height > ps.full_height ||
      ps.crop_width > ps.full_width)
    fail("the cropped area " + std::to_string(ps.crop_width) + "x" + std::to_string(ps.crop_height) + "+" +
         std::to_string(ps.crop_left) + "+" + std::to_string(ps.crop_top) + " does not fit the full panorama " +
         std::to_string(ps.full_width) + "x" + std::to_string(ps.full_height));
  // A stereo frame's fields describe one eye.
  const bool tb = ps.stereo_mode == "top-bottom", sbs = ps.stereo_mode == "left-right";
  if ((tb && size.height % 2) || (sbs && size.width % 2))
    fail("GSpherical:StereoMode=" + ps.stereo_mode + " but the image is " + size_text(size) + " (odd: no two equal eyes)");
  if (tb) size.height /= 2;
  if (sbs) size.width /= 2;
  // The stored image may be the crop scaled; both axes by the same factor.
  const double sx = static_cast<double>(size.width) / static_cast<double>(ps.crop_width);
  const double sy = static_cast<double>(size.height) / static_cast<double>(ps.crop_height);
  if (std::fabs(sx / sy - 1.0) > 0.01)
    fail(std::string(tb || sbs ? "an eye" : "the image") + " is " + size_text(size) + " but its cropped area is " +
         size_text({ps.crop_width, ps.crop_height}));
  const double fw = static_cast<double>(ps.full_width), fh = static_cast<double>(ps.full_height);
  const double hfov = 360.0 * static_cast<double>(ps.crop_width) / fw;
  const double vfov = 180.0 * static_cast<double>(ps.crop_height) / fh;
  double lon0 = ((static_cast<double>(ps.crop_left) + 0.5 * static_cast<double>(ps.crop_width)) / fw - 0.5) * 360.0;
  lon0 = std::remainder(lon0, 360.0);  // a crop past the seam's right wraps
  const double lat0 = (0.5 - (static_cast<double>(ps.crop_top) + 0.5 * static_cast<double>(ps.crop_height)) / fh) * 180.0;
  char text[200];
  std::snprintf(text, sizeof text, "equirect:hfov=%.17g,vfov=%.17g,lon0=%.17g,lat0=%.17g%s", hfov, vfov, lon0, lat0,
                tb ? ",stereo=tb" : sbs ? ",stereo=sbs" : "");
  return text;
}

PhotoSphere photo_sphere_of(const Equirect& e) {
  PhotoSphere ps;
  const Size s = e.size();
  const double hfov = e.axis().hfov, vfov = e.vfov();
  ps.crop_width = s.width;
  ps.crop_height = s.height;
  ps.full_width = std::llround(static_cast<double>(s.width) * kTwoPi / hfov);
  ps.full_height = std::llround(static_cast<double>(s.height) * kPi / vfov);
  // The crop's left edge and top from its centre's longitude and latitude.
  const double lon_left = e.axis().lon0 - 0.5 * hfov;
  ps.crop_left = std::llround((lon_left / kTwoPi + 0.5) * static_cast<double>(ps.full_width));
  ps.crop_left = ((ps.crop_left % ps.full_width) + ps.full_width) % ps.full_width;
  ps.crop_top = std::llround((0.5 - e.lat_top() / kPi) * static_cast<double>(ps.full_height));
  return ps;
}

std::string photo_sphere_xmp(const PhotoSphere& ps) {
  std::ostringstream o;
  o << "<?xpacket begin=\"\xEF\xBB\xBF\" id=\"W5M0MpCehiHzreSzNTczkc9d\"?>"
    << "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\"><rdf:RDF xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">"
    << "<rdf:Description rdf:about=\"\" xmlns:GPano=\"http://ns.google.com/photos/1.0/panorama/\""
    << " GPano:UsePanoramaViewer=\"True\" GPano:ProjectionType=\"" << ps.projection_type << "\""
    << " GPano:FullPanoWidthPixels=\"" << ps.full_width << "\" GPano:FullPanoHeightPixels=\"" << ps.full_height << "\""
    << " GPano:CroppedAreaImageWidthPixels=\"" << ps.crop_width << "\" GPano:CroppedAreaImageHeightPixels=\""
    << ps.crop_height << "\" GPano:CroppedAreaLeftPixels=\"" << ps.crop_left << "\" GPano:CroppedAreaTopPixels=\""
    << ps.crop_top << "\"";
  if (ps.pose_pitch != 0 || ps.pose_roll != 0)
    o << " GPano:PosePitchDegrees=\"" << ps.pose_pitch << "\" GPano:PoseRollDegrees=\"" << ps.pose_roll << "\"";
  if (!ps.stereo_mode.empty())
    o << " xmlns:GSpherical=\"http://ns.google.com/videos/1.0/spherical/\" GSpherical:StereoMode=\"" << ps.stereo_mode << "\"";
  o << "/></rdf:RDF></x:xmpmeta><?xpacket end=\"w\"?>";
  return o.str();
}

XmpInsertion xmp_insertion(std::string_view b, const std::string& xmp) {
  if (b.substr(0, 8) == std::string_view(kPngSignature, 8)) {
    // An iTXt chunk right after IHDR (the first chunk: 8 + 25 bytes).
    if (b.size() < 33 || b.substr(12, 4) != "IHDR") throw Error("cannot add XMP: a damaged PNG");
    std::string chunk = std::string("iTXt") + std::string(kPngXmpKeyword, sizeof kPngXmpKeyword) + std::string(4, '\0') + xmp;
    return {33, be32_bytes(static_cast<uint32_t>(chunk.size() - 4)) + chunk + be32_bytes(crc32(chunk))};
  }
  const size_t payload = sizeof kXmpHeader + xmp.size();
  if (b.size() < 2 || static_cast<unsigned char>(b[0]) != 0xFF || static_cast<unsigned char>(b[1]) != 0xD8 ||
      payload + 2 > 0xFFFF)
    throw Error("cannot add XMP: not a JPEG or PNG, or the packet is over 64 KB");
  std::string seg = "\xFF\xE1";
  seg += static_cast<char>((payload + 2) >> 8);
  seg += static_cast<char>((payload + 2) & 0xFF);
  seg.append(kXmpHeader, sizeof kXmpHeader);
  seg += xmp;
  // After the JFIF (APP0) and EXIF (APP1) segments, where readers expect XMP.
  size_t at = 2;
  while (at + 4 <= b.size() && static_cast<unsigned char>(b[at]) == 0xFF &&
         (static_cast<unsigned char>(b[at + 1]) == 0xE0 || static_cast<unsigned char>(b[at + 1]) == 0xE1)) {
    const size_t len = (static_cast<unsigned char>(b[at + 2]) << 8) | static_cast<unsigned char>(b[at + 3]);
    if (len < 2 || at + 2 + len > b.size()) break;
    at += 2 + len;
  }
  return {at, std::move(seg)};
}

std::string with_xmp(const std::string& file_bytes, const std::string& xmp) {
  const XmpInsertion x = xmp_insertion(file_bytes, xmp);
  return file_bytes.substr(0, x.offset) + x.bytes + file_bytes.substr(x.offset);
}

}  // namespace panoproj
