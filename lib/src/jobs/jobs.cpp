// The job list, the rows jobs share (write options, the command's own) and Arguments (jobs.hpp).
#include "jobs/list.hpp"

#include <algorithm>
#include <array>

#include "io/atomic_output.hpp"
#include "io/formats.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

const std::string& value_text(const OptionValue& v) {
  return std::get<std::string>(v);
}

// A row's Python default as a value: 'text' unquoted, numbers, True/False; None: nothing.
std::optional<OptionValue> default_of(const OptionDef& row) {
  const std::string_view d = row.default_text ? row.default_text : "None";
  if (d == "None" || d.empty()) return std::nullopt;
  switch (row.type) {
    case OptionType::Flag:
      return d == "True";
    case OptionType::Integer:
      return static_cast<int64_t>(std::stoll(std::string(d)));
    case OptionType::Angle:
      return std::stod(std::string(d));
    case OptionType::Paths:
      return std::vector<std::string>{};
    case OptionType::Text:
    case OptionType::Path:
      return std::string(d.size() >= 2 && d.front() == '\'' ? d.substr(1, d.size() - 2) : d);
  }
  return std::nullopt;
}

bool holds_type(OptionType t, const OptionValue& v) {
  switch (t) {
    case OptionType::Angle:
      return std::holds_alternative<double>(v);
    case OptionType::Integer:
      return std::holds_alternative<int64_t>(v);
    case OptionType::Flag:
      return std::holds_alternative<bool>(v);
    case OptionType::Text:
    case OptionType::Path:
      return std::holds_alternative<std::string>(v);
    case OptionType::Paths:
      return std::holds_alternative<std::vector<std::string>>(v);
  }
  return false;
}

std::optional<PixelType> parse_depth(const std::string& text) {
  if (text.empty() || text == "keep") return std::nullopt;
  for (PixelType t : {PixelType::U8, PixelType::U16, PixelType::F16, PixelType::F32})
    if (text == name_of(t)) return t;
  throw Error("depth: " + text + " (expected keep, uint8, uint16, half or float)");
}

}  // namespace

const std::vector<const JobDef*>& jobs() {
#define PANOPROJ_JOB_ENTRY(name) &name##_job,
  static const std::vector<const JobDef*> list{PANOPROJ_JOBS(PANOPROJ_JOB_ENTRY)};
#undef PANOPROJ_JOB_ENTRY
  return list;
}

const JobDef& job_named(std::string_view name) {
  std::string names;
  for (const JobDef* j : jobs()) {
    if (name == j->name) return *j;
    names += (names.empty() ? "" : ", ") + std::string(j->name);
  }
  throw Error("unknown job '" + std::string(name) + "' (expected one of: " + names + ")");
}

void abandon_staged(const StagedFolder& folder) {
  OutputFolder::remove_staged(folder);
}

std::vector<OptionDef> job_rows(std::vector<OptionDef> own, unsigned use,
                                const std::vector<OptionDef>& after) {
  for (const OptionDef& d : conversion_options())
    if (d.use & use) own.push_back(d);
  own.insert(own.end(), after.begin(), after.end());
  return own;
}

OptionDef with_help(const OptionDef& row, const char* help) {
  OptionDef d = row;
  d.help = help;
  return d;
}

const std::vector<OptionDef>& write_options() {
  static const std::vector<OptionDef> rows{
      {"depth", OptionType::Text, 0, "None", "output samples: keep|uint8|uint16|half|float",
       nullptr, "keep|uint8|uint16|half|float"},
      {"overwrite", OptionType::Flag, 0, "False", "replace an existing output"},
      {"quality", OptionType::Integer, 0, "95", "JPEG output quality, 1 to 100 (default 95)"},
      {"subsampling", OptionType::Text, 0, "'420'",
       "JPEG output chroma: 420 (default: half width and height), 422 (half width) or 444 (full)",
       nullptr, "420|422|444"},
  };
  return rows;
}

const OptionDef& write_option(std::string_view name) {
  for (const OptionDef& d : write_options())
    if (name == d.name) return d;
  throw InternalError("no write option " + std::string(name));
}

const OptionDef& web_format_option() {
  // "jpg|png", "'jpg'" and "jpg (default) | png" from the table's web formats.
  static const std::array<std::string, 3> text = [] {
    std::string choices, help;
    for (const ImageFormat* f : image_formats()) {
      if (!f->web) continue;
      const std::string ext(f->extensions[0].substr(1));  // (without its dot)
      help.append(choices.empty() ? "" : " | ")
          .append(ext)
          .append(choices.empty() ? " (default)" : "");
      choices.append(choices.empty() ? "" : "|").append(ext);
    }
    std::string fallback("'");
    fallback.append(choices, 0, choices.find('|')).append("'");
    return std::array<std::string, 3>{choices, fallback, help};
  }();
  static const OptionDef row{"format", OptionType::Text, 0, text[1].c_str(), text[2].c_str(),
                             nullptr,  text[0].c_str()};
  return row;
}

const OptionDef& command_option(std::string_view name) {
  static const std::vector<OptionDef> rows{
      {"quiet", OptionType::Flag, 0, "False", "print nothing on success (warnings neither)",
       nullptr, nullptr, "-q,--quiet", kCommandOnly},
      {"verbose", OptionType::Flag, 0, "False", "let image libraries print their own warnings",
       nullptr, nullptr, "-v,--verbose", kCommandOnly},
  };
  for (const OptionDef& d : rows)
    if (name == d.name) return d;
  throw InternalError("no command option " + std::string(name));
}

const OptionDef& Arguments::row(std::string_view name) const {
  std::string names;
  for (const OptionDef& d : *rows_) {
    if (name == d.name) return d;
    names += (names.empty() ? "" : ", ") + std::string(d.name);
  }
  throw Error("unknown option '" + std::string(name) + "' (expected one of: " + names + ")");
}

Arguments& Arguments::set(std::string_view name, OptionValue value) {
  const OptionDef& d = row(name);
  if (!holds_type(d.type, value))
    throw InternalError(std::string("option ") + d.name + " was handed a value of another type");
  for (auto& [k, v] : values_)
    if (k == name) {
      v = std::move(value);
      return *this;
    }
  values_.emplace_back(std::string(name), std::move(value));
  return *this;
}

const OptionValue* Arguments::find(std::string_view name) const {
  for (const auto& [k, v] : values_)
    if (k == name) return &v;
  return nullptr;
}

std::optional<std::string> Arguments::optional_text(std::string_view name) const {
  if (const OptionValue* v = find(name)) return value_text(*v);
  const auto d = default_of(row(name));
  return d ? std::optional<std::string>(value_text(*d)) : std::nullopt;
}

std::string Arguments::text(std::string_view name) const {
  return optional_text(name).value_or("");
}

int64_t Arguments::integer(std::string_view name) const {
  if (const OptionValue* v = find(name)) return std::get<int64_t>(*v);
  const auto d = default_of(row(name));
  return d ? std::get<int64_t>(*d) : 0;
}

std::optional<int64_t> Arguments::optional_integer(std::string_view name) const {
  if (const OptionValue* v = find(name)) return std::get<int64_t>(*v);
  const auto d = default_of(row(name));
  return d ? std::optional<int64_t>(std::get<int64_t>(*d)) : std::nullopt;
}

bool Arguments::flag(std::string_view name) const {
  if (const OptionValue* v = find(name)) return std::get<bool>(*v);
  const auto d = default_of(row(name));
  return d && std::get<bool>(*d);
}

double Arguments::angle(std::string_view name) const {
  if (const OptionValue* v = find(name)) return std::get<double>(*v);
  const auto d = default_of(row(name));
  return d ? std::get<double>(*d) : 0;
}

std::optional<double> Arguments::optional_angle(std::string_view name) const {
  if (const OptionValue* v = find(name)) return std::get<double>(*v);
  const auto d = default_of(row(name));
  if (d) return std::get<double>(*d);
  return std::nullopt;
}

std::vector<std::string> Arguments::paths(std::string_view name) const {
  if (const OptionValue* v = find(name)) return std::get<std::vector<std::string>>(*v);
  row(name);
  return {};
}

ConvertOptions Arguments::options() const {
  ConvertOptions o;
  for (const auto& [k, v] : values_) {
    const OptionDef& d = row(k);
    if (d.set) d.set(o, v);
  }
  return o;
}

WriteOptions Arguments::write() const {
  WriteOptions w;
  for (const OptionDef& d : *rows_) {
    const std::string_view n = d.name;
    if (n == "overwrite")
      w.overwrite = flag(n);
    else if (n == "quality") {
      const int64_t q = integer(n);
      if (q < 1 || q > 100) throw Error("quality: " + std::to_string(q) + " (expected 1 to 100)");
      w.quality = static_cast<int>(q);
    } else if (n == "subsampling")
      w.subsampling = parse_subsampling(text(n));
    else if (n == "depth")
      w.type = parse_depth(text(n));
  }
  check_write_options(w);
  return w;
}

ReportValue report_size(Size size) {
  return {std::vector<ReportValue>{{size.width}, {size.height}}, true};
}

void report_set(Report& report, std::string_view key, ReportValue value) {
  for (ReportField& f : report)
    if (f.key == key) {
      f.value = std::move(value);
      return;
    }
  report.push_back({std::string(key), std::move(value)});
}

const ReportValue* report_find(const Report& report, std::string_view key) {
  for (const ReportField& f : report)
    if (f.key == key) return &f.value;
  return nullptr;
}

}  // namespace panoproj
