#pragma once
// Jobs: what the command's subcommands and Python's folder functions run (convert, maps, tiles,
// views, accuracy, stability, info; the list: lib/src/jobs/list.hpp). A job is a module: its
// name, its parameter rows (OptionDef, options.hpp: the conversion options' row type), a run,
// and for jobs that a scheduler may share out, staged parts. The front ends are made from the
// rows: the command adds a flag (or positional) per row, python/generate_api.py writes Python's
// function, signature, TypedDict and stub; both hand the given values over as Arguments.
//
// Staged jobs (tiles, views) run in parts for a scheduler (Python's client=): begin checks
// everything, creates the temporary folder beside the output and says how many parts there are;
// render writes the given parts into it (any process, any order: each file's bytes depend only on
// the arguments); finish writes the rest and lands the folder; abandon_staged removes it. A local
// run gives the same bytes.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "panoproj/io.hpp"
#include "panoproj/options.hpp"

namespace panoproj {

// Largest map the file jobs and Python's Plan keep in memory (about 30 Mpx of output).
inline constexpr int64_t kMapCacheBudget = int64_t{512} << 20;

// The values given for a job's rows, by row name, in the order given. set() checks the name
// against the rows and the value's alternative against the row's type; the getters return the
// given value, else the row's default (std::nullopt / empty for a default of None).
class Arguments {
 public:
  explicit Arguments(const std::vector<OptionDef>& rows) : rows_(&rows) {}
  Arguments& set(std::string_view name, OptionValue value);  // throws Error naming an unknown row
  std::string text(std::string_view name) const;
  std::optional<std::string> optional_text(std::string_view name) const;
  int64_t integer(std::string_view name) const;
  std::optional<int64_t> optional_integer(
      std::string_view name) const;  // none: not given, no default
  bool flag(std::string_view name) const;
  double angle(std::string_view name) const;
  std::optional<double> optional_angle(std::string_view name) const;  // none: not given, no default
  std::vector<std::string> paths(std::string_view name) const;
  // The conversion options (conversion_options()) given, through their setters, in order.
  ConvertOptions options() const;
  // The write options (write_options()) given.
  WriteOptions write() const;
  const std::vector<OptionDef>& rows() const { return *rows_; }
  const OptionDef& row(std::string_view name) const;  // throws Error listing the rows

 private:
  const OptionValue* find(std::string_view name) const;
  const std::vector<OptionDef>* rows_;
  std::vector<std::pair<std::string, OptionValue>> values_;
};

// The write options' rows: overwrite, depth, quality, subsampling (a job lists those it takes).
const std::vector<OptionDef>& write_options();
const OptionDef& write_option(std::string_view name);
// The command's own rows (quiet, verbose): read by the command, not by the job.
const OptionDef& command_option(std::string_view name);

// A report: ordered key/values, each a number, flag, text, list (or tuple) or a nested report.
struct ReportField;
struct ReportValue {
  std::variant<bool, int64_t, double, std::string, std::vector<ReportValue>,
               std::vector<ReportField>>
      value;
  bool tuple = false;  // a list of fixed length (Python's tuple), e.g. a size
};
struct ReportField {
  std::string key;
  ReportValue value;
};
using Report = std::vector<ReportField>;
ReportValue report_size(Size size);  // (width, height) as a tuple
const ReportValue* report_find(const Report& report, std::string_view key);
// Sets the value of key (appended when absent).
void report_set(Report& report, std::string_view key, ReportValue value);

// What a run tells its caller as it goes: progress (the fraction done) and the lines the command
// prints (each a result, e.g. a converted file; none with --quiet), both from the calling thread.
struct JobEvents {
  std::function<void(double)> progress;
  std::function<void(const std::string&)> line;
  std::function<void(const std::string&)> warning;  // what the user should see even when quiet
  std::function<void(double, const std::string&)>
      status;  // progress with a word ("frame 57, 9.8 fps")
};

// The written and empty files of staged parts (summed over parts by the scheduler).
struct PartCounts {
  int64_t written = 0, empty = 0;
};

struct Staged {
  StagedFolder folder;
  int64_t parts = 0;  // render takes part numbers 0 .. parts - 1
};

struct JobDef {
  const char* name;                         // the subcommand; Python's function
  const char* summary;                      // the command's one line
  const char* python;                       // Python's docstring; nullptr: the command only
  const std::vector<OptionDef>& (*rows)();  // in the order the command and Python list them
  // A report whose "ok" is false makes the command exit 1 (e.g. a stability bound failed).
  Report (*run)(const Arguments& args, const JobEvents& events);
  Staged (*begin)(const Arguments& args) = nullptr;  // nullptr: not staged
  PartCounts (*render)(const Arguments& args, const StagedFolder& folder,
                       const std::vector<int64_t>& parts) = nullptr;
  Report (*finish)(const Arguments& args, const StagedFolder& folder, PartCounts counts) = nullptr;
  const char* python_name = nullptr;  // Python's function where not `name` (taken by another)
};

const std::vector<const JobDef*>& jobs();
const JobDef& job_named(std::string_view name);  // throws Error listing the jobs
// Removes a staged job's temporary folder (after a failed part; nothing if already gone).
void abandon_staged(const StagedFolder& folder);

}  // namespace panoproj
