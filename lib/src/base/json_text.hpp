#pragma once
// JSON text for the files the jobs write (configs, transforms.json).
#include <cstdio>
#include <string>
#include <string_view>

namespace panoproj {

// A JSON string literal: quotes, backslashes and control characters escaped (RFC 8259, 7).
inline std::string json_string(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned>(c));
      out += b;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace panoproj
