// The panoproj command: a subcommand per job, made from the job's rows
// (lib/include/panoproj/jobs.hpp).
#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "base/text.hpp"
#include "panoproj/error.hpp"
#include "panoproj/jobs.hpp"
#include "panoproj/spec.hpp"

namespace {

using namespace panoproj;

// Image libraries (libpng, libjpeg via OpenImageIO) print their own messages to stderr; the
// CLI reports failures itself in one line, so it holds stderr while a job runs.
class QuietStderr {
 public:
  explicit QuietStderr(bool active) {
    if (!active) return;
    std::fflush(stderr);
    saved_ = ::dup(2);
    const int null_fd = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null_fd >= 0) ::dup2(null_fd, 2);
    if (null_fd >= 0) ::close(null_fd);
    if (saved_ >= 0) set_notice_handler([fd = saved_](const std::string& text) { ::dprintf(fd, "panoproj: %s\n", text.c_str()); });
  }
  ~QuietStderr() {
    if (saved_ < 0) return;
    set_notice_handler({});
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;
  // The real stderr while held (for the progress bar).
  int fd() const { return saved_ >= 0 ? saved_ : 2; }

 private:
  int saved_ = -1;
};

// "[#####.....]  52%" redrawn in place, only on a terminal.
class ProgressBar {
 public:
  ProgressBar(int fd, bool enabled) : fd_(fd), enabled_(enabled && ::isatty(fd)) {}
  ~ProgressBar() {
    if (enabled_ && shown_) (void)!::write(fd_, "\r\033[K", 4);
  }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  // Erases the bar, for a line to take its place.
  void clear() {
    if (enabled_ && shown_) (void)!::write(fd_, "\r\033[K", 4);
    last_ = -1;
  }
  // The bar at `fraction`, with the time left at the rate so far and the job's status ("frame
  // 57, 9.8 fps").
  void update(double fraction, const std::string& status = {}) {
    if (!enabled_) return;
    const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100);
    if (percent == last_ && status == status_) return;
    last_ = percent, status_ = status;
    shown_ = true;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char eta[32] = "";
    if (fraction > 0.02 && fraction < 1) {
      const auto left = static_cast<int64_t>(elapsed * (1 - fraction) / fraction);
      std::snprintf(eta, sizeof eta, ", %lld:%02lld left", static_cast<long long>(left / 60),
                    static_cast<long long>(left % 60));
    }
    char line[256];
    const int filled = percent * 30 / 100;
    const int n = std::snprintf(line, sizeof line, "\r[%.*s%.*s] %3d%%%s%s%s\033[K", filled,
                                "##############################", 30 - filled,
                                "..............................", percent,
                                status.empty() ? "" : ", ", status.c_str(), eta);
    (void)!::write(fd_, line, static_cast<size_t>(std::min<int>(n, sizeof line - 1)));
  }

 private:
  int fd_;
  bool enabled_, shown_ = false;
  int last_ = -1;
  std::string status_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// A job's subcommand, made from its rows (jobs.hpp): a flag or positional per row the command
// shows, bound to text (the row's type parses it: option_value) or to a flag. A Paths
// positional takes every word but those of the positionals after it (IN... OUT).
class Command {
 public:
  Command(CLI::App& app, const JobDef& job)
      : job_(job), sub_(app.add_subcommand(job.name, job.summary)) {
    const std::vector<OptionDef>& rows = job.rows();
    for (size_t i = 0; i < rows.size(); ++i) {
      const OptionDef& d = rows[i];
      if (d.traits & (kPythonOnly | kNeither)) continue;
      Bound& b = bound_.emplace_back(Bound{&d, {}, {}, false, nullptr, 0});
      if (d.type == OptionType::Paths) {
        for (size_t k = i + 1; k < rows.size() && (rows[k].traits & kPositional); ++k) ++b.after;
        b.option = sub_->add_option(flag_of(d), b.words, d.help)
                       ->expected(static_cast<int>(b.after) + 1, -1);
        i += b.after;
      } else if (d.type == OptionType::Flag) {
        // (bound to a bool: CLI11 refuses --alpha=maybe)
        b.option = sub_->add_flag(flag_of(d), b.flag, d.help);
      } else {
        b.option = sub_->add_option(flag_of(d), b.text, d.help);
        if (d.type == OptionType::Integer) b.option->type_name("INT");
      }
      if (d.traits & kRequired) b.option->required();
    }
  }
  bool parsed() const { return sub_->parsed(); }
  const JobDef& job() const { return job_; }

  // The given values as the job's arguments.
  Arguments arguments() const {
    Arguments args(job_.rows());
    const std::vector<OptionDef>& rows = job_.rows();
    for (const Bound& b : bound_) {
      if (b.option->count() == 0) continue;
      const OptionDef& d = *b.def;
      if (d.type == OptionType::Paths) {
        const size_t own = b.words.size() - b.after;
        args.set(d.name, std::vector<std::string>(
                             b.words.begin(), b.words.begin() + static_cast<std::ptrdiff_t>(own)));
        const size_t at = static_cast<size_t>(&d - rows.data());
        for (size_t k = 0; k < b.after; ++k) args.set(rows[at + 1 + k].name, b.words[own + k]);
      } else {
        args.set(d.name,
                 d.type == OptionType::Flag ? OptionValue(b.flag) : option_value(d, b.text));
      }
    }
    return args;
  }

 private:
  struct Bound {
    const OptionDef* def;
    std::string text;
    std::vector<std::string> words;
    bool flag;
    CLI::Option* option;
    size_t after;  // a Paths row's positionals that follow it
  };
  const JobDef& job_;
  CLI::App* sub_;
  std::deque<Bound> bound_;  // (stable addresses: CLI11 keeps pointers to text and flag)
};

// Runs the job: its lines on stdout (none with --quiet), progress on a terminal's stderr, library
// chatter held back unless --verbose. Exit 1 when its report says it failed.
int run_job(const Command& command) {
  const Arguments args = command.arguments();
  const auto has = [&](const char* name) {
    for (const OptionDef& d : args.rows())
      if (std::string_view(d.name) == name) return args.flag(name);
    return false;
  };
  const bool quiet = has("quiet");
  QuietStderr hold(!has("verbose"));
  install_signal_cleanup(hold.fd());  // (a batch's line on the real stderr)
  ProgressBar bar(hold.fd(), !quiet);
  JobEvents events;
  events.progress = [&](double f) { bar.update(f); };
  events.status = [&](double f, const std::string& s) { bar.update(f, s); };
  if (!quiet)
    events.line = [&](const std::string& line) {
      bar.clear();
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
  if (!quiet)
    events.warning = [&](const std::string& line) {  // (the real stderr)
      bar.clear();
      dprintf(hold.fd(), "panoproj: warning: %s\n", line.c_str());
    };
  const Report report = command.job().run(args, events);
  const ReportValue* ok = report_find(report, "ok");
  return ok && !std::get<bool>(ok->value) ? 1 : 0;
}

// The command's own texts where CLI11's would be raw: a word that is no command, a flag the
// command does not take (a projection's key: it goes in the spec), each with the nearest name.
// "" when the line's commands and flags are all known.
std::string unknown_words(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  std::vector<std::string> names;
  const JobDef* job = nullptr;
  for (const JobDef* j : jobs()) {
    names.emplace_back(j->name);
    if (names.back() == argv[1]) job = j;
  }
  if (!job) {
    const std::string near = closest(argv[1], names);
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    return "'" + std::string(argv[1]).substr(0, 60) + "' is not a command (" +
           (near.empty() ? "" : "did you mean " + near + "? ") + "the commands: " + list + ")";
  }
  std::vector<std::string> flags{"--help", "-h"};
  for (const OptionDef& d : job->rows()) {
    if (d.traits & (kPythonOnly | kNeither | kPositional)) continue;
    std::stringstream spelled(flag_of(d));
    for (std::string f; std::getline(spelled, f, ',');) flags.push_back(f);
  }
  // A projection's key given as a flag goes in the target's spec: --to's, as given, for the
  // example.
  const bool takes_to = std::find(flags.begin(), flags.end(), "--to") != flags.end();
  std::string to = "<projection>";
  for (int i = 2; i + 1 < argc; ++i)
    if (std::string_view(argv[i]) == "--to") to = std::string(argv[i + 1]).substr(0, 200);
  for (int i = 2; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--") break;
    if (word.rfind("--", 0) != 0) continue;
    const std::string flag = word.substr(0, word.find('='));
    if (std::find(flags.begin(), flags.end(), flag) != flags.end()) continue;
    std::string key = flag.substr(2);
    std::replace(key.begin(), key.end(), '-', '_');
    const std::string head = flag.substr(0, 60) + " is not an option of " + job->name;
    for (const ProjectionDef& d : projection_catalog())
      for (const ParamDef& p : d.params)
        if (takes_to && key == p.key) {
          const std::string value = word.find('=') != std::string::npos
                                        ? word.substr(word.find('=') + 1)
                                    : i + 1 < argc ? std::string(argv[i + 1])
                                                   : std::string("...");
          return head + ": a projection's keys go in its spec (--to " + to +
                 (to.find(':') == std::string::npos ? ":" : ",") + key + "=" + value.substr(0, 20) +
                 ")";
        }
    std::vector<std::string> longs;
    for (const std::string& f : flags)
      if (f.rfind("--", 0) == 0) longs.push_back(f.substr(2));
    const std::string near = closest(flag.substr(2), longs);
    return head + " (" + (near.empty() ? "" : "did you mean --" + near + "? ") + "see panoproj " +
           job->name + " --help)";
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"panoproj: convert images between panoramic, fisheye, pinhole, cubemap and map "
               "projections"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "panoproj " PANOPROJ_VERSION);
  std::deque<Command> commands;
  for (const JobDef* job : jobs()) commands.emplace_back(app, *job);
  if (const std::string said = unknown_words(argc, argv); !said.empty()) {
    std::fprintf(stderr, "panoproj: error: %s\n", said.c_str());
    return 1;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, exit 1 (CLI11's own codes are 100 and up).
    std::fprintf(stderr, "panoproj: error: %s (see panoproj %s--help)\n", one_line(e.what()).c_str(),
                 argc > 1 && argv[1][0] != '-' ? (std::string(argv[1]) + " ").c_str() : "");
    return 1;
  }
  install_signal_cleanup();
  try {
    for (const Command& c : commands)
      if (c.parsed()) return run_job(c);
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "panoproj: error: out of memory (ask for a smaller size, or set --memory-limit to be "
                         "refused before the work starts)\n");
    return 1;
  } catch (const InternalError& e) {
    std::fprintf(stderr, "panoproj: %s (a bug: please report it with the command line)\n", one_line(e.what()).c_str());
    return 70;  // EX_SOFTWARE
  } catch (const std::exception& e) {
    std::fprintf(stderr, "panoproj: error: %s\n", one_line(e.what()).c_str());
    return 1;
  }
}
