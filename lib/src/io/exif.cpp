#include "io/exif.hpp"

#include <cstdint>

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

constexpr uint32_t kOrientation = 0x0112, kExifIfd = 0x8769, kPixelX = 0xA002, kPixelY = 0xA003;
constexpr uint32_t kShort = 3, kLong = 4;

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

}  // namespace

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
