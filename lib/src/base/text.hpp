#pragma once
// Small text helpers for the parsers of user text (specs, spec files, rigs).
#include <algorithm>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace panoproj {

// s without leading and trailing characters of `space`.
inline std::string trim(std::string_view s, std::string_view space = " \t") {
  const auto b = s.find_first_not_of(space);
  if (b == std::string_view::npos) return {};
  return std::string(s.substr(b, s.find_last_not_of(space) - b + 1));
}

// A number as text: `digits` significant digits (17: it reads back to the same double), -0 as 0.
inline std::string number_text(double v, int digits = 17) {
  char b[40];
  std::snprintf(b, sizeof b, "%.*g", digits, v + 0.0);
  return b;
}

// A value the user gave, as a message quotes it: at most `most` bytes (then "..."), cut between
// UTF-8 characters (Error's message escapes what is not printable).
inline std::string shown(std::string_view s, size_t most = 80) {
  if (s.size() <= most) return std::string(s);
  size_t cut = most - 3;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
  return std::string(s.substr(0, cut)) + "...";
}

// Levenshtein distance, for "did you mean" on a misspelt name.
inline size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The name of `names` nearest `word`: one it begins or that begins it (cubic, bicubic), else
// within `most` edits; "" if none.
inline std::string closest(std::string_view word, const std::vector<std::string>& names,
                           size_t most = 2) {
  std::string best;
  size_t best_distance = most + 1;
  for (const std::string& n : names) {
    const bool part = word.size() >= 3 &&
                      (n.find(word) != std::string::npos || word.find(n) != std::string::npos);
    if (const size_t e = part ? 0 : edit_distance(word, n); e < best_distance)
      best_distance = e, best = n;
  }
  return best;
}

}  // namespace panoproj
