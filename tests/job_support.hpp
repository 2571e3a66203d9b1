#pragma once
// Jobs run as the front ends run them (jobs.hpp): arguments by row name, reports read by key.
#include <string>
#include <utility>
#include <vector>

#include "panoproj/jobs.hpp"

namespace panoproj::test {

inline Arguments job_args(const char* job, std::vector<std::pair<const char*, OptionValue>> given) {
  Arguments a(job_named(job).rows());
  for (auto& [name, value] : given) a.set(name, std::move(value));
  return a;
}

inline Report run_job(const char* job, const Arguments& args) {
  return job_named(job).run(args, {});
}

inline const ReportValue& field(const Report& r, std::string_view key) {
  const ReportValue* v = report_find(r, key);
  if (!v) throw std::runtime_error("report has no " + std::string(key));
  return *v;
}
inline int64_t integer(const Report& r, std::string_view key) {
  return std::get<int64_t>(field(r, key).value);
}
inline const std::string& text(const Report& r, std::string_view key) {
  return std::get<std::string>(field(r, key).value);
}
inline const std::vector<ReportValue>& list(const Report& r, std::string_view key) {
  return std::get<std::vector<ReportValue>>(field(r, key).value);
}
inline const Report& item(const ReportValue& v) {
  return std::get<Report>(v.value);
}
inline Size size(const Report& r, std::string_view key) {
  const auto& s = list(r, key);
  return {std::get<int64_t>(s[0].value), std::get<int64_t>(s[1].value)};
}

}  // namespace panoproj::test
