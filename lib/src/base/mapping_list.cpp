// A list of flat mappings from YAML or JSON text (mapping_list.hpp).
#include "base/mapping_list.hpp"

#include <algorithm>
#include <cctype>

#include "base/text.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

std::string unquoted(std::string s) {
  if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front())
    s = s.substr(1, s.size() - 2);
  return s;
}

// The text before a '#' that is outside quotes.
std::string without_comment(const std::string& line) {
  char quote = 0;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#') {
      return line.substr(0, i);
    }
  }
  return line;
}

// Splits at the commas outside quotes.
std::vector<std::string> split_outside_quotes(const std::string& s) {
  std::vector<std::string> parts(1);
  char quote = 0;
  for (const char c : s) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == ',') {
      parts.emplace_back();
      continue;
    }
    parts.back() += c;
  }
  return parts;
}

void add_entry(Mapping& m, const std::string& key, const std::string& value, int line,
               const std::string& where, const ListWords& words) {
  const std::string k = unquoted(trim(key));
  for (const auto& e : m.entries)
    if (e.first == k) throw Error(where + "'" + shown(k) + "' given twice in one " + words.noun);
  m.entries.emplace_back(k, unquoted(trim(value)));
  m.lines.push_back(line);
}

std::vector<Mapping> parse_yaml(const std::string& text, const std::string& label,
                                const ListWords& words, size_t most) {
  std::vector<Mapping> items;
  bool top = false;
  const std::string top_line = std::string(words.top) + ":";
  size_t at = 0;
  int line_no = 0;
  while (at < text.size()) {
    const size_t nl = std::min(text.find('\n', at), text.size());
    std::string line = text.substr(at, nl - at);
    at = nl + 1;
    ++line_no;
    const std::string where = label + " line " + std::to_string(line_no) + ": ";
    if (line.find('\t') != std::string::npos)
      throw Error(where + "a tab (YAML indents with spaces)");
    std::string s = trim(without_comment(line), " \r");
    if (s.empty() || s == "---") continue;
    if (s == top_line && items.empty() && !top) {
      top = true;
      continue;
    }
    if (s == "-" || s.rfind("- ", 0) == 0) {
      if (items.size() == most)
        throw Error(where + "more than " + std::to_string(most) + " " + words.plural);
      items.emplace_back();
      items.back().line = line_no;
      s = trim(s.substr(1));
      if (s.empty()) continue;
      if (s.front() == '{') {
        if (s.back() != '}')
          throw Error(where + "'" + shown(s) + "' (a flow mapping ends with '}' on its line)");
        for (const std::string& kv : split_outside_quotes(s.substr(1, s.size() - 2))) {
          if (trim(kv).empty()) continue;
          const size_t colon = kv.find(':');
          if (colon == std::string::npos)
            throw Error(where + "'" + shown(trim(kv)) + "' (expected key: value)");
          add_entry(items.back(), kv.substr(0, colon), kv.substr(colon + 1), line_no, where, words);
        }
        continue;
      }
    } else if (items.empty()) {
      throw Error(where + "'" + shown(s) + "' (expected a list of " + words.plural +
                  ": lines starting '- ', optionally under '" + top_line + "')");
    }
    const size_t colon = s.find(':');
    if (colon == std::string::npos) throw Error(where + "'" + shown(s) + "' (expected key: value)");
    add_entry(items.back(), s.substr(0, colon), s.substr(colon + 1), line_no, where, words);
  }
  return items;
}

// [{"key": value, ...}, ...] or {"<top>": [...]}: string, number, true, false values.
class JsonList {
 public:
  JsonList(const std::string& text, const std::string& label, const ListWords& words, size_t most)
      : t_(text), label_(label), words_(words), most_(most) {}

  std::vector<Mapping> parse() {
    skip();
    std::vector<Mapping> items;
    if (peek() == '{') {
      ++i_;
      skip();
      const std::string key = string();
      if (key != words_.top)
        fail("'" + key + "' (expected the key \"" + std::string(words_.top) + "\")");
      expect(':');
      items = array();
      expect('}');
    } else {
      items = array();
    }
    skip();
    if (i_ != t_.size()) fail("text after the list");
    return items;
  }

 private:
  const std::string& t_;
  const std::string& label_;
  const ListWords& words_;
  size_t most_;
  size_t i_ = 0;

  int line() const { return 1 + static_cast<int>(std::count(t_.begin(), t_.begin() + i_, '\n')); }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(label_ + " line " + std::to_string(line()) + ": " + what +
                " (expected JSON: a list of " + words_.plural + ", e.g. [" + words_.example + "])");
  }
  char peek() const { return i_ < t_.size() ? t_[i_] : '\0'; }
  void skip() {
    while (i_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[i_]))) ++i_;
  }
  void expect(char c) {
    skip();
    if (peek() != c) fail(std::string("no '") + c + "'");
    ++i_;
    skip();
  }
  std::string string() {
    if (peek() != '"') fail("a string must start with \"");
    std::string s;
    for (++i_; i_ < t_.size() && t_[i_] != '"'; ++i_) {
      if (t_[i_] == '\\' && i_ + 1 < t_.size()) ++i_;
      s += t_[i_];
    }
    if (i_ >= t_.size()) fail("an unterminated string");
    ++i_;
    return s;
  }
  std::vector<Mapping> array() {
    expect('[');
    std::vector<Mapping> items;
    if (peek() == ']') {
      ++i_;
      return items;
    }
    while (true) {
      if (items.size() == most_) fail("more than " + std::to_string(most_) + " " + words_.plural);
      items.push_back(object());
      skip();
      if (peek() == ',') {
        ++i_;
        skip();
        continue;
      }
      expect(']');
      return items;
    }
  }
  Mapping object() {
    Mapping m;
    m.line = line();
    if (peek() != '{') fail("no '{' (each " + std::string(words_.noun) + " is an object)");
    ++i_;
    skip();
    if (peek() == '}') {
      ++i_;
      return m;
    }
    while (true) {
      skip();
      const int at = line();
      const std::string key = string();
      expect(':');
      std::string value;
      if (peek() == '"') {
        value = string();
      } else {
        const size_t start = i_;
        while (i_ < t_.size() && t_[i_] != ',' && t_[i_] != '}' &&
               !std::isspace(static_cast<unsigned char>(t_[i_])))
          ++i_;
        value = t_.substr(start, i_ - start);
        if (value.empty() || value[0] == '{' || value[0] == '[')
          fail("the value of \"" + key + "\" is not a string or number (nothing nested)");
      }
      add_entry(m, key, value, at, label_ + " line " + std::to_string(at) + ": ", words_);
      skip();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      expect('}');
      return m;
    }
  }
};

}  // namespace

std::vector<Mapping> parse_mapping_list(const std::string& text, const std::string& label,
                                        const ListWords& words, size_t most) {
  if (const size_t nul = text.find('\0'); nul != std::string::npos)
    throw Error(label + " line " +
                std::to_string(1 + std::count(text.begin(), text.begin() + nul, '\n')) +
                ": a NUL byte (expected YAML text)");
  std::string body = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? text.substr(3) : text;
  const std::string head = trim(body, " \t\r\n");
  const bool json = !head.empty() && (head[0] == '[' || head[0] == '{');
  std::vector<Mapping> items =
      json ? JsonList(body, label, words, most).parse() : parse_yaml(body, label, words, most);
  if (items.empty())
    throw Error(label + ": no " + words.plural + " (expected a list: - " + words.example + ")");
  return items;
}

}  // namespace panoproj
