#include "jobs/frame_selection.hpp"

#include <algorithm>
#include <string>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

// "12.5", "1:02.5", "01:02:03" in seconds; throws Error naming the option.
double parse_time(const std::string& text, const char* option) {
  double total = 0;
  size_t at = 0;
  int parts = 0;
  bool ok = !text.empty();
  while (ok && at <= text.size()) {
    const size_t colon = text.find(':', at);
    const std::string part =
        text.substr(at, colon == std::string::npos ? std::string::npos : colon - at);
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    ok = !part.empty() && end && *end == '\0' && std::isfinite(v) && v >= 0 && ++parts <= 3 &&
         (colon == std::string::npos || v == std::floor(v));
    total = total * 60 + v;
    if (colon == std::string::npos) break;
    at = colon + 1;
  }
  if (!ok || total > 1e9)
    throw Error(option_text(option, text) +
                " is not a time (seconds, e.g. 12.5, or [HH:]MM:SS[.s])");
  return total;
}

}  // namespace

double FrameSelection::step(double rate) const {
  if (fps > 0) return 1 / fps;
  return rate > 0 ? static_cast<double>(std::max<int64_t>(every, 1)) / rate : 0;
}

double FrameSelection::expected(const VideoInfo& info) const {
  if (whole() && info.frames > 0) return static_cast<double>(info.frames);
  const double rate =
      info.frame_rate[1] > 0 ? static_cast<double>(info.frame_rate[0]) / info.frame_rate[1] : 0;
  const double span = std::min(info.duration, range.end) - range.start;
  const double taken =
      fps > 0 ? std::min(fps, rate) : rate / static_cast<double>(std::max<int64_t>(every, 1));
  return std::max(0.0, span * taken);
}

const std::vector<OptionDef>& frame_selection_rows() {
  static const std::vector<OptionDef> rows{
      {"stream", OptionType::Integer, 0, "None",
       "video: the video stream to read, counted among the video streams from 0 (default: the "
       "first)"},
      {"start", OptionType::Text, 0, "None",
       "video: from this time (seconds or [HH:]MM:SS[.s]; the output's times count from it)"},
      {"duration", OptionType::Text, 0, "None",
       "video: this long (seconds or [HH:]MM:SS[.s]; default: to the end)"},
      {"fps", OptionType::Text, 0, "None",
       "video: at most this many frames a second, e.g. 2 or 0.5 (frames dropped)"},
      {"every", OptionType::Integer, 0, "None", "video: every n-th frame (frames dropped)"},
  };
  return rows;
}

FrameSelection frame_selection_of(const Arguments& a) {
  FrameSelection s;
  if (const auto n = a.optional_integer("stream")) {
    if (*n < 0 || *n > (1 << 20))
      throw Error(option_number("stream", std::to_string(*n)) +
                  " is out of range (0 for the first video stream)");
    s.stream = static_cast<int>(*n);
  }
  if (const std::string t = a.text("start"); !t.empty()) s.range.start = parse_time(t, "start");
  if (const std::string t = a.text("duration"); !t.empty()) {
    const double d = parse_time(t, "duration");
    if (d <= 0) throw Error(option_text("duration", t) + " is empty (give a time over 0)");
    s.range.end = s.range.start + d;
  }
  if (const auto e = a.optional_integer("every")) {
    if (*e < 1 || *e > 1000000)
      throw Error(option_number("every", std::to_string(*e)) + " is out of range (1 to 1000000)");
    s.every = *e;
  }
  if (const std::string t = a.text("fps"); !t.empty()) {
    char* end = nullptr;
    s.fps = std::strtod(t.c_str(), &end);
    if (!end || *end || !std::isfinite(s.fps) || s.fps <= 0 || s.fps > 1000)
      throw Error(option_text("fps", t) + " is not a frame rate (over 0, up to 1000)");
    if (s.every > 0)
      throw Error(option_text("fps") + " and " + option_text("every") +
                  " both pick frames: give one");
  }
  return s;
}

bool frame_selection_given(const FrameSelection& s) {
  return s.stream >= 0 || !s.whole();
}

bool FramePicker::take(int64_t pts) {
  const int64_t k = read_++;
  if (s_.every > 1) return k % s_.every == 0;
  if (s_.fps <= 0) return true;
  const double t = static_cast<double>(pts) * tb_;
  if (k > 0 && t < due_ - 1e-9) return false;
  due_ = std::max(due_ + 1 / s_.fps, t + 0.5 / s_.fps);
  return true;
}

}  // namespace panoproj
