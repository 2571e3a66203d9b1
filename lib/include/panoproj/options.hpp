#pragma once
// The conversion options, declared once (lib/src/engine/options.cpp): the command adds a flag
// per row to each subcommand that takes it, Python's convert/build_map/Plan take a keyword per
// row (their signatures and docstrings are made from it), and both set ConvertOptions through
// the row's setter. A new option is a ConvertOptions field, a row, and the code that uses it.
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "panoproj/convert.hpp"

namespace panoproj {

// How front ends hand a value over: a number of degrees, an integer, a flag, or text the row's
// setter parses (sizes "WxH", choices, colours, byte counts).
enum class OptionType { Angle, Integer, Flag, Text };
using OptionValue = std::variant<double, int64_t, bool, std::string>;

// Which calls take an option (bits).
enum OptionUse : unsigned { kUseConvert = 1, kUseMaps = 2, kUseAccuracy = 4 };

struct OptionDef {
  const char* name;          // Python's keyword; the command's flag is --name with '-' for '_'
  OptionType type;
  unsigned use;              // OptionUse bits
  const char* default_text;  // the default as Python writes it ("None": derived or unset)
  const char* help;          // one line, for --help and docstrings
  // Stores the value; throws Error naming the option and what it expects. A value of the wrong
  // alternative is an InternalError (the front ends convert by `type`).
  void (*set)(ConvertOptions& options, const OptionValue& value);
};

const std::vector<OptionDef>& conversion_options();
// The row named `name` (Python's spelling); throws Error listing the names `use` allows.
const OptionDef& conversion_option(std::string_view name, unsigned use);
// "--memory-limit" for "memory_limit".
std::string flag_of(const OptionDef& option);
// The command's text of a value option as its type's value ("nan" and "inf" pass as numbers: the
// plan names them); throws Error naming the flag for text that is not one. (Flags have no text.)
OptionValue option_value(const OptionDef& option, const std::string& text);

// "WxH", both positive integers; throws Error naming `what`.
Size parse_size(std::string_view text, std::string_view what = "size");

}  // namespace panoproj
