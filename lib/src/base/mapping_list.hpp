#pragma once
// A list of flat mappings (key: scalar), the shape of the rig files (views' rigs, stitch's lens
// rigs): YAML in block or flow style ("- key: value" lines, or "- {key: value, ...}"), optionally
// under one top key ("views:"), or JSON (an array of flat objects, optionally the value of that
// one key of an object). Quotes around keys and values are taken off; '#' starts a YAML comment
// outside quotes. Errors name the text (`label`) and the line.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace panoproj {

struct Mapping {
  int line = 0;                                              // where its item starts
  std::vector<std::pair<std::string, std::string>> entries;  // in order, each key once
  std::vector<int> lines;                                    // each entry's line
};

// What the list holds, for errors: noun "view" / "lens", plural "views" / "lenses", top key
// "views", an example item ("{name: front, yaw: 0, hfov: 90}").
struct ListWords {
  const char* noun;
  const char* plural;
  const char* top;
  const char* example;
};

// Throws Error: a NUL byte, tabs, malformed lines, a key twice in one item, more than `most`
// items, none at all.
std::vector<Mapping> parse_mapping_list(const std::string& text, const std::string& label,
                                        const ListWords& words, size_t most);

}  // namespace panoproj
