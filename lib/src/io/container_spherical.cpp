#include "io/container_spherical.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <vector>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

constexpr uint64_t kMostMoov = uint64_t{256} << 20;
constexpr double kUnit = 4294967295.0;  // (0.32 fixed point, UINT32_MAX as 1, as FFmpeg's)
constexpr size_t kVisualEntry = 78;     // a VisualSampleEntry's fields before its child boxes

uint32_t be32(std::string_view d, size_t at) {
  const auto* p = reinterpret_cast<const unsigned char*>(d.data() + at);
  return static_cast<uint32_t>(p[0]) << 24 | static_cast<uint32_t>(p[1]) << 16 |
         static_cast<uint32_t>(p[2]) << 8 | p[3];
}

uint64_t be64(std::string_view d, size_t at) {
  return static_cast<uint64_t>(be32(d, at)) << 32 | be32(d, at + 4);
}

void put32(std::string& d, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) d[at + static_cast<size_t>(i)] = static_cast<char>(v >> (24 - 8 * i));
}

struct Box {
  std::string_view type;
  size_t start = 0, body = 0, end = 0;  // offsets in the buffer: the box, its payload, its end
  bool wide = false;                    // a 64-bit size
};

// The boxes in [begin, end) of `d`; throws Error where a size runs past `end`.
std::vector<Box> children(std::string_view d, size_t begin, size_t end, const std::string& what) {
  std::vector<Box> out;
  size_t at = begin;
  while (end - at >= 8) {
    Box b;
    b.start = at, b.type = d.substr(at + 4, 4);
    uint64_t size = be32(d, at);
    size_t header = 8;
    if (size == 1) {
      if (end - at < 16) break;
      size = be64(d, at + 8), header = 16, b.wide = true;
    } else if (size == 0) {
      size = end - at;
    }
    if (size < header || size > end - at)
      throw Error(what + ": its box " + std::string(b.type) + " runs past its parent",
                  ErrorKind::File);
    b.body = at + header, b.end = at + static_cast<size_t>(size);
    out.push_back(b);
    at = b.end;
  }
  return out;
}

std::optional<Box> child(std::string_view d, const Box& parent, std::string_view type,
                         const std::string& what, size_t skip = 0) {
  if (parent.end - parent.body < skip) return std::nullopt;
  for (const Box& b : children(d, parent.body + skip, parent.end, what))
    if (b.type == type) return b;
  return std::nullopt;
}

// A track's path down to its first sample entry (trak, mdia, minf, stbl, stsd, entry); none
// where it is not a video track.
std::optional<std::vector<Box>> video_entry(std::string_view d, const Box& trak,
                                            const std::string& what) {
  const auto mdia = child(d, trak, "mdia", what);
  const auto hdlr = mdia ? child(d, *mdia, "hdlr", what) : std::nullopt;
  if (!hdlr || hdlr->end - hdlr->body < 12 || d.substr(hdlr->body + 8, 4) != "vide")
    return std::nullopt;
  const auto minf = child(d, *mdia, "minf", what);
  const auto stbl = minf ? child(d, *minf, "stbl", what) : std::nullopt;
  const auto stsd = stbl ? child(d, *stbl, "stsd", what) : std::nullopt;
  // (stsd: version and flags, an entry count, then the entries)
  const auto entries = stsd && stsd->end - stsd->body >= 8
                           ? children(d, stsd->body + 8, stsd->end, what)
                           : std::vector<Box>{};
  if (entries.empty()) return std::nullopt;
  return std::vector<Box>{trak, *mdia, *minf, *stbl, *stsd, entries[0]};
}

std::vector<Box> traks(std::string_view moov, const std::string& what) {
  const std::vector<Box> top = children(moov, 0, moov.size(), what);
  if (top.empty() || top[0].type != "moov") throw InternalError("not a moov box");
  std::vector<Box> out;
  for (const Box& b : children(moov, top[0].body, top[0].end, what))
    if (b.type == "trak") out.push_back(b);
  return out;
}

// A full box's payload after its version and flags, if at least `bytes` long.
std::optional<size_t> full_box(const Box& b, size_t bytes) {
  if (b.end - b.body < 4 + bytes) return std::nullopt;
  return b.body + 4;
}

// An equi box's bounds (top, bottom, left, right from `at`), as MP4's and Matroska's carry them.
void read_equi(std::string_view d, size_t at, SphericalVideo& v, const std::string& what) {
  const uint32_t t = be32(d, at), bo = be32(d, at + 4), l = be32(d, at + 8), r = be32(d, at + 12);
  if (l >= UINT32_MAX - r || t >= UINT32_MAX - bo)
    throw Error(what + ": its spherical metadata's equi bounds cross (the frame would be empty)",
                ErrorKind::File);
  v.kind = SphericalVideo::Kind::Equirect;
  v.name = t || bo || l || r ? "tiled equirectangular" : "equirectangular";
  v.top = t / kUnit, v.bottom = bo / kUnit, v.left = l / kUnit, v.right = r / kUnit;
}

// A cbmp box's layout and padding (from `at`).
void read_cbmp(std::string_view d, size_t at, SphericalVideo& v) {
  const uint32_t layout = be32(d, at);
  v.kind = layout == 0 ? SphericalVideo::Kind::Cubemap : SphericalVideo::Kind::Other;
  v.name = layout == 0 ? "cubemap" : "cubemap layout " + std::to_string(layout);
  v.padding = be32(d, at + 4);
}

void read_sv3d(std::string_view d, const Box& sv3d, SphericalVideo& v, const std::string& what) {
  const auto proj = child(d, sv3d, "proj", what);
  if (!proj) return;
  for (const Box& b : children(d, proj->body, proj->end, what)) {
    if (b.type == "prhd") {
      if (const auto at = full_box(b, 12)) {
        v.yaw = static_cast<int32_t>(be32(d, *at)) / 65536.0;
        v.pitch = static_cast<int32_t>(be32(d, *at + 4)) / 65536.0;
        v.roll = static_cast<int32_t>(be32(d, *at + 8)) / 65536.0;
      }
    } else if (b.type == "equi") {
      if (const auto at = full_box(b, 16)) read_equi(d, *at, v, what);
    } else if (b.type == "cbmp") {
      if (const auto at = full_box(b, 8)) read_cbmp(d, *at, v);
    } else if (b.type == "mshp") {
      v.kind = SphericalVideo::Kind::Other, v.name = "mesh";
    }
  }
}

// Spherical Video V1 (a uuid box in the trak holding RDF XML), read as libavformat reads it: an
// equirect where StitchingSoftware is there and Spherical, Stitched and ProjectionType say
// true, true and equirectangular; StereoMode's left-right or top-bottom. The initial view's
// heading, pitch and roll are where a viewer starts looking, not the frame's pose: not read
// (libavformat 5.1 reads them as 0).
constexpr std::string_view kV1Uuid =
    "\xff\xcc\x82\x63\xf8\x55\x4a\x93\x88\x14\x58\x7a\x02\x52\x1f\xdd";

// The text after `key` (case-insensitively), or npos.
size_t after(std::string_view xml, std::string_view key) {
  const auto it = std::search(xml.begin(), xml.end(), key.begin(), key.end(), [](char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) ==
           std::tolower(static_cast<unsigned char>(b));
  });
  return it == xml.end() ? std::string_view::npos
                         : static_cast<size_t>(it - xml.begin()) + key.size();
}

bool says(std::string_view xml, std::string_view key, std::string_view value) {
  const size_t at = after(xml, key);
  return at != std::string_view::npos && after(xml.substr(at), value) != std::string_view::npos;
}

void read_v1(std::string_view xml, SphericalVideo& v) {
  if (after(xml, "<GSpherical:StitchingSoftware>") == std::string_view::npos ||
      !says(xml, "<GSpherical:Spherical>", "true") || !says(xml, "<GSpherical:Stitched>", "true") ||
      !says(xml, "<GSpherical:ProjectionType>", "equirectangular"))
    return;
  v.kind = SphericalVideo::Kind::Equirect, v.name = "equirectangular";
  if (after(xml, "<GSpherical:StereoMode>") != std::string_view::npos) {
    const bool lr = after(xml, "left-right") != std::string_view::npos;
    const bool tb = !lr && after(xml, "top-bottom") != std::string_view::npos;
    v.stereo = lr   ? SphericalVideo::Stereo::LeftRight
               : tb ? SphericalVideo::Stereo::TopBottom
                    : SphericalVideo::Stereo::Mono;
    v.stereo_name = lr ? "side by side" : tb ? "top and bottom" : "2D";
  }
}

void read_st3d(std::string_view d, const Box& st3d, SphericalVideo& v) {
  const auto at = full_box(st3d, 1);
  if (!at) return;
  const auto mode = static_cast<unsigned char>(d[*at]);
  v.stereo = mode == 0   ? SphericalVideo::Stereo::Mono
             : mode == 1 ? SphericalVideo::Stereo::TopBottom
             : mode == 2 ? SphericalVideo::Stereo::LeftRight
                         : SphericalVideo::Stereo::Other;
  v.stereo_name = mode == 0   ? "2D"
                  : mode == 1 ? "top and bottom"
                  : mode == 2 ? "side by side"
                  : mode == 4 ? "side by side (inverted)"
                              : "st3d mode " + std::to_string(mode);
}

std::string box(std::string_view type, const std::string& payload) {
  std::string b(8, '\0');
  put32(b, 0, static_cast<uint32_t>(8 + payload.size()));
  b.replace(4, 4, type);
  return b + payload;
}

std::string u32s(std::initializer_list<uint32_t> values) {
  std::string s(4 * values.size(), '\0');
  size_t at = 0;
  for (uint32_t v : values) put32(s, at, v), at += 4;
  return s;
}

// libavformat's writing of the same (movenc.c's st3d and sv3d).
std::string spherical_boxes(const SphericalVideo& v) {
  std::string out;
  if (v.stereo == SphericalVideo::Stereo::TopBottom ||
      v.stereo == SphericalVideo::Stereo::LeftRight)
    out +=
        box("st3d", std::string(4, '\0') +
                        static_cast<char>(v.stereo == SphericalVideo::Stereo::TopBottom ? 1 : 2));
  if (v.kind != SphericalVideo::Kind::Equirect && v.kind != SphericalVideo::Kind::Cubemap)
    return out;
  const auto fixed = [](double a) {
    return static_cast<uint32_t>(static_cast<int32_t>(std::llround(a * 65536)));
  };
  const auto bound = [](double f) {
    return static_cast<uint32_t>(std::floor(std::clamp(f, 0.0, 1.0) * kUnit));
  };
  const std::string map =
      v.kind == SphericalVideo::Kind::Cubemap
          ? box("cbmp", u32s({0, 0, static_cast<uint32_t>(v.padding)}))
          : box("equi", u32s({0, bound(v.top), bound(v.bottom), bound(v.left), bound(v.right)}));
  const std::string proj =
      box("proj", box("prhd", u32s({0, fixed(v.yaw), fixed(v.pitch), fixed(v.roll)})) + map);
  return out + box("sv3d", box("svhd", std::string(4, '\0') + "panoproj" + '\0') + proj);
}

bool read_at(int fd, std::string& into, uint64_t offset) {
  size_t done = 0;
  while (done < into.size()) {
    const ssize_t n =
        ::pread(fd, into.data() + done, into.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

// The top-level moov box's offset and size in the file at `fd` of `bytes` bytes; none where the
// boxes do not lead to one.
std::optional<std::pair<uint64_t, uint64_t>> find_moov(int fd, uint64_t bytes) {
  uint64_t at = 0;
  while (bytes - at >= 8) {
    std::string h(16, '\0');
    h.resize(static_cast<size_t>(std::min<uint64_t>(16, bytes - at)));
    if (!read_at(fd, h, at)) return std::nullopt;
    uint64_t size = be32(h, 0);
    if (size == 1 && h.size() >= 16) size = be64(h, 8);
    if (size == 0) size = bytes - at;
    if (size < 8 || size > bytes - at) return std::nullopt;
    if (h.compare(4, 4, "moov") == 0) return std::pair{at, size};
    at += size;
  }
  return std::nullopt;
}

// Matroska's EBML: an element's ID (its marker bit kept) and its payload's place.
struct Element {
  uint32_t id = 0;
  size_t body = 0, end = 0;
};

constexpr uint32_t kSegment = 0x18538067, kTracks = 0x1654AE6B, kTrackEntry = 0xAE,
                   kTrackType = 0x83, kVideo = 0xE0, kStereoMode = 0x53B8, kProjection = 0x7670,
                   kProjectionType = 0x7671, kProjectionPrivate = 0x7672, kPoseYaw = 0x7673,
                   kPosePitch = 0x7674, kPoseRoll = 0x7675;

// A variable-length integer at `at` (advanced past it): an ID (marker kept, at most 4 bytes) or
// a size (at most 8; all ones: unknown, given as npos). None where the bytes do not hold one.
std::optional<uint64_t> vint(std::string_view d, size_t& at, bool id) {
  if (at >= d.size()) return std::nullopt;
  const auto first = static_cast<unsigned char>(d[at]);
  int length = 1;
  while (length <= 8 && !(first & (0x80 >> (length - 1)))) ++length;
  if (length > (id ? 4 : 8) || at + static_cast<size_t>(length) > d.size()) return std::nullopt;
  uint64_t v = id ? first : first & (0xFFu >> length);
  bool ones = v == (0xFFu >> length);
  for (int i = 1; i < length; ++i) {
    const auto byte = static_cast<unsigned char>(d[at + static_cast<size_t>(i)]);
    v = v << 8 | byte;
    ones = ones && byte == 0xFF;
  }
  at += static_cast<size_t>(length);
  return !id && ones ? std::optional<uint64_t>(std::string_view::npos) : v;
}

// The elements in [begin, end) of `d`: an unknown size runs to `end`; an element past `end`
// throws Error unless `cut` (the bytes read end before the file: the walk stops there).
std::vector<Element> elements(std::string_view d, size_t begin, size_t end, const std::string& what,
                              bool cut = false) {
  std::vector<Element> out;
  size_t at = begin;
  while (at < end) {
    const auto id = vint(d, at, true);
    const auto size = id ? vint(d, at, false) : std::nullopt;
    if (!size || at > end) {
      if (cut) break;
      throw Error(what + ": its Matroska element headers run past their parent", ErrorKind::File);
    }
    Element e{static_cast<uint32_t>(*id), at, *size == std::string_view::npos ? end : 0};
    if (*size != std::string_view::npos) {
      if (*size > end - at) {
        if (cut) break;
        throw Error(
            what + ": its Matroska element " + std::to_string(*id) + " runs past its parent",
            ErrorKind::File);
      }
      e.end = at + static_cast<size_t>(*size);
    }
    out.push_back(e);
    at = e.end;
  }
  return out;
}

std::optional<Element> element(std::string_view d, const Element& parent, uint32_t id,
                               const std::string& what) {
  for (const Element& e : elements(d, parent.body, parent.end, what))
    if (e.id == id) return e;
  return std::nullopt;
}

uint64_t uinteger(std::string_view d, const Element& e) {
  uint64_t v = 0;
  for (size_t i = e.body; i < e.end && i < e.body + 8; ++i)
    v = v << 8 | static_cast<unsigned char>(d[i]);
  return v;
}

double real(std::string_view d, const Element& e) {
  const uint64_t bits = uinteger(d, e);
  if (e.end - e.body == 4) {
    float f;
    const auto b32 = static_cast<uint32_t>(bits);
    std::memcpy(&f, &b32, 4);
    return f;
  }
  if (e.end - e.body != 8) return 0;
  double x;
  std::memcpy(&x, &bits, 8);
  return x;
}

// Matroska's StereoMode as libavformat gives it (matroska.c's conversion: left eye first unless
// "inverted").
void read_stereo_mode(uint64_t mode, SphericalVideo& v) {
  using S = SphericalVideo::Stereo;
  static const std::pair<S, const char*> kModes[] = {
      {S::Mono, ""},  // (mono: libavformat gives no layout)
      {S::LeftRight, "side by side"},
      {S::Other, "top and bottom (inverted)"},
      {S::TopBottom, "top and bottom"},
      {S::Other, "checkerboard (inverted)"},
      {S::Other, "checkerboard"},
      {S::Other, "interleaved lines (inverted)"},
      {S::Other, "interleaved lines"},
      {S::Other, "interleaved columns (inverted)"},
      {S::Other, "interleaved columns"},
      {S::Mono, ""},  // (anaglyphs: libavformat gives no layout)
      {S::Other, "side by side (inverted)"},
      {S::Mono, ""},
      {S::Other, "frame alternate"},
      {S::Other, "frame alternate (inverted)"}};
  if (mode >= std::size(kModes) || !*kModes[mode].second) return;
  v.stereo = kModes[mode].first, v.stereo_name = kModes[mode].second;
}

// A Projection element as libavformat reads it (matroskadec.c): equirect with no private data
// or an equi payload, cubemap with a cbmp payload (layout 0 only), the pose truncated to 16.16.
void read_projection(std::string_view d, const Element& projection, SphericalVideo& v,
                     const std::string& what) {
  std::optional<Element> type, priv;
  double pose[3] = {0, 0, 0};
  for (const Element& e : elements(d, projection.body, projection.end, what)) {
    if (e.id == kProjectionType) type = e;
    if (e.id == kProjectionPrivate) priv = e;
    if (e.id == kPoseYaw) pose[0] = real(d, e);
    if (e.id == kPosePitch) pose[1] = real(d, e);
    if (e.id == kPoseRoll) pose[2] = real(d, e);
  }
  const uint64_t kind = type ? uinteger(d, *type) : 0;
  const size_t bytes = priv ? priv->end - priv->body : 0;
  if (kind == 1) {
    if (bytes == 20) {
      read_equi(d, priv->body + 4, v, what);
    } else if (bytes == 0) {
      v.kind = SphericalVideo::Kind::Equirect, v.name = "equirectangular";
    } else {
      throw Error(what + ": its Projection's private data (" + std::to_string(bytes) +
                      " bytes) is not an equi box's",
                  ErrorKind::File);
    }
  } else if (kind == 2) {
    if (bytes != 12)
      throw Error(what + ": its Projection's private data (" + std::to_string(bytes) +
                      " bytes) is not a cbmp box's",
                  ErrorKind::File);
    if (be32(d, priv->body + 4) != 0) return;  // (libavformat: an unknown layout, unread)
    read_cbmp(d, priv->body + 4, v);
  } else {
    return;  // (rectangular, and types libavformat 5.1 does not read: a mesh)
  }
  const auto fixed = [](double a) {
    return std::isfinite(a)
               ? static_cast<int32_t>(std::clamp(a, -32768.0, 32767.0) * 65536) / 65536.0
               : 0;
  };
  v.yaw = fixed(pose[0]), v.pitch = fixed(pose[1]), v.roll = fixed(pose[2]);
}

// The Tracks element of a Matroska file's first bytes, none where they do not hold it whole.
std::optional<Element> tracks_of(std::string_view head, const std::string& what) {
  std::optional<Element> tracks;
  for (const Element& top : elements(head, 0, head.size(), what, true)) {
    if (top.id != kSegment) continue;
    for (const Element& e : elements(head, top.body, std::min(top.end, head.size()), what, true))
      if (e.id == kTracks && !tracks) tracks = e;
    break;
  }
  return tracks;
}

}  // namespace

SphericalVideo spherical_of_matroska(std::string_view head, int stream, const std::string& what) {
  SphericalVideo v;
  const std::optional<Element> tracks = tracks_of(head, what);
  if (!tracks) return v;
  std::vector<Element> entries;
  for (const Element& e : elements(head, tracks->body, tracks->end, what))
    if (e.id == kTrackEntry) entries.push_back(e);
  const auto video = [&](const Element& entry) -> std::optional<Element> {
    const auto type = element(head, entry, kTrackType, what);
    return type && uinteger(head, *type) == 1 ? element(head, entry, kVideo, what) : std::nullopt;
  };
  std::optional<Element> track;
  if (stream >= 0 && static_cast<size_t>(stream) < entries.size())
    track = video(entries[static_cast<size_t>(stream)]);
  for (size_t i = 0; i < entries.size() && !track; ++i) track = video(entries[i]);
  if (!track) return v;
  for (const Element& e : elements(head, track->body, track->end, what)) {
    if (e.id == kStereoMode) read_stereo_mode(uinteger(head, e), v);
    if (e.id == kProjection) read_projection(head, e, v, what);
  }
  return v;
}

SphericalVideo read_matroska_spherical(const std::string& path, int stream,
                                       const std::string& what) {
  // (64 kB, then more up to 16 MB, until the bytes hold the Tracks element: it is near the start)
  std::ifstream f(path, std::ios::binary);
  std::string head;
  for (size_t want = size_t{64} << 10; want <= size_t{16} << 20; want *= 16) {
    const size_t had = head.size();
    head.resize(want);
    f.read(head.data() + had, static_cast<std::streamsize>(want - had));
    head.resize(had + static_cast<size_t>(std::max<std::streamsize>(f.gcount(), 0)));
    if (head.size() < want || tracks_of(head, what)) break;
  }
  return spherical_of_matroska(head, stream, what);
}

SphericalVideo spherical_of_moov(std::string_view moov, int stream, const std::string& what) {
  SphericalVideo v;
  const std::vector<Box> all = traks(moov, what);
  std::optional<std::vector<Box>> path;
  if (stream >= 0 && static_cast<size_t>(stream) < all.size())
    path = video_entry(moov, all[static_cast<size_t>(stream)], what);
  for (size_t i = 0; i < all.size() && !path; ++i) path = video_entry(moov, all[i], what);
  if (!path) return v;
  const Box& entry = path->back();
  if (entry.end - entry.body < kVisualEntry) return v;
  for (const Box& b : children(moov, entry.body + kVisualEntry, entry.end, what)) {
    if (b.type == "sv3d") read_sv3d(moov, b, v, what);
    if (b.type == "st3d") read_st3d(moov, b, v);
  }
  if (v.any()) return v;  // (V2's boxes, else V1's XML)
  for (const Box& b : children(moov, path->front().body, path->front().end, what))
    if (b.type == "uuid" && b.end - b.body >= 16 && moov.substr(b.body, 16) == kV1Uuid)
      read_v1(moov.substr(b.body + 16, b.end - b.body - 16), v);
  return v;
}

std::string read_moov(const std::string& path, bool* last) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  struct stat st {};
  std::string moov;
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
    const auto bytes = static_cast<uint64_t>(st.st_size);
    if (const auto found = find_moov(fd, bytes); found && found->second <= kMostMoov) {
      moov.resize(static_cast<size_t>(found->second));
      if (!read_at(fd, moov, found->first)) moov.clear();
      if (last) *last = found->first + found->second == bytes;
    }
  }
  ::close(fd);
  return moov;
}

std::string moov_with_spherical(std::string_view moov, const SphericalVideo& v) {
  const std::string what = "its moov box";
  std::optional<std::vector<Box>> path;
  for (const Box& t : traks(moov, what))
    if (!path) path = video_entry(moov, t, what);
  if (!path) throw Error(what + " has no video track");
  const Box& entry = path->back();
  if (entry.end - entry.body < kVisualEntry)
    throw Error(what + ": its video sample entry is short");
  size_t end = entry.body + kVisualEntry;
  for (const Box& b : children(moov, entry.body + kVisualEntry, entry.end, what)) {
    if (b.type == "sv3d" || b.type == "st3d")
      throw Error(what + ": its video track has a " + std::string(b.type) + " box already");
    if (be32(moov, b.start) == 0) end = 0;  // (a box "to the end" would take in those added)
    if (end) end = b.end;
  }
  if (end != entry.end)
    throw Error(what + ": its video sample entry's boxes do not end where it does");
  const std::string added = spherical_boxes(v);
  std::string out(moov.substr(0, entry.end));
  out += added;
  out += moov.substr(entry.end);
  std::vector<Box> grown = *path;
  grown.insert(grown.begin(), children(moov, 0, moov.size(), what)[0]);  // (the moov box)
  for (const Box& b : grown) {
    if (b.wide) throw Error(what + ": its box " + std::string(b.type) + " has a 64-bit size");
    put32(out, b.start, static_cast<uint32_t>(b.end - b.start + added.size()));
  }
  return out;
}

void write_mp4_spherical(int fd, const std::string& path, const SphericalVideo& v) {
  struct stat st {};
  const auto fail = [&](const std::string& why) {
    throw Error("cannot write " + path + ": " + why, ErrorKind::File);
  };
  // (Read through a second descriptor of the same file: `fd` may be open for writing only.)
  const int in = ::open(("/proc/self/fd/" + std::to_string(fd)).c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0 || ::fstat(in, &st) != 0) {
    if (in >= 0) ::close(in);
    fail(std::strerror(errno));
  }
  const auto bytes = static_cast<uint64_t>(st.st_size);
  const auto found = find_moov(in, bytes);
  std::string moov(found ? static_cast<size_t>(std::min(found->second, kMostMoov)) : 0, '\0');
  const bool read = found && read_at(in, moov, found->first);
  ::close(in);
  if (!found || found->first + found->second != bytes || found->second > kMostMoov || !read)
    fail("its spherical metadata cannot be written: its moov box does not end the file");
  const std::string out = moov_with_spherical(moov, v);
  size_t done = 0;
  while (done < out.size()) {
    const ssize_t n =
        ::pwrite(fd, out.data() + done, out.size() - done, static_cast<off_t>(found->first + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(std::strerror(n < 0 ? errno : ENOSPC));
    done += static_cast<size_t>(n);
  }
}

}  // namespace panoproj
