#include "panoproj/options.hpp"

#include <charconv>

#include "panoproj/error.hpp"

namespace panoproj {

Antialias parse_antialias(std::string_view text) {
  if (text == "off") return {Antialias::Mode::Off, 1};
  if (text == "auto") return {Antialias::Mode::Auto, 1};
  if (text == "mip") return {Antialias::Mode::Mip, 1};
  int n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec == std::errc() && end == text.data() + text.size() && n >= 2 && n <= 16) return {Antialias::Mode::Supersample, n};
  throw Error("antialias '" + std::string(text) + "' is not off, auto, mip or a sub-pixel count from 2 to 16");
}

std::string name_of(const Antialias& a) {
  switch (a.mode) {
    case Antialias::Mode::Off: return "off";
    case Antialias::Mode::Auto: return "auto";
    case Antialias::Mode::Mip: return "mip";
    case Antialias::Mode::Supersample: break;
  }
  return std::to_string(a.n);
}

}  // namespace panoproj
