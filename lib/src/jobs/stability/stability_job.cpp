// The stability job: every projection's round trips at its extremes and singular points against
// their bounds (diagnostics/stability.hpp); the command only, exit 1 when a bound fails.
#include <algorithm>

#include "jobs/list.hpp"
#include "panoproj/diagnostics/stability.hpp"

namespace panoproj {
namespace {

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows;
  return rows;
}

Report run(const Arguments&, const JobEvents& events) {
  std::vector<StabilityResult> results;
  for (const StabilityCase& c : stability_cases()) results.push_back(run_stability_case(c));
  const auto failed =
      std::count_if(results.begin(), results.end(), [](const auto& r) { return !r.pass(); });
  if (events.line)
    events.line(stability_table(results) + "\n" + std::to_string(results.size()) + " cases, " +
                std::to_string(failed) + " outside their bounds");
  return {{"cases", {static_cast<int64_t>(results.size())}},
          {"failed", {static_cast<int64_t>(failed)}},
          {"ok", {failed == 0}}};
}

}  // namespace

const JobDef stability_job{
    .name = "stability",
    .summary =
        "round-trip every projection at its extremes and singular points; exit 1 if a bound fails",
    .python = nullptr,
    .rows = rows,
    .run = run,
};

}  // namespace panoproj
