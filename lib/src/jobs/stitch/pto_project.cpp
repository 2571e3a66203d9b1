// The .pto reader (pto_project.hpp): lines split into tokens (a key from the line's table, then a
// number, "=N" (image N's value), or a quoted text), checked as they are read.
#include "jobs/stitch/pto_project.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

#include "base/input_check.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

// The keys each line takes, longest first where one is a prefix of another.
const std::vector<std::string_view> kPanoKeys{"f", "w", "h", "v", "E", "R",
                                              "S", "n", "k", "T", "P"};
const std::vector<std::string_view> kOptionKeys{"g", "i", "f", "m", "p"};
const std::vector<std::string_view> kImageKeys{
    "TrX", "TrY", "TrZ", "Tpy", "Tpp", "Eev", "Ra", "Rb", "Rc", "Rd", "Re", "Er", "Eb", "Va",
    "Vb",  "Vc",  "Vd",  "Vx",  "Vy",  "Vm",  "Vf", "Rt", "w",  "h",  "f",  "v",  "y",  "p",
    "r",   "j",   "a",   "b",   "c",   "d",   "e",  "g",  "t",  "S",  "C",  "n"};
const std::vector<std::string_view> kMaskKeys{"i", "t", "p"};
// Image values that may be links (=N), and those that make an image's lens.
const std::vector<std::string_view> kLensKeys{"v", "a", "b", "c", "d", "e", "g", "t"};

struct Token {
  std::string key, text;  // text: the value as written (quotes removed)
  bool quoted = false;
};

class Reader {
 public:
  Reader(std::string path, int line, std::string_view what)
      : path_(std::move(path)), line_(line), what_(what) {}
  [[noreturn]] void fail(const std::string& msg) const {
    throw Error(path_ + ":" + std::to_string(line_) + ": " + std::string(what_) + ": " + msg);
  }
  std::vector<Token> tokens(std::string_view rest,
                            const std::vector<std::string_view>& keys) const {
    std::vector<Token> out;
    size_t i = 0;
    while (true) {
      while (i < rest.size() && (rest[i] == ' ' || rest[i] == '\t' || rest[i] == '\r')) ++i;
      if (i >= rest.size()) break;
      const std::string_view at = rest.substr(i);
      std::string_view key;
      for (std::string_view k : keys)
        if (at.substr(0, k.size()) == k && k.size() > key.size()) key = k;
      if (key.empty()) {
        const size_t end = std::min(at.find_first_of(" \t\r"), at.size());
        std::string known;
        for (std::string_view k : keys) known += (known.empty() ? "" : " ") + std::string(k);
        fail("unknown token '" + std::string(at.substr(0, std::min<size_t>(end, 40))) +
             "' (expected one of " + known + ")");
      }
      Token t{std::string(key), "", false};
      i += key.size();
      if (i < rest.size() && rest[i] == '"') {
        const size_t close = rest.find('"', i + 1);
        if (close == std::string_view::npos) fail("token " + t.key + ": no closing quote");
        t.text = std::string(rest.substr(i + 1, close - i - 1));
        t.quoted = true;
        i = close + 1;
      } else {
        const size_t end = std::min(rest.find_first_of(" \t\r", i), rest.size());
        t.text = std::string(rest.substr(i, end - i));
        i = end;
      }
      for (const Token& o : out)
        if (o.key == t.key) fail("token " + t.key + " given twice");
      out.push_back(std::move(t));
    }
    return out;
  }
  double number(const Token& t) const {
    double v = 0;
    const char* b = t.text.data();
    const char* e = b + t.text.size();
    const auto r = std::from_chars(b, e, v);
    if (t.quoted || t.text.empty() || r.ec != std::errc() || r.ptr != e || !std::isfinite(v))
      fail("token " + t.key + t.text + ": expected a finite number");
    return v;
  }
  int64_t integer(const Token& t, int64_t lo, int64_t hi) const {
    const double v = number(t);
    if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
      fail("token " + t.key + t.text + ": expected a whole number in [" + std::to_string(lo) +
           ", " + std::to_string(hi) + "]");
    return static_cast<int64_t>(v);
  }
  // "l,r,t,b" inside a frame of w x h (none given: not checked against it).
  PtoRect rect(const Token& t, int64_t w, int64_t h) const {
    PtoRect r;
    int64_t* v[4] = {&r.left, &r.right, &r.top, &r.bottom};
    std::string_view s = t.text;
    for (int k = 0; k < 4; ++k) {
      const size_t comma = k < 3 ? s.find(',') : s.size();
      if (comma == std::string_view::npos)
        fail("token S" + t.text + ": expected left,right,top,bottom");
      *v[k] = integer(Token{"S", std::string(s.substr(0, comma))}, -(int64_t{1} << 31),
                      int64_t{1} << 31);
      s = k < 3 ? s.substr(comma + 1) : std::string_view{};
    }
    if (!(r.left < r.right && r.top < r.bottom) ||
        (w > 0 && (r.left < 0 || r.top < 0 || r.right > w || r.bottom > h)))
      fail("token S" + t.text + ": the crop must be a non-empty rectangle inside the " +
           std::to_string(w) + "x" + std::to_string(h) + " frame");
    return r;
  }
  int line() const { return line_; }

 private:
  std::string path_;
  int line_;
  std::string_view what_;
};

constexpr int64_t kMaxSide = (int64_t{1} << 31) - 1;

void read_pano(const Reader& rd, std::string_view rest, PtoPanorama& p) {
  p.line = rd.line();
  bool size_w = false, size_h = false;
  std::optional<Token> crop;
  for (const Token& t : rd.tokens(rest, kPanoKeys)) {
    if (t.key == "f")
      p.projection = static_cast<int>(rd.integer(t, 0, 99));
    else if (t.key == "w")
      p.width = rd.integer(t, 1, kMaxSide), size_w = true;
    else if (t.key == "h")
      p.height = rd.integer(t, 1, kMaxSide), size_h = true;
    else if (t.key == "v") {
      p.hfov = rd.number(t);
      if (!(p.hfov > 0 && p.hfov <= 360))
        rd.fail("token v" + t.text + ": expected a field of view in (0, 360]");
    } else if (t.key == "S")
      crop = t;
    else if (t.key == "T")
      p.depth = t.text;
    else if (t.key == "n")
      p.output = t.text;
    else if (t.key == "P") {
      std::istringstream in(t.text);
      for (std::string w; in >> w;) p.params.push_back(rd.number(Token{"P", w}));
    } else if (t.key == "E") {
      p.exposure = rd.number(t);
    } else if (t.key == "R") {
      p.hdr = rd.integer(t, 0, 1) == 1;
    } else if (t.key == "k") {
      rd.number(t);
    }
  }
  if (!size_w || !size_h) rd.fail("the panorama needs w and h");
  if (p.hfov == 0) rd.fail("the panorama needs v (its field of view)");
  if (crop) p.crop = rd.rect(*crop, p.width, p.height);
  if (!p.depth.empty() && p.depth != "UINT8" && p.depth != "UINT16" && p.depth != "FLOAT")
    rd.fail("token T\"" + p.depth + "\": expected UINT8, UINT16 or FLOAT");
}

struct PendingImage {
  PtoImage image;
  std::map<std::string, int> links;  // key -> image
  std::map<std::string, double> values;
};

PendingImage read_image(const Reader& rd, std::string_view rest, bool disabled) {
  PendingImage p;
  PtoImage& im = p.image;
  im.line = rd.line();
  im.disabled = disabled;
  std::optional<Token> crop;
  bool has_w = false, has_h = false, has_n = false;
  for (const Token& t : rd.tokens(rest, kImageKeys)) {
    if (t.key == "n") {
      im.name = t.text, has_n = true;
    } else if (t.key == "S") {
      crop = t;
    } else if (t.key == "C") {
      rd.fail("token C (a cut frame) is not supported: give the crop as S");
    } else if (t.key == "Vf") {
      im.flat_field = t.text;
    } else if (t.key == "Vm") {
      im.vignetting_mode = static_cast<int>(rd.integer(t, 0, 15));
    } else if (t.key == "Rt") {
      im.response_type = static_cast<int>(rd.integer(t, 0, 4));
      if (im.response_type > 1)
        rd.fail("token Rt" + t.text +
                ": expected 0 (EMoR) or 1 (linear); Hugin has no other response in a project");
    } else if (t.key == "w") {
      im.width = rd.integer(t, 1, kMaxSide), has_w = true;
    } else if (t.key == "h") {
      im.height = rd.integer(t, 1, kMaxSide), has_h = true;
    } else if (t.key == "f") {
      im.lens_type = static_cast<int>(rd.integer(t, 0, 99));
    } else if (!t.quoted && t.text.size() > 1 && t.text[0] == '=') {
      p.links[t.key] =
          static_cast<int>(rd.integer(Token{t.key, t.text.substr(1)}, 0, kMaxPtoImages - 1));
    } else {
      p.values[t.key] = rd.number(t);
    }
  }
  if (!has_w || !has_h) rd.fail("an image needs w and h");
  if (!has_n) rd.fail("an image needs n (its file)");
  for (const char* k : {"TrX", "TrY", "TrZ", "Tpy", "Tpp"}) {
    const auto i = p.values.find(k);
    if (i != p.values.end() && i->second != 0)
      rd.fail(std::string("token ") + k + ": translation (mosaic mode) is not supported");
  }
  if (crop) im.crop = rd.rect(*crop, im.width, im.height);
  return p;
}

void read_mask(const Reader& rd, std::string_view rest, PtoMask& m, int images) {
  m.line = rd.line();
  bool has_i = false, has_p = false;
  for (const Token& t : rd.tokens(rest, kMaskKeys)) {
    if (t.key == "i")
      m.image = static_cast<int>(rd.integer(t, 0, kMaxPtoImages - 1)), has_i = true;
    else if (t.key == "t")
      m.type = static_cast<int>(rd.integer(t, 0, 4));
    else {
      std::istringstream in(t.text);
      for (std::string w; in >> w;) m.xy.push_back(rd.number(Token{"p", w}));
      has_p = true;
    }
  }
  if (!has_i || !has_p) rd.fail("a mask needs i (its image) and p (its points)");
  if (m.image >= images)
    rd.fail("token i" + std::to_string(m.image) + ": no such image (" + std::to_string(images) +
            " before it)");
  if (m.xy.size() % 2 != 0 || m.xy.size() < 6)
    rd.fail("token p: a mask needs at least 3 points (x y pairs), got " +
            std::to_string(m.xy.size()) + " numbers");
}

double& image_value(PtoImage& im, std::string_view key) {
  static double ignored;
  if (key == "v") return im.hfov;
  if (key == "y") return im.yaw;
  if (key == "p") return im.pitch;
  if (key == "r") return im.roll;
  if (key == "a") return im.a;
  if (key == "b") return im.b;
  if (key == "c") return im.c;
  if (key == "d") return im.d;
  if (key == "e") return im.e;
  if (key == "g") return im.g;
  if (key == "t") return im.t;
  if (key == "Eev") return im.exposure;
  if (key == "Er") return im.red;
  if (key == "Eb") return im.blue;
  if (key == "Vx") return im.vignetting_x;
  if (key == "Vy") return im.vignetting_y;
  if (key.size() == 2 && key[0] == 'R' && key[1] >= 'a' && key[1] <= 'e')
    return im.emor[static_cast<size_t>(key[1] - 'a')];
  if (key.size() == 2 && key[0] == 'V' && key[1] >= 'a' && key[1] <= 'd')
    return im.vignetting[static_cast<size_t>(key[1] - 'a')];
  return ignored;
}

// Links resolved to values (a chain followed to its end; a cycle refused), lenses grouped.
void resolve(std::vector<PendingImage>& pending, const std::string& path) {
  const int n = static_cast<int>(pending.size());
  for (int i = 0; i < n; ++i) {
    PendingImage& p = pending[static_cast<size_t>(i)];
    const Reader rd(path, p.image.line, "i line");
    std::map<std::string, double> values = p.values;
    for (const auto& [key, to] : p.links) {
      int at = to, steps = 0;
      while (true) {
        if (at >= n) rd.fail("token " + key + "=" + std::to_string(to) + ": no such image");
        const PendingImage& q = pending[static_cast<size_t>(at)];
        if (const auto l = q.links.find(key); l != q.links.end()) {
          if (++steps > n)
            rd.fail("token " + key + "=" + std::to_string(to) + ": the links form a cycle");
          at = l->second;
          continue;
        }
        const auto v = q.values.find(key);
        values[key] = v == q.values.end() ? 0.0 : v->second;
        break;
      }
      if (key == "v") p.image.lens = at;
      if (key == "j") p.image.stack = at;
    }
    if (!p.links.count("v")) p.image.lens = i;
    if (!p.links.count("j")) p.image.stack = i;
    for (const auto& [key, v] : values) image_value(p.image, key) = v;
    if (!values.count("v")) rd.fail("an image needs v (its field of view)");
    if (!(p.image.hfov > 0 && p.image.hfov <= 360))
      rd.fail("token v: expected a field of view in (0, 360]");
    if (p.image.vignetting_mode != 5) p.image.vignetting = {1, 0, 0, 0};
  }
}

}  // namespace

PtoProject parse_pto(std::string_view text, const std::string& path) {
  if (static_cast<int64_t>(text.size()) > kMaxPtoBytes)
    throw Error(path + ": a project of " + std::to_string(text.size()) + " bytes (at most " +
                std::to_string(kMaxPtoBytes) + ")");
  PtoProject project;
  project.path = path;
  std::vector<PendingImage> pending;
  bool has_pano = false, disabled = false;
  int line = 0;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view l = text.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    while (!l.empty() && (l.back() == '\r' || l.back() == ' ' || l.back() == '\t'))
      l.remove_suffix(1);
    if (l.empty()) continue;
    if (l.find('\0') != std::string_view::npos)
      Reader(path, line, "line").fail("a NUL byte: not a text project");
    if (l.substr(0, 7) == "#-hugin") {
      disabled = l.find(" disabled") != std::string_view::npos;
      continue;
    }
    if (l[0] == '#') continue;
    if (l.size() > 1 && l[1] != ' ' && l[1] != '\t')
      Reader(path, line, "line")
          .fail("unknown line '" + std::string(l.substr(0, 20)) +
                "' (expected p, m, i, k, v or c)");
    const std::string_view rest = l.substr(1);
    switch (l[0]) {
      case 'p': {
        const Reader rd(path, line, "p line");
        if (has_pano) rd.fail("a second p line");
        read_pano(rd, rest, project.pano);
        has_pano = true;
        break;
      }
      case 'm': {
        const Reader rd(path, line, "m line");
        for (const Token& t : rd.tokens(rest, kOptionKeys)) {
          const double v = rd.number(t);
          if (t.key == "i") project.interpolator = static_cast<int>(rd.integer(t, 0, 7));
          (void)v;
        }
        break;
      }
      case 'i': {
        if (static_cast<int>(pending.size()) >= kMaxPtoImages)
          Reader(path, line, "i line")
              .fail("more than " + std::to_string(kMaxPtoImages) + " images");
        pending.push_back(read_image(Reader(path, line, "i line"), rest, disabled));
        disabled = false;
        break;
      }
      case 'k': {
        PtoMask m;
        read_mask(Reader(path, line, "k line"), rest, m, static_cast<int>(pending.size()));
        project.masks.push_back(std::move(m));
        break;
      }
      case 'v':
      case 'c':
        break;
      default:
        Reader(path, line, "line")
            .fail("unknown line '" + std::string(l.substr(0, 20)) +
                  "' (expected p, m, i, k, v or c)");
    }
  }
  if (!has_pano) throw Error(path + ": no p line (the panorama)");
  if (pending.empty()) throw Error(path + ": no i lines (the images)");
  resolve(pending, path);
  for (PendingImage& p : pending) project.images.push_back(std::move(p.image));
  for (const PtoMask& m : project.masks)
    if (m.image >= static_cast<int>(project.images.size()))
      Reader(path, m.line, "k line").fail("token i" + std::to_string(m.image) + ": no such image");
  return project;
}

PtoProject read_pto(const std::string& path) {
  // One byte more than the bound: a longer file is refused by parse_pto's size check.
  const std::string text = read_head(path, static_cast<size_t>(kMaxPtoBytes) + 1, "the project",
                                     "a Hugin project (.pto)");
  return parse_pto(text, path);
}

}  // namespace panoproj
