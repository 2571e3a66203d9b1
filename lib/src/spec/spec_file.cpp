// Specs from files: a flat JSON object or a flat YAML mapping whose "projection" names the form
// and whose other keys are its spec keys (a lens calibration kept beside the photos), turned into
// spec text for parse_spec.
#include "panoproj/spec.hpp"

#include <cctype>
#include <sstream>
#include <utility>
#include <vector>

#include "panoproj/error.hpp"
#include "base/input_check.hpp"
#include "base/text.hpp"

namespace panoproj {
namespace {

using Pairs = std::vector<std::pair<std::string, std::string>>;

constexpr std::string_view kSpace = " \t\r\n";

// {"key": value, ...} with string or number values; nothing nested.
Pairs parse_json(const std::string& text, const std::string& path) {
  Pairs out;
  size_t i = 0;
  auto fail = [&](const std::string& what) -> void {
    throw Error(path + ": " + what + " at character " + std::to_string(i + 1) +
                " (expected a flat JSON object of spec keys, e.g. {\"projection\": \"kannala-brandt\", \"fx\": 620.5})");
  };
  auto skip = [&] {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  };
  auto string = [&] {
    std::string s;
    if (text[i] != '"') fail("a string must start with \"");
    for (++i; i < text.size() && text[i] != '"'; ++i) {
      if (text[i] == '\\' && i + 1 < text.size()) ++i;
      s += text[i];
    }
    if (i >= text.size()) fail("an unterminated string");
    ++i;
    return s;
  };
  skip();
  if (i >= text.size() || text[i] != '{') fail("no object");
  ++i;
  skip();
  if (i < text.size() && text[i] == '}') return out;
  while (true) {
    skip();
    const std::string key = string();
    skip();
    if (i >= text.size() || text[i] != ':') fail("no ':' after \"" + key + "\"");
    ++i;
    skip();
    std::string value;
    if (i < text.size() && text[i] == '"') {
      value = string();
    } else {
      const size_t start = i;
      while (i < text.size() && text[i] != ',' && text[i] != '}' && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
      value = text.substr(start, i - start);
      if (value.empty() || value[0] == '{' || value[0] == '[') fail("the value of \"" + key + "\" is not a string or number");
    }
    out.emplace_back(key, value);
    skip();
    if (i < text.size() && text[i] == ',') {
      ++i;
      continue;
    }
    if (i < text.size() && text[i] == '}') {
      ++i;
      skip();
      if (i != text.size()) fail("text after the object");
      return out;
    }
    fail("no ',' or '}'");
  }
}

// key: value lines; '#' comments, blank lines and a leading "---" are skipped.
Pairs parse_yaml(const std::string& text, const std::string& path) {
  Pairs out;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    line = trim(line, kSpace);
    if (line.empty() || line == "---") continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos || line[0] == '-' || line[0] == ' ')
      throw Error(path + ": line " + std::to_string(n) + " is not 'key: value' (expected a flat YAML mapping of spec keys)");
    std::string value = trim(line.substr(colon + 1), kSpace);
    if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') && value.back() == value.front())
      value = value.substr(1, value.size() - 2);
    if (value.empty()) throw Error(path + ": line " + std::to_string(n) + " has no value (nested mappings are not supported)");
    out.emplace_back(trim(line.substr(0, colon), kSpace), value);
  }
  return out;
}

}  // namespace

std::string spec_from_file(const std::string& path) {
  // A spec file is a few lines: at most 1 MiB is read; read_head refuses directories, FIFOs and
  // devices before reading.
  constexpr size_t kMax = size_t{1} << 20;
  std::string text = read_head(path, kMax + 1, "the spec file", "a JSON or YAML file after @");
  if (text.size() > kMax) throw Error(path + " is over 1 MiB (expected a small JSON or YAML spec file)");
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // a UTF-8 byte order mark
  const std::string head = trim(text, kSpace);
  const Pairs pairs = !head.empty() && head[0] == '{' ? parse_json(head, path) : parse_yaml(text, path);
  std::string name, keys;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const auto& [k, v] = pairs[i];
    for (size_t j = 0; j < i; ++j)
      if (pairs[j].first == k)
        throw Error(path + ": the key \"" + k + "\" is given twice (expected each key once)");
    if (k == "projection") {
      name = v;
    } else {
      if (v.find_first_of(",:") != std::string::npos)
        throw Error(path + ": the value of " + k + " holds ',' or ':' (expected a number or a word)");
      keys += "," + k + "=" + v;
    }
  }
  if (name.empty()) throw Error(path + ": no \"projection\" key (expected one naming the form, e.g. kannala-brandt)");
  // The name may carry keys of its own ("fisheye:fov=200").
  if (!keys.empty() && name.find(':') == std::string::npos) keys[0] = ':';
  return name + keys;
}

}  // namespace panoproj
