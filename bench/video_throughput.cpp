// A video's decode and convert alone (no encoder, no output): the convert job's pipeline with its
// frames handed to a sink, for scripts/bench.sh video against ffmpeg's v360 to a null output.
// Usage: video_throughput IN.mp4 TO_SPEC [--size WxH] [--interp NAME] [--from SPEC]; prints the
// report's line.
#include <cstdio>
#include <string>

#include "io/video_plugin.hpp"
#include "jobs/convert/video_convert.hpp"
#include "panoproj/error.hpp"

namespace {

class Sink final : public panoproj::VideoWriter {
 public:
  void write(const panoproj::VideoFrame&) override {}
  void finish() override {}
  const std::vector<std::string>& notes() const override { return notes_; }

 private:
  std::vector<std::string> notes_;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: video_throughput IN TO_SPEC [--size WxH] [--interp NAME] [--from SPEC]\n");
    return 2;
  }
  try {
    panoproj::VideoRequest r;
    r.files.inputs = {argv[1]}, r.files.output = "null.mp4", r.files.to = argv[2];
    for (int i = 3; i + 1 < argc; i += 2) {
      const std::string k = argv[i], v = argv[i + 1];
      if (k == "--size") {
        const auto x = v.find('x');
        r.files.options.size =
            panoproj::Size{std::stoll(v.substr(0, x)), std::stoll(v.substr(x + 1))};
      } else if (k == "--interp") {
        r.files.options.interp = panoproj::parse_interp(v);
      } else if (k == "--from") {
        r.files.from = v;
      } else {
        std::fprintf(stderr, "video_throughput: unknown option %s\n", k.c_str());
        return 2;
      }
    }
    panoproj::JobEvents events;
    events.line = [](const std::string& l) { std::printf("%s\n", l.c_str()); };
    Sink sink;
    panoproj::convert_video(r, events, &sink);
  } catch (const panoproj::Error& e) {
    std::fprintf(stderr, "video_throughput: %s\n", e.what());
    return 1;
  }
  return 0;
}
