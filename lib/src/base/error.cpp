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

std::string option_text(std::string_view cli_option, std::string_view value) {
  return python_names ? option_text(cli_option) + "'" + std::string(value) + "'"
                      : option_text(cli_option) + " " + std::string(value);
}

std::string option_number(std::string_view cli_option, std::string_view number) {
  return option_text(cli_option) + (python_names ? "" : " ") + std::string(number);
}

std::string one_line(std::string s) {
  constexpr size_t kMost = 240;
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  if (s.size() > kMost) s = s.substr(0, kMost - 3) + "...";
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
