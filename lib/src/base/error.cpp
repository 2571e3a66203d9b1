#include "panoproj/error.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <mutex>
#include <utility>

namespace panoproj {
namespace {
std::atomic<bool> python_names{false};
}  // namespace

void use_python_option_names() { python_names = true; }

std::string option_text(std::string_view cli_option) {
  if (!python_names) return "--" + std::string(cli_option);
  // The keyword arguments of python/panoproj/__init__.py.
  static const std::pair<std::string_view, std::string_view> kPython[] = {
      {"overwrite", "overwrite=True"}, {"from", "src="},        {"to", "dst="},
      {"size", "size="},               {"alpha", "alpha=True"}, {"antialias", "antialias="},
      {"memory-limit", "memory_limit="}};
  for (const auto& [cli, py] : kPython)
    if (cli == cli_option) return std::string(py);
  std::string name(cli_option);
  std::replace(name.begin(), name.end(), '-', '_');
  return name + "=";
}

std::string front_end_text(std::string_view cli, std::string_view python) {
  return std::string(python_names ? python : cli);
}

std::string option_text(std::string_view cli_option, std::string_view value) {
  return python_names ? option_text(cli_option) + "'" + std::string(value) + "'"
                      : option_text(cli_option) + " " + std::string(value);
}

std::string option_number(std::string_view cli_option, std::string_view number) {
  return option_text(cli_option) + (python_names ? "" : " ") + std::string(number);
}

std::string printable(std::string_view text) {
  std::string s;
  s.reserve(text.size());
  const auto byte = [&](size_t i) { return static_cast<unsigned char>(text[i]); };
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = byte(i);
    // The length of a valid UTF-8 sequence starting here (RFC 3629: no overlongs, no surrogates).
    size_t n = c < 0x80                 ? 1
               : c >= 0xC2 && c <= 0xDF ? 2
               : c >= 0xE0 && c <= 0xEF ? 3
               : c >= 0xF0 && c <= 0xF4 ? 4
                                        : 0;
    for (size_t k = 1; k < n; ++k)
      if (i + k >= text.size() || (byte(i + k) & 0xC0) != 0x80) n = 0;
    if (n >= 3) {
      const unsigned char d = byte(i + 1);
      if ((c == 0xE0 && d < 0xA0) || (c == 0xED && d > 0x9F) || (c == 0xF0 && d < 0x90) ||
          (c == 0xF4 && d > 0x8F))
        n = 0;
    }
    if (n == 1 && (c < 0x20 || c == 0x7F) && c != '\n' && c != '\t') n = 0;
    if (n == 0) {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02X", c);
      s += hex;
      ++i;
    } else {
      s.append(text.substr(i, n));
      i += n;
    }
  }
  return s;
}

std::string one_line(std::string s) {
  constexpr size_t kMost = 240;
  s = printable(s);
  for (char& c : s)
    if (c == '\n' || c == '\t') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  if (s.size() > kMost) {
    size_t cut = s.rfind(' ', kMost - 4);
    if (cut == std::string::npos || cut < kMost / 2) cut = kMost - 4;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // whole UTF-8
    s.resize(cut);
    while (!s.empty() && (s.back() == ',' || s.back() == ';' || s.back() == ' ')) s.pop_back();
    s += " ...";
  }
  return s;
}

}  // namespace panoproj

namespace panoproj {
namespace {
std::mutex notice_mutex;
std::function<void(const std::string&)> notice_handler;
}  // namespace

void notice(const std::string& text) {
  std::lock_guard lock(notice_mutex);
  if (notice_handler) notice_handler(text);
  else std::fprintf(stderr, "panoproj: %s\n", text.c_str());
}

void set_notice_handler(std::function<void(const std::string&)> handler) {
  std::lock_guard lock(notice_mutex);
  notice_handler = std::move(handler);
}

}  // namespace panoproj
