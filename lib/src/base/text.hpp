#pragma once
// Small text helpers for the parsers of user text (specs, spec files, rigs).
#include <string>
#include <string_view>

namespace panoproj {

// s without leading and trailing characters of `space`.
inline std::string trim(std::string_view s, std::string_view space = " \t") {
  const auto b = s.find_first_not_of(space);
  if (b == std::string_view::npos) return {};
  return std::string(s.substr(b, s.find_last_not_of(space) - b + 1));
}

}  // namespace panoproj
