#pragma once
// The exception the library throws at its edges (spec parsing, factories, I/O) for what the user
// gave: one line, "what: value (expected ...)". Kernels never throw. A broken invariant (a bug,
// not a user's mistake) throws InternalError instead.
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace panoproj {

// What went wrong, for front ends that map it (Python: ValueError, OSError, FileExistsError,
// FileNotFoundError, MemoryError).
enum class ErrorKind { Value, File, Exists, Missing, Memory };

// `text` with each byte that is not part of valid UTF-8, and each control character but a
// newline or a tab, written \xNN.
std::string printable(std::string_view text);

// The message is kept printable: bytes that are not UTF-8 and control characters other than a
// newline or a tab (a hostile file's name or text quoted back) become \xNN.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, ErrorKind kind = ErrorKind::Value)
      : std::runtime_error(printable(message)), kind_(kind) {}
  ErrorKind kind() const { return kind_; }

 private:
  ErrorKind kind_;
};

// A broken invariant of the library: a bug to report, never the user's input. Not an Error, so
// front ends show it as what it is (the command: "internal error ... please report"; Python:
// RuntimeError).
class InternalError : public std::logic_error {
 public:
  explicit InternalError(const std::string& what) : std::logic_error("internal error: " + what) {}
};

// An option as the user writes it in messages: "--overwrite" on the command line (default),
// "overwrite=True" once the Python module called use_python_option_names().
std::string option_text(std::string_view cli_option);
// An option with a text value: "--interp nearest", or "interp='nearest'" in Python.
std::string option_text(std::string_view cli_option, std::string_view value);
// An option with a number: "--crf 99", or "crf=99" in Python.
std::string option_number(std::string_view cli_option, std::string_view number);
void use_python_option_names();
// Where a front end lists something: `cli` on the command line, `python` in the Python module
// ("panoproj info" / "panoproj.projections()").
std::string front_end_text(std::string_view cli, std::string_view python);

// Something the user should know that is not an error (a stale temporary removed): "panoproj:
// <text>" on stderr, or given to the handler set (the command's, whose stderr is held during a job).
void notice(const std::string& text);
void set_notice_handler(std::function<void(const std::string&)> handler);

// A library's message as one line of at most 240 characters (newlines folded, the rest cut at a
// word).
std::string one_line(std::string text);

}  // namespace panoproj
