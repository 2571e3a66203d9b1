#pragma once
// Projection specs: "name[:key=value[,key=value...]]", angles in degrees, sizes in pixels.
// One table (projection_catalog, gathered from each projection's module) defines every name, key,
// default and range; the parser, the factories, `panoproj info`, Python's classes and the docs
// all read it.
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "panoproj/projections/list.hpp"

namespace panoproj {

// The projection type a spec makes (one per line of projections/list.hpp, in its order).
#define PANOPROJ_KIND_(Type) Type,
enum class Kind { PANOPROJ_PROJECTIONS(PANOPROJ_KIND_) };
#undef PANOPROJ_KIND_

enum class ParamType { Number, Integer, Choice, Text };  // Text: checked by its module

struct ParamDef {
  const char* key;
  ParamType type;
  const char* default_text;  // "" when the default is derived (from the size or other keys)
  double lo, hi;             // numeric range
  bool lo_open, hi_open;     // exclusive bounds
  const char* choices;       // "a|b|c" for Choice
  const char* help;
};

struct ProjectionDef {
  const char* name;
  const char* summary;
  std::vector<ParamDef> params;
  Kind kind{};  // set by projection_catalog from the module that declares the entry
};

const std::vector<ProjectionDef>& projection_catalog();
// A key's range as messages give it: "0 < fov <= 360", "one of a|b".
std::string range_text(const ParamDef& p);
const ProjectionDef& projection_def(Kind kind, std::string_view name);

class ProjectionSpec {
 public:
  ProjectionSpec(const ProjectionDef& def, std::map<std::string, std::string> values);

  Kind kind() const { return def_->kind; }
  const std::string& name() const { return name_; }
  const ProjectionDef& def() const { return *def_; }
  bool given(std::string_view key) const { return values_.count(std::string(key)) > 0; }
  // The given value, else the table default, else nullopt (a derived default).
  std::optional<double> number(std::string_view key) const;
  std::string choice(std::string_view key) const;  // a Choice or Text key
  // A Text key's numbers "a/b/c": least..most finite numbers, else Error naming the key and
  // `expected`.
  std::vector<double> numbers(std::string_view key, size_t least, size_t most,
                              const char* expected) const;
  // Canonical text: name and the given keys in table order.
  std::string str() const;

 private:
  const ProjectionDef* def_;
  std::string name_;
  std::map<std::string, std::string> values_;
};

// Throws panoproj::Error naming the bad part and what was expected. "@path" reads the spec from a
// file (spec_from_file).
ProjectionSpec parse_spec(std::string_view text);

// The spec text of a file holding a flat JSON object or a flat YAML mapping: "projection" names
// the form, the other keys are its spec keys (e.g. a lens calibration: {"projection":
// "kannala-brandt", "fx": 620.5, "k1": 0.036, ...}). Throws panoproj::Error naming the file and
// what was wrong.
std::string spec_from_file(const std::string& path);

}  // namespace panoproj
