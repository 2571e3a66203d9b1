#pragma once
// The jobs, one line each, in the order the command lists them (jobs.hpp). Each is a module in
// its folder (lib/src/jobs/<name>/) defining `const JobDef <name>_job`.
#include "panoproj/jobs.hpp"

#define PANOPROJ_JOBS(X) \
  X(convert)             \
  X(maps)                \
  X(tiles)               \
  X(views)               \
  X(model)               \
  X(undistort)           \
  X(stitch)              \
  X(accuracy)            \
  X(stability)           \
  X(info)

namespace panoproj {
#define PANOPROJ_DECLARE_JOB(name) extern const JobDef name##_job;
PANOPROJ_JOBS(PANOPROJ_DECLARE_JOB)
#undef PANOPROJ_DECLARE_JOB

// A job's rows: `own` with the conversion options `use` takes inserted before the first row
// of `after`.
std::vector<OptionDef> job_rows(std::vector<OptionDef> own, unsigned use,
                                const std::vector<OptionDef>& after);
// The folder jobs' image format row: the web formats (formats.hpp) by their usual extension, the
// first one the default.
const OptionDef& web_format_option();
// A shared row with this job's help line.
OptionDef with_help(const OptionDef& row, const char* help);
}  // namespace panoproj
