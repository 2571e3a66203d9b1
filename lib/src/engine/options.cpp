// The conversion options table (options.hpp).
#include "panoproj/options.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>

#include "base/parallel.hpp"
#include "panoproj/error.hpp"
#include "panoproj/limits.hpp"
#include "sampling/interpolator.hpp"

namespace panoproj {
namespace {

template <class T>
const T& value_as(const OptionValue& v, const char* name) {
  if (const T* p = std::get_if<T>(&v)) return *p;
  throw InternalError(std::string("option ") + name + " was handed a value of another type");
}

std::vector<OptionDef> make_options() {
  constexpr unsigned kAll = kUseConvert | kUseMaps | kUseAccuracy;
  return {
      {"size", OptionType::Text, kAll | kUseViews | kUseStitch, "None",
       "output size WxH, or N for a square: the whole image in every layout but "
       "cubemap:layout=files (there one face); default: the source's resolution at the target's "
       "centre, square pixels",
       [](ConvertOptions& o, const OptionValue& v) {
         o.size = parse_size(value_as<std::string>(v, "size"));
       }},
      {"face_size", OptionType::Integer, kUseConvert | kUseMaps, "None",
       "a cube target's faces, N x N pixels, in any layout (its spec's face=N; instead of size)",
       [](ConvertOptions& o, const OptionValue& v) {
         o.face_size = value_as<int64_t>(v, "face_size");
       }},
      {"yaw", OptionType::Angle, kAll | kUseTiles, "0.0", "degrees, positive looks right",
       [](ConvertOptions& o, const OptionValue& v) { o.yaw = value_as<double>(v, "yaw"); }},
      {"pitch", OptionType::Angle, kAll | kUseTiles, "0.0", "degrees, positive looks up",
       [](ConvertOptions& o, const OptionValue& v) { o.pitch = value_as<double>(v, "pitch"); }},
      {"roll", OptionType::Angle, kAll | kUseTiles, "0.0",
       "degrees, positive turns the view clockwise",
       [](ConvertOptions& o, const OptionValue& v) { o.roll = value_as<double>(v, "roll"); }},
      {"interp", OptionType::Text, kUseConvert | kUseTiles | kUseViews, "'bicubic'",
       "nearest|bilinear|bicubic|lanczos3|bicubic-dering|lanczos3-dering (default bicubic; "
       "-dering: no ringing)",
       [](ConvertOptions& o, const OptionValue& v) {
         o.interp = parse_interp(value_as<std::string>(v, "interp"));
       },
       "nearest|bilinear|bicubic|lanczos3|bicubic-dering|lanczos3-dering"},
      {"threads", OptionType::Integer, kAll | kUseTiles | kUseViews | kUseStitch, "0",
       "worker threads (default 0: all cores)",
       [](ConvertOptions& o, const OptionValue& v) {
         const int64_t n = value_as<int64_t>(v, "threads");
         check_threads(n);
         o.threads = static_cast<int>(n);
       }},
      {"engine", OptionType::Text, kUseConvert | kUseTiles | kUseViews | kUseStitch, "'simd'",
       "simd (default) | scalar (same tiles, no SIMD) | reference (exact, slow)",
       [](ConvertOptions& o, const OptionValue& v) {
         o.engine = parse_engine(value_as<std::string>(v, "engine"));
       },
       "simd|scalar|reference"},
      {"antialias", OptionType::Text, kUseConvert | kUseTiles | kUseViews | kUseStitch, "None",
       "auto (default: where the output shrinks the source, each pixel the area-weighted mean of "
       "the source pixels "
       "under its footprint) | off | mip (mip levels) | N (N x N sub-pixels, 2..16); the reference "
       "engine has none",
       [](ConvertOptions& o, const OptionValue& v) {
         o.antialias = parse_antialias(value_as<std::string>(v, "antialias"));
       },
       "auto|off|mip"},
      {"alpha", OptionType::Flag, kUseConvert, "False",
       "output alpha: 0 where there is no source, the covered share of each pixel on the field's "
       "edge (antialiased "
       "edges; a source without alpha gets an opaque one)",
       [](ConvertOptions& o, const OptionValue& v) {
         o.add_alpha = value_as<bool>(v, "alpha");
         o.edges.soft = o.edges.soft || o.add_alpha;
       }},
      {"fill", OptionType::Text, kUseConvert, "None",
       "colour where there is no source, blended into the field's antialiased edge: R,G,B[,A] in "
       "unit range (1,1,1 "
       "is white) or #rrggbb[aa] (default: 0, or alpha 0)",
       [](ConvertOptions& o, const OptionValue& v) {
         o.edges.colour = parse_fill_colour(value_as<std::string>(v, "fill"));
         o.edges.soft = true;
       }},
      {"decode_scale", OptionType::Text, kUseFiles | kUseTiles | kUseViews, "'auto'",
       "auto (default: a JPEG source that the view samples at under half its resolution everywhere "
       "decodes at 1/2, "
       "1/4 or 1/8 by DCT scaling, still twice the detail the output holds) | 1 | 2 | 4 | 8",
       [](ConvertOptions& o, const OptionValue& v) {
         const std::string t = value_as<std::string>(v, "decode_scale");
         if (t == "auto")
           o.decode_scale = 0;
         else if (t == "1" || t == "2" || t == "4" || t == "8")
           o.decode_scale = t[0] - '0';
         else
           throw Error(option_text("decode-scale") + " " + t + " (expected auto, 1, 2, 4 or 8)");
       },
       "auto|1|2|4|8"},
      {"memory_limit", OptionType::Text, kAll | kUseTiles | kUseViews | kUseStitch, "None",
       "bytes a job may allocate, e.g. 4G or 512M (default: 3/4 of the memory available now, at "
       "least 1 GiB left free); larger jobs "
       "are refused "
       "before any work",
       [](ConvertOptions& o, const OptionValue& v) {
         o.memory_limit = parse_memory_limit(value_as<std::string>(v, "memory_limit"));
       }},
  };
}

}  // namespace

const std::vector<OptionDef>& conversion_options() {
  static const std::vector<OptionDef> options = make_options();
  return options;
}

const OptionDef& conversion_option(std::string_view name, unsigned use) {
  std::string names;
  for (const OptionDef& d : conversion_options()) {
    if (!(d.use & use)) continue;
    if (name == d.name) return d;
    names += (names.empty() ? "" : ", ") + std::string(d.name);
  }
  throw Error("unknown option '" + std::string(name) + "' (expected one of: " + names + ")");
}

std::string flag_of(const OptionDef& option) {
  if (option.flag)
    return option.flag[0] == '-' || (option.traits & kPositional) ? option.flag
                                                                  : std::string("--") + option.flag;
  if (option.traits & kPositional) return option.name;
  std::string flag = std::string("--") + option.name;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

OptionValue option_value(const OptionDef& option, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  switch (option.type) {
    case OptionType::Angle: {
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size())
        throw Error(flag_of(option) + ": " + text + " is not a number (expected degrees)");
      return v;
    }
    case OptionType::Integer: {
      const long long v = std::strtoll(text.c_str(), &end, 10);
      if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE)
        throw Error(flag_of(option) + ": " + text + " is not a 64-bit integer");
      return static_cast<int64_t>(v);
    }
    case OptionType::Text:
    case OptionType::Path:
      return text;
    case OptionType::Paths:
      return std::vector<std::string>{text};
    case OptionType::Flag:
      break;
  }
  throw InternalError(flag_of(option) + " is a flag: it has no text to parse");
}

Size parse_size(std::string_view text, std::string_view what) {
  const std::string t(text);
  // "WxH" (either x), or "N" for a square.
  const auto x = t.find_first_of("xX");
  auto whole = [](const std::string& part, long long& v) {
    size_t used = 0;
    try {
      v = std::stoll(part, &used);
    } catch (const std::exception&) {
      return false;
    }
    return used == part.size() && !part.empty() &&
           std::isdigit(static_cast<unsigned char>(part[0]));
  };
  long long w = 0, h = 0;
  const bool ok = x == std::string::npos ? whole(t, w) && (h = w, true)
                                         : whole(t.substr(0, x), w) && whole(t.substr(x + 1), h);
  if (ok && w > 0 && h > 0) return {w, h};
  throw Error(std::string(what) + ": " + t.substr(0, 60) +
              " (expected WxH with positive integers, e.g. 2048x1024, or N for a square)");
}

}  // namespace panoproj
