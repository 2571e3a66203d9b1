#include "panoproj/convert.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <array>
#include <map>
#include <set>
#include <vector>
#include <sstream>

#include "base/parallel.hpp"
#include "base/text.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "panoproj/rotation.hpp"
#include "photometry/source_correction.hpp"

namespace panoproj {

namespace {

StereoLayout stereo_layout(const ProjectionSpec& s) {
  const std::string l = s.choice("stereo");
  return l == "tb" ? StereoLayout::TopBottom : l == "sbs" ? StereoLayout::SideBySide : StereoLayout::Mono;
}

Stereo stereo_of(const ProjectionSpec& from, const ProjectionSpec& to) {
  const Stereo s{stereo_layout(from), stereo_layout(to), from.choice("eye") == "right" ? 1 : 0};
  if (from.given("eye") && s.source == StereoLayout::Mono)
    throw Error(from.str() + ": eye=" + from.choice("eye") + " picks an eye of a stereo source (add stereo=tb or sbs)");
  if (to.given("eye"))
    throw Error(to.str() + ": eye= is for the source (a stereo target gets both eyes; a mono one the source's eye=)");
  if (from.given("eye") && s.target != StereoLayout::Mono)
    throw Error(from.str() + ": eye= with a stereo target (it gets both eyes; drop eye= or make the target mono)");
  for (const ProjectionSpec* p : {&from, &to})
    if (stereo_layout(*p) != StereoLayout::Mono && p->kind() == Kind::Cubemap && p->choice("layout") == "files")
      throw Error(p->str() + ": stereo= with layout=files (stereo cubes are one image: use layout 6x1, 3x2, eac, ...)");
  return s;
}

}  // namespace

Size stereo_frame(Size eye, StereoLayout layout) {
  if (layout == StereoLayout::TopBottom) return {eye.width, 2 * eye.height};
  if (layout == StereoLayout::SideBySide) return {2 * eye.width, eye.height};
  return eye;
}

Size stereo_eye(Size frame, StereoLayout layout, const char* what) {
  if (layout == StereoLayout::Mono) return frame;
  const bool tb = layout == StereoLayout::TopBottom;
  if ((tb ? frame.height : frame.width) % 2 != 0)
    throw Error(std::string(what) + ": " + size_text(frame) + " does not split into two eyes " +
                (tb ? "top and bottom (stereo=tb needs an even height)" : "side by side (stereo=sbs needs an even width)"));
  return tb ? Size{frame.width, frame.height / 2} : Size{frame.width / 2, frame.height};
}

std::array<int64_t, 2> stereo_origin(Size eye, StereoLayout layout, int e) {
  if (layout == StereoLayout::TopBottom) return {0, e * eye.height};
  if (layout == StereoLayout::SideBySide) return {e * eye.width, 0};
  return {0, 0};
}

namespace {

// The smallest side of a default output size; below it the field is refused, not rendered.
constexpr int64_t kMinDefaultSide = 8;

// The values of the spec's given numeric keys that, each changed alone, give a default size of at
// least kMinDefaultSide a side: "vfov >= 0.32 (0 < vfov < 180)", or "" when none does. Along each
// key, doubling (or halving) steps from its value to the first size that fits, then bisection.
std::string usable_values(const ProjectionSpec& spec, double density) {
  const auto fits = [&](const ParamDef& key, double v) {
    std::map<std::string, std::string> values;
    for (const ParamDef& p : spec.def().params) {
      if (!spec.given(p.key)) continue;
      char text[40];
      std::snprintf(text, sizeof text, "%.17g", p.key == key.key ? v : spec.number(p.key).value_or(0));
      values[p.key] = p.type == ParamType::Number ? text : spec.choice(p.key);
    }
    try {
      const Size s = default_size(ProjectionSpec(spec.def(), values), density);
      return s.width >= kMinDefaultSide && s.height >= kMinDefaultSide;
    } catch (const Error&) {
      return false;
    }
  };
  std::string hints;
  for (const ParamDef& p : spec.def().params) {
    if (p.type != ParamType::Number || !spec.given(p.key)) continue;
    const double v = *spec.number(p.key);
    for (const double step : {2.0, 0.5}) {
      const double end = step > 1 ? (p.hi_open ? std::nextafter(p.hi, p.lo) : p.hi) : (p.lo_open ? std::nextafter(p.lo, p.hi) : p.lo);
      if (v == 0 || !std::isfinite(end) || (step > 1 ? end <= v : end >= v)) continue;
      double bad = v, good = NAN;
      for (int k = 0; k < 64 && std::isnan(good); ++k) {
        const double next = step > 1 ? std::min(bad * step, end) : std::max(bad * step, end);
        if (fits(p, next)) good = next;
        else if (next == end) break;
        else bad = next;
      }
      if (std::isnan(good)) continue;
      for (int k = 0; k < 48; ++k) {
        const double mid = 0.5 * (bad + good);
        (fits(p, mid) ? good : bad) = mid;
      }
      char text[160];
      std::snprintf(text, sizeof text, "%s%s %s %.3g (%s)", hints.empty() ? "" : ", or ", p.key, step > 1 ? ">=" : "<=",
                    step > 1 ? good * (1 + 5e-4) : good * (1 - 5e-4), range_text(p).c_str());
      hints += text;
      break;
    }
  }
  return hints;
}

// Throws unless p's pixel centres that see a direction span at least two columns and two rows (or
// the frame's whole width or height, under two). Found on a grid of up to 256 x 256 centres; where
// the grid finds none, or all within one grid column or row, every centre is looked at around
// what it found and around the pixels of the 26 axis and diagonal directions.
void require_valid_pixels(const Projection& p, const ProjectionSpec& spec, const char* role) {
  const Size s = size_of(p);
  const int64_t nx = std::min<int64_t>(s.width, 256), ny = std::min<int64_t>(s.height, 256);  // the fine grid
  const auto valid = [&](int64_t x, int64_t y) {
    Ray d;
    return to_ray(p, static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, d);
  };
  const int64_t need_x = std::min<int64_t>(2, s.width), need_y = std::min<int64_t>(2, s.height);
  std::vector<std::array<int64_t, 2>> found;
  // A 16 x 16 grid first, then the fine one: a usual field is settled in a few dozen rays.
  for (const int64_t n : {int64_t{16}, int64_t{256}}) {
    const int64_t mx = std::min(s.width, n), my = std::min(s.height, n);
    std::set<int64_t> gx, gy;
    found.clear();
    for (int64_t j = 0; j < my; ++j)
      for (int64_t i = 0; i < mx; ++i) {
        const int64_t x = (2 * i + 1) * s.width / (2 * mx), y = (2 * j + 1) * s.height / (2 * my);
        if (!valid(x, y)) continue;
        if (found.size() < 4) found.push_back({x, y});
        gx.insert(x), gy.insert(y);
        if (static_cast<int64_t>(gx.size()) >= need_x && static_cast<int64_t>(gy.size()) >= need_y) return;
      }
    if (!found.empty()) break;
  }
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) {
        double x, y;
        if ((a || b || c) && to_pixel(p, Ray(a, b, c).normalized(), x, y) && found.size() < 32)
          found.push_back({static_cast<int64_t>(std::floor(x)), static_cast<int64_t>(std::floor(y))});
      }
  std::set<int64_t> columns, rows;
  const int64_t rx = s.width / nx + 1, ry = s.height / ny + 1;
  for (const auto& [cx, cy] : found)
    for (int64_t y = std::max<int64_t>(0, cy - ry); y <= std::min(s.height - 1, cy + ry); ++y)
      for (int64_t x = std::max<int64_t>(0, cx - rx); x <= std::min(s.width - 1, cx + rx); ++x)
        if (valid(x, y)) columns.insert(x), rows.insert(y);
  if (static_cast<int64_t>(columns.size()) >= need_x && static_cast<int64_t>(rows.size()) >= need_y) return;
  throw Error(std::string(role) + ": " + spec.str() + " on a " + size_text(s) + " frame " +
              (columns.empty() ? std::string("has no pixel that sees a direction")
                               : "sees directions from " + std::to_string(columns.size()) + " column(s) and " +
                                     std::to_string(rows.size()) + " row(s) of pixels only") +
              " (its valid region is empty or under a pixel across): give parameters that show a field");
}

// The target spec with --face-size N as its face=N.
ProjectionSpec with_face_size(const ProjectionSpec& to, const ConvertOptions& o) {
  if (!o.face_size) return to;
  const int64_t n = *o.face_size;
  const std::string given = option_number("face-size", std::to_string(n));
  if (o.size)
    throw Error("give " + option_text("size") + " or " + option_text("face-size") + ", not both");
  const auto& keys = to.def().params;
  if (std::none_of(keys.begin(), keys.end(),
                   [](const ParamDef& p) { return std::string_view(p.key) == "face"; }))
    throw Error(given + ": " + to.name() + " has no faces (it sizes cube targets; give " +
                option_text("size") + " WxH)");
  if (n < 1 || n > kMaxSide)
    throw Error(given + " (expected 1 to " + std::to_string(kMaxSide) + " pixels a side)");
  if (to.given("face") && *to.number("face") != static_cast<double>(n))
    throw Error(given + " and the spec's face=" + number_text(*to.number("face")) +
                " differ (give one)");
  const std::string text = to.str();
  return parse_spec(text + (text.find(':') == std::string::npos ? ":" : ",") +
                    "face=" + std::to_string(n));
}

}  // namespace

ConversionGeometry make_geometry(Size source_size, const ProjectionSpec& from,
                                 const ProjectionSpec& to_given, const ConvertOptions& o) {
  const ProjectionSpec to = with_face_size(to_given, o);
  for (const auto& [name, v] : {std::pair{"yaw", o.yaw}, {"pitch", o.pitch}, {"roll", o.roll}}) {
    if (!std::isfinite(v) || std::fabs(v) > 1e6) {
      std::ostringstream s;
      s << name << ": " << v << (std::isfinite(v) ? " (expected degrees within +-1e6; any angle mod 360 turns alike)"
                                                  : " (expected a finite angle in degrees)");
      throw Error(s.str());
    }
  }
  check_threads(o.threads);
  const Stereo stereo = stereo_of(from, to);
  Projection source = make_projection(from, stereo_eye(source_size, stereo.source, "the source"));
  require_valid_pixels(source, from, "from");
  Size size;
  if (o.size) {
    size = *o.size;
    if (size.width < 1 || size.height < 1 || size.width > kMaxSide || size.height > kMaxSide)
      throw Error("size: " + size_text(size) + " (expected 1 to " + std::to_string(kMaxSide) + " pixels a side)");
    size = stereo_eye(size, stereo.target, "size");
  } else {
    size = default_size(to, center_density(source));
    if (size.width < kMinDefaultSide || size.height < kMinDefaultSide) {
      const std::string wider = usable_values(to, center_density(source));
      throw Error("to: " + to.str() + " at the source's resolution would be " + size_text(size) + " (under " +
                  std::to_string(kMinDefaultSide) + " px a side: its field spans fewer than " +
                  std::to_string(kMinDefaultSide) + " of the source's pixels); give " + option_text("size") +
                  " WxH, or " + (wider.empty() ? "a wider field" : wider));
    }
  }
  Projection target = make_projection(to, size);
  require_valid_pixels(target, to, "to");
  // Absurd sizes stop here, before any per-tile work: the output alone, at one byte a pixel.
  const Size frame = stereo_frame(size_of(target), stereo.target);
  if (frame.width > kMaxSide || frame.height > kMaxSide)
    throw Error("size: " + std::string(stereo.target == StereoLayout::Mono ? "" : "both eyes' ") +
                size_text(frame) + " (expected at most " + std::to_string(kMaxSide) +
                " pixels a side)");
  require_memory("output " + size_text(frame), image_bytes(frame, 1, 1), o.memory_limit);
  auto correction = SourceCorrection::make(from, to, source, stereo.source);
  return {std::move(source),
          std::move(target),
          rotation_from_ypr(o.yaw, o.pitch, o.roll),
          stereo,
          {},
          std::move(correction)};
}

void require_mono(const ConversionGeometry& g, const char* what) {
  if (g.stereo.any())
    throw Error(std::string(what) + ": stereo= (they are one eye's: give one eye's specs and size without stereo=)");
}

void require_no_correction(const ConversionGeometry& g, const std::string& what,
                           const std::string& instead) {
  if (g.correction)
    throw Error(what +
                ": photometric keys (response, ev, wb, vignetting, flat_field) correct a "
                "source's colours; " +
                instead);
}

Antialias antialias_of(const ConvertOptions& options) {
  // nearest copies source pixels (labels, masks, ids): it never averages them.
  if (options.interp == Interp::Nearest) {
    if (options.antialias && options.antialias->mode != Antialias::Mode::Off)
      throw Error(option_text("antialias", name_of(*options.antialias)) + " with " +
                  option_text("interp", "nearest") + ": nearest copies source pixels and never averages them (give " +
                  option_text("antialias", "off") + ", or another interp)");
    return {Antialias::Mode::Off, 1};
  }
  if (options.antialias) return *options.antialias;
  return {options.engine == Engine::Reference ? Antialias::Mode::Off : Antialias::Mode::Auto, 1};
}

const Image& source_for(const Image& source, const ConvertOptions& options, Image& storage) {
  if (!options.add_alpha || source.alpha_channel() >= 0) return source;
  if (source.channels() > 3)
    throw Error("alpha: the image has " + std::to_string(source.channels()) +
                " channels and none is alpha (give at most 3 channels, or no --alpha)");
  storage = source.with_alpha();
  return storage;
}

int output_channels(int channels, const ConvertOptions& options) {
  return channels + (options.add_alpha && channels < 4 && channels != 2 ? 1 : 0);
}

void require_job_memory(const ConversionGeometry& geometry, int channels, PixelType type,
                        const ConvertOptions& options, uint64_t more, const std::string& more_what) {
  const Size out = geometry.target_frame();
  const int out_channels = output_channels(channels, options);
  require_memory("output " + size_text(out) + " (" + std::to_string(out_channels) + " channels of " + name_of(type) + ")" +
                     (more > 0 ? " with " + more_what : ""),
                 add_bytes(image_bytes(out, out_channels, bytes_of(type)), more), options.memory_limit);
}

Image convert(const Image& source, const ProjectionSpec& from, const ProjectionSpec& to,
              const ConvertOptions& options) {
  const ConversionGeometry geometry = make_geometry(source.size(), from, to, options);
  require_job_memory(geometry, source.channels(), source.type(), options, 0);
  Image storage;
  return Converter(geometry, options).run(source_for(source, options, storage));
}

}  // namespace panoproj
