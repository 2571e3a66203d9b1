#include "io/exif.hpp"

#include <cstdint>
#include <cstring>
#include <iterator>

namespace panoproj {
namespace {

// TIFF 6.0: header "II*\0" or "MM\0*" + IFD0's offset; an IFD is a 2-byte count, 12-byte entries
// (tag, type, count, value or offset), a 4-byte offset of the next IFD.
class Tiff {
 public:
  explicit Tiff(std::string& b) : b_(b), little_(b.size() >= 8 && b[0] == 'I') {}
  bool valid() const {
    return b_.size() >= 8 && ((b_[0] == 'I' && b_[1] == 'I') || (b_[0] == 'M' && b_[1] == 'M')) && u16(2) == 42;
  }
  bool fits(uint64_t at, uint64_t n) const { return at <= b_.size() && n <= b_.size() - at; }
  std::string_view bytes() const { return b_; }
  uint32_t u16(uint64_t at) const {
    const auto* p = reinterpret_cast<const unsigned char*>(b_.data() + at);
    return little_ ? p[0] | p[1] << 8 : p[0] << 8 | p[1];
  }
  uint32_t u32(uint64_t at) const {
    return little_ ? u16(at) | u16(at + 2) << 16 : u16(at) << 16 | u16(at + 2);
  }
  void put16(uint64_t at, uint32_t v) {
    b_[at + (little_ ? 0 : 1)] = static_cast<char>(v & 0xFF);
    b_[at + (little_ ? 1 : 0)] = static_cast<char>(v >> 8);
  }
  void put32(uint64_t at, uint32_t v) {
    put16(at + (little_ ? 0 : 2), v & 0xFFFF);
    put16(at + (little_ ? 2 : 0), v >> 16);
  }
  // The entries of the IFD at `at` (false: it does not fit).
  bool entries(uint64_t at, uint32_t& count) const {
    if (!fits(at, 2)) return false;
    count = u16(at);
    return fits(at + 2, uint64_t{count} * 12 + 4);
  }

 private:
  std::string& b_;
  bool little_;
};

constexpr uint32_t kOrientation = 0x0112, kExifIfd = 0x8769, kGpsIfd = 0x8825, kPixelX = 0xA002, kPixelY = 0xA003;
constexpr uint32_t kByte = 1, kAscii = 2, kShort = 3, kLong = 4, kRational = 5, kUndefined = 7, kSlong = 9,
                   kSrational = 10;

// Sets a 1-value SHORT or LONG entry to v (a SHORT too small for v becomes a LONG).
void set_number(Tiff& t, uint64_t entry, uint32_t v) {
  if (t.u32(entry + 4) != 1 || (t.u16(entry + 2) != kShort && t.u16(entry + 2) != kLong)) return;
  if (t.u16(entry + 2) == kShort && v <= 0xFFFF) {
    t.put16(entry + 8, v);
    t.put16(entry + 10, 0);
  } else {
    t.put16(entry + 2, kLong);
    t.put32(entry + 8, v);
  }
}

// The tags read as attributes, by OpenImageIO's names (its exif.cpp tables), per IFD.
struct Tag {
  uint32_t id;
  const char* name;
};
constexpr Tag kIfd0Tags[] = {{0x010E, "ImageDescription"}, {0x010F, "Make"}, {0x0110, "Model"},
                             {0x0112, "Orientation"}, {0x011A, "XResolution"}, {0x011B, "YResolution"},
                             {0x0128, "ResolutionUnit"}, {0x0131, "Software"}, {0x0132, "DateTime"},
                             {0x013B, "Artist"}, {0x0213, "Exif:YCbCrPositioning"}, {0x8298, "Copyright"}};
constexpr Tag kExifTags[] = {
    {0x829A, "ExposureTime"}, {0x829D, "FNumber"}, {0x8822, "Exif:ExposureProgram"},
    {0x8827, "Exif:PhotographicSensitivity"}, {0x9000, "Exif:ExifVersion"}, {0x9003, "Exif:DateTimeOriginal"},
    {0x9004, "Exif:DateTimeDigitized"}, {0x9204, "Exif:ExposureBiasValue"}, {0x9207, "Exif:MeteringMode"},
    {0x920A, "Exif:FocalLength"}, {0xA000, "Exif:FlashPixVersion"}, {0xA001, "Exif:ColorSpace"},
    {0xA002, "Exif:PixelXDimension"}, {0xA003, "Exif:PixelYDimension"}, {0xA403, "Exif:WhiteBalance"},
    {0xA405, "Exif:FocalLengthIn35mmFilm"}, {0xA431, "Exif:BodySerialNumber"}, {0xA433, "Exif:LensMake"},
    {0xA434, "Exif:LensModel"}};
constexpr Tag kGpsTags[] = {{0x0001, "GPS:LatitudeRef"},  {0x0002, "GPS:Latitude"}, {0x0003, "GPS:LongitudeRef"},
                            {0x0004, "GPS:Longitude"},    {0x0005, "GPS:AltitudeRef"}, {0x0006, "GPS:Altitude"}};

// One entry's value as an attribute; false if its type, count or place does not fit.
bool entry_value(const Tiff& t, uint64_t e, const char* name, Metadata& out) {
  const uint32_t type = t.u16(e + 2), count = t.u32(e + 4);
  const uint32_t unit = type == kShort ? 2 : type == kLong || type == kSlong ? 4 : type == kRational || type == kSrational ? 8 : 1;
  if (count == 0 || count > (1u << 20)) return false;
  const uint64_t bytes = uint64_t{count} * unit, at = bytes <= 4 ? e + 8 : t.u32(e + 8);
  if (!t.fits(at, bytes)) return false;
  const auto rational = [&](uint32_t i) {
    const uint32_t n = t.u32(at + 8 * uint64_t{i}), d = t.u32(at + 8 * uint64_t{i} + 4);
    const double num = type == kSrational ? double(static_cast<int32_t>(n)) : double(n);
    const double den = type == kSrational ? double(static_cast<int32_t>(d)) : double(d);
    return den != 0 ? num / den : 0.0;
  };
  if (type == kAscii || type == kUndefined) {
    std::string v(t.bytes().substr(at, bytes));
    if (const size_t nul = v.find('\0'); nul != std::string::npos) v.resize(nul);
    out.push_back({name, std::move(v)});
  } else if (std::strcmp(name, "ResolutionUnit") == 0 && type == kShort && count == 1) {
    const uint32_t u = t.u16(at);
    out.push_back({name, std::string(u == 2 ? "in" : u == 3 ? "cm" : "none")});
  } else if ((type == kByte || type == kShort || type == kLong || type == kSlong) && count == 1) {
    const uint32_t v = type == kByte ? static_cast<uint8_t>(t.bytes()[at]) : type == kShort ? t.u16(at) : t.u32(at);
    out.push_back({name, type == kSlong ? int64_t{static_cast<int32_t>(v)} : int64_t{v}});
  } else if ((type == kRational || type == kSrational) && count == 1) {
    out.push_back({name, static_cast<double>(static_cast<float>(rational(0)))});  // OpenImageIO's float
  } else if (type == kRational && count == 3) {
    out.push_back({name, std::vector<double>{rational(0), rational(1), rational(2)}});
  } else {
    return false;
  }
  return true;
}

// The tags of `table` in the IFD at `ifd`; the offset of a sub-IFD tag's IFD, if asked.
void read_ifd(const Tiff& t, uint64_t ifd, const Tag* begin, const Tag* end, Metadata& out,
              uint64_t* exif_ifd = nullptr, uint64_t* gps_ifd = nullptr) {
  uint32_t n = 0;
  if (ifd < 8 || !t.entries(ifd, n)) return;
  for (uint32_t i = 0; i < n; ++i) {
    const uint64_t e = ifd + 2 + 12 * uint64_t{i};
    const uint32_t id = t.u16(e);
    if (exif_ifd && id == kExifIfd) *exif_ifd = t.u32(e + 8);
    if (gps_ifd && id == kGpsIfd) *gps_ifd = t.u32(e + 8);
    for (const Tag* tag = begin; tag != end; ++tag)
      if (tag->id == id) entry_value(t, e, tag->name, out);
  }
}

}  // namespace

Metadata exif_attributes(std::string_view exif) {
  std::string b(exif);
  const Tiff t(b);
  Metadata out;
  if (!t.valid()) return out;
  uint64_t exif_ifd = 0, gps_ifd = 0;
  read_ifd(t, t.u32(4), std::begin(kIfd0Tags), std::end(kIfd0Tags), out, &exif_ifd, &gps_ifd);
  read_ifd(t, exif_ifd, std::begin(kExifTags), std::end(kExifTags), out);
  read_ifd(t, gps_ifd, std::begin(kGpsTags), std::end(kGpsTags), out);
  return out;
}

std::string exif_for_output(std::string_view exif, Size size) {
  std::string b(exif);
  Tiff t(b);
  if (!t.valid()) return {};
  const uint64_t ifd0 = t.u32(4);
  uint32_t n = 0;
  if (!t.entries(ifd0, n)) return {};
  uint64_t exif_ifd = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const uint64_t e = ifd0 + 2 + 12 * uint64_t{i};
    if (t.u16(e) == kOrientation) set_number(t, e, 1);
    if (t.u16(e) == kExifIfd && t.u32(e + 4) == 1) exif_ifd = t.u32(e + 8);
  }
  t.put32(ifd0 + 2 + 12 * uint64_t{n}, 0);  // no IFD1: the old thumbnail
  uint32_t m = 0;
  if (exif_ifd != 0 && t.entries(exif_ifd, m)) {
    for (uint32_t i = 0; i < m; ++i) {
      const uint64_t e = exif_ifd + 2 + 12 * uint64_t{i};
      if (t.u16(e) == kPixelX) set_number(t, e, static_cast<uint32_t>(size.width));
      if (t.u16(e) == kPixelY) set_number(t, e, static_cast<uint32_t>(size.height));
    }
  }
  return b;
}

}  // namespace panoproj
