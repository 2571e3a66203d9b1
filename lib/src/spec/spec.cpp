// The projection catalogue (gathered from the modules) and the spec-string parser.
#include "panoproj/spec.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "base/text.hpp"
#include "panoproj/error.hpp"
#include "projections/module.hpp"
#include "spec/photometric_keys.hpp"

namespace panoproj {
namespace {

// Names other tools use for a catalogue entry (py360convert, Hugin, FFmpeg's v360, cartography).
constexpr std::pair<std::string_view, std::string_view> kOtherNames[] = {
    {"perspective", "pinhole"},       {"rectilinear", "pinhole"},         {"gnomonic", "pinhole"},
    {"flat", "pinhole"},              {"equirectangular", "equirect"},    {"erp", "equirect"},
    {"latlong", "equirect"},          {"spherical", "equirect"},          {"plate-carree", "equirect"},
    {"cube", "cubemap"},              {"dice", "cubemap:layout=cross"},   {"cross", "cubemap:layout=cross"},
    {"horizon", "cubemap:layout=6x1"}, {"c6x1", "cubemap:layout=6x1"},    {"c3x2", "cubemap:layout=3x2"},
    {"skybox", "cubemap"},            {"dfisheye", "dual-fisheye"},       {"fish-eye", "fisheye"},
    {"equidistant", "fisheye"},       {"ball", "fisheye"},                {"hammer-aitoff", "hammer"},
    {"cylinder", "cylindrical"},      {"brown", "brown-conrady"},         {"opencv-fisheye", "kannala-brandt"},
};

// "did you mean X? " for another tool's name, a catalogue name within two edits, or one that
// begins the text (equirectangle); else "".
std::string did_you_mean(const std::string& name) {
  std::string lower = name;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::replace(lower.begin(), lower.end(), '_', '-');
  for (const auto& [other, ours] : kOtherNames)
    if (lower == other) return "did you mean " + std::string(ours) + "? ";
  std::string best;
  size_t best_distance = 3;
  for (const auto& d : projection_catalog())
    if (const size_t e = lower.rfind(d.name, 0) == 0 ? 0 : edit_distance(lower, d.name); e < best_distance)
      best_distance = e, best = d.name;
  return best.empty() ? "" : "did you mean " + best + "? ";
}

std::string list_names() {
  std::string s;
  for (const auto& d : projection_catalog()) s += (s.empty() ? "" : ", ") + std::string(d.name);
  return s;
}

// Checks one value against its definition; returns the canonical text.
std::string validate(const ProjectionDef& d, const ParamDef& p, const std::string& text) {
  const std::string where = std::string(d.name) + ": " + p.key + "=" + text;
  if (p.type == ParamType::Choice) {
    std::string choices = std::string("|") + p.choices + "|";
    if (text.empty() || text.find('|') != std::string::npos ||
        choices.find("|" + text + "|") == std::string::npos)
      throw Error(where + " is not a valid value (expected " + range_text(p) + ")");
    return text;
  }
  // Text: its module's check reads it; here only what no value may hold.
  if (p.type == ParamType::Text) {
    if (text.size() > 1024)
      throw Error(std::string(d.name) + ": " + p.key + "= is " + std::to_string(text.size()) +
                  " characters long (expected up to 1024)");
    if (text.empty() || text.find_first_of("|\"") != std::string::npos)
      throw Error(where + " is not a valid value (expected up to 1024 characters, no '|' or '\"')");
    return text;
  }
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size())
    throw Error(where + " is not a number (expected " + range_text(p) + ")");
  if (!std::isfinite(v)) throw Error(where + " is not finite (expected " + range_text(p) + ")");
  if (p.type == ParamType::Integer && v != std::floor(v))
    throw Error(where + " is not a whole number (expected " + range_text(p) + ")");
  const bool lo_ok = p.lo_open ? v > p.lo : v >= p.lo;
  const bool hi_ok = p.hi_open ? v < p.hi : v <= p.hi;
  if (!lo_ok || !hi_ok) throw Error(where + " is out of range (expected " + range_text(p) + ")");
  return text;
}

}  // namespace

std::string range_text(const ParamDef& p) {
  std::ostringstream o;
  if (p.type == ParamType::Choice) return std::string("one of ") + p.choices;
  if (p.type == ParamType::Text) return "text";
  if (std::isfinite(p.lo)) o << p.lo << (p.lo_open ? " < " : " <= ");
  o << p.key;
  if (std::isfinite(p.hi)) o << (p.hi_open ? " < " : " <= ") << p.hi;
  if (!std::isfinite(p.lo) && !std::isfinite(p.hi)) o << " finite";
  return o.str();
}

const std::vector<ProjectionDef>& projection_catalog() {
  static const std::vector<ProjectionDef> catalog = [] {
    std::vector<ProjectionDef> all;
    for (size_t k = 0; k < std::variant_size_v<Projection>; ++k)
      for (ProjectionDef d : module_of(static_cast<Kind>(k)).catalog()) {
        d.kind = static_cast<Kind>(k);
        // Every form as a stereo frame (convert.hpp: Stereo).
        d.params.push_back({"stereo", ParamType::Choice, "mono", 0, 0, false, false, "mono|tb|sbs",
                            "two eyes in one image: tb top (left eye) and bottom, sbs left and right; each eye "
                            "converts within its half"});
        d.params.push_back({"eye", ParamType::Choice, "left", 0, 0, false, false, "left|right",
                            "a stereo source's eye a mono target takes"});
        // Every form's photometry; a two-lens frame's per lens.
        for (ParamDef& p :
             photometric_key_defs(d.kind == Kind::DualFisheye || d.kind == Kind::GoProMax))
          d.params.push_back(p);
        all.push_back(std::move(d));
      }
    return all;
  }();
  return catalog;
}

const ProjectionDef& projection_def(Kind kind, std::string_view name) {
  for (const auto& d : projection_catalog())
    if (d.kind == kind && (name.empty() || name == d.name)) return d;
  throw Error("unknown projection: " + std::string(name));
}

ProjectionSpec::ProjectionSpec(const ProjectionDef& def, std::map<std::string, std::string> values)
    : def_(&def), name_(def.name), values_(std::move(values)) {}

std::optional<double> ProjectionSpec::number(std::string_view key) const {
  for (const auto& p : def_->params) {
    if (key != p.key) continue;
    auto it = values_.find(std::string(key));
    const std::string text = it != values_.end() ? it->second : p.default_text;
    if (text.empty()) return std::nullopt;
    return std::strtod(text.c_str(), nullptr);
  }
  throw InternalError(std::string(def_->name) + " has no key " + std::string(key));
}

std::vector<double> ProjectionSpec::numbers(std::string_view key, size_t least, size_t most,
                                            const char* expected) const {
  const std::string value = choice(key);
  std::vector<double> out;
  size_t at = 0;
  while (true) {
    const size_t slash = value.find('/', at);
    const std::string item = value.substr(at, slash - at);
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(v))
      throw Error(name_ + ": " + std::string(key) + "=" + value + " (expected " + expected + ")");
    out.push_back(v);
    if (slash == std::string::npos) break;
    at = slash + 1;
  }
  if (out.size() < least || out.size() > most)
    throw Error(name_ + ": " + std::string(key) + "=" + value + " has " +
                std::to_string(out.size()) + " numbers (expected " + expected + ")");
  return out;
}

std::string ProjectionSpec::choice(std::string_view key) const {
  for (const auto& p : def_->params) {
    if (key != p.key) continue;
    auto it = values_.find(std::string(key));
    return it != values_.end() ? it->second : p.default_text;
  }
  throw InternalError(std::string(def_->name) + " has no key " + std::string(key));
}

std::string ProjectionSpec::str() const {
  std::string s = name_;
  char sep = ':';
  for (const auto& p : def_->params) {
    auto it = values_.find(p.key);
    if (it == values_.end()) continue;
    s += sep + std::string(p.key) + "=" + it->second;
    sep = ',';
  }
  return s;
}

ProjectionSpec parse_spec(std::string_view text) {
  if (const std::string t = trim(text); !t.empty() && t[0] == '@') {
    const std::string from_file = spec_from_file(t.substr(1));
    if (!from_file.empty() && from_file[0] == '@') throw Error(t + ": a spec file cannot name another");
    return parse_spec(from_file);
  }
  const auto colon = text.find(':');
  const std::string name = trim(text.substr(0, colon));
  const ProjectionDef* def = nullptr;
  for (const auto& d : projection_catalog())
    if (name == d.name) def = &d;
  if (!def)
    throw Error("unknown projection '" + shown(name) + "' (" + did_you_mean(name) +
                "expected one of the " + std::to_string(projection_catalog().size()) + " that " +
                front_end_text("panoproj info", "panoproj.projections()") +
                " lists: " + list_names() + ")");

  std::map<std::string, std::string> values;
  if (colon != std::string_view::npos) {
    std::string_view rest = text.substr(colon + 1);
    while (true) {
      const auto comma = rest.find(',');
      const std::string item = trim(rest.substr(0, comma));
      const auto eq = item.find('=');
      if (eq == std::string::npos)
        throw Error(std::string(def->name) + ": '" + item + "' is not key=value");
      const std::string key = trim(item.substr(0, eq)), value = trim(item.substr(eq + 1));
      const ParamDef* p = nullptr;
      for (const auto& q : def->params)
        if (key == q.key) p = &q;
      if (!p) {
        std::string keys;
        std::vector<std::string> names;
        for (const auto& q : def->params) {
          keys += (keys.empty() ? "" : ", ") + std::string(q.key);
          names.emplace_back(q.key);
        }
        const std::string near =
            key.size() > 2 ? closest(key, names) : "";  // (a letter or two: any key is near)
        throw Error(std::string(def->name) + ": unknown key '" + shown(key) + "' (" +
                    (near.empty() ? "" : "did you mean " + near + "? ") +
                    "expected one of: " + (keys.empty() ? "none" : keys) + ")");
      }
      if (values.count(key)) throw Error(std::string(def->name) + ": " + key + " given twice");
      values[key] = validate(*def, *p, value);
      if (comma == std::string_view::npos) break;
      rest = rest.substr(comma + 1);
    }
  }
  return ProjectionSpec(*def, std::move(values));
}

}  // namespace panoproj
