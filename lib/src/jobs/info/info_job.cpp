// The info job: the projection catalogue with its parameters, ranges and defaults; the command
// only (Python has panoproj.projections()).
#include <sstream>

#include "jobs/list.hpp"
#include "panoproj/spec.hpp"

namespace panoproj {
namespace {

const std::vector<OptionDef>& rows() {
  static const std::vector<OptionDef> rows;
  return rows;
}

std::string range_of(const ParamDef& p) {
  std::ostringstream range;
  if (p.type == ParamType::Choice)
    range << p.choices;
  else if (p.type == ParamType::Text)
    range << "text";
  else
    range << (p.lo_open ? "(" : "[") << p.lo << ", " << p.hi << (p.hi_open ? ")" : "]");
  return range.str();
}

Report run(const Arguments&, const JobEvents& events) {
  std::ostringstream out;
  out << "Projections (spec: name[:key=value,...], angles in degrees, sizes in pixels):\n";
  for (const auto& d : projection_catalog()) {
    out << "\n  " << d.name << " - " << d.summary << "\n";
    for (const auto& p : d.params)
      out << "      " << p.key << "=" << (*p.default_text ? p.default_text : "<derived>") << "  "
          << range_of(p) << "  " << p.help << "\n";
  }
  out << "\nInterpolators: nearest, bilinear, bicubic (Keys a=-0.5, default), lanczos3; "
         "bicubic-dering and\n"
         "lanczos3-dering clamp to the 2x2 taps around each sample (no ringing at sharp edges, "
         "e.g. around an\n"
         "HDR sun)\n"
         "Rotation: --yaw (positive looks right), --pitch (positive looks up), --roll "
         "(positive turns the view clockwise); applied roll, then pitch, then yaw.";
  if (events.line) events.line(out.str());
  return {{"projections", {static_cast<int64_t>(projection_catalog().size())}}};
}

}  // namespace

const JobDef info_job{
    .name = "info",
    .summary = "list projections, their parameters and defaults",
    .python = nullptr,
    .rows = rows,
    .run = run,
};

}  // namespace panoproj
