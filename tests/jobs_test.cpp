// Jobs and their rows (jobs.hpp): every job's rows well formed (names and flags once, defaults of
// their type and among their choices), the command's help listing exactly the command's rows,
// Arguments refusing unknown names and wrong types, defaults from the rows, and a report read by
// key.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <sstream>

#include "job_support.hpp"
#include "jobs/list.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

std::string help_of(const std::string& job) {
  const std::string cmd = std::string(PANOPROJ_CLI) + " " + job + " --help";
  FILE* f = popen(cmd.c_str(), "r");
  std::string out;
  char b[4096];
  for (size_t n; f && (n = fread(b, 1, sizeof b, f)) > 0;) out.append(b, n);
  if (f) pclose(f);
  return out;
}

std::vector<std::string> choices_of(const OptionDef& d) {
  std::vector<std::string> out;
  std::stringstream s(d.choices ? d.choices : "");
  for (std::string c; std::getline(s, c, '|');) out.push_back(c);
  return out;
}

TEST(Jobs, EveryJobsRowsAreWellFormed) {
  std::set<std::string> names;
  for (const JobDef* job : jobs()) {
    EXPECT_TRUE(names.insert(job->name).second) << job->name;
    EXPECT_EQ(&job_named(job->name), job);
    EXPECT_EQ(job->begin == nullptr, job->render == nullptr) << job->name;
    EXPECT_EQ(job->begin == nullptr, job->finish == nullptr) << job->name;
    std::set<std::string> rows, flags;
    bool named = false;  // a non-positional row seen
    const Arguments args(job->rows());
    for (const OptionDef& d : job->rows()) {
      EXPECT_TRUE(rows.insert(d.name).second) << job->name << ": " << d.name << " twice";
      if (!(d.traits & (kPythonOnly | kNeither))) {
        EXPECT_TRUE(flags.insert(flag_of(d)).second) << flag_of(d);
      }
      if (d.traits & kPositional) {
        EXPECT_FALSE(named) << job->name << ": positional " << d.name << " after flags";
      }
      named = named || !(d.traits & kPositional);
      EXPECT_TRUE(d.help && *d.help) << d.name;
      // The default reads as the row's type, and is one of its choices.
      std::string value;
      switch (d.type) {
        case OptionType::Angle:
          EXPECT_NO_THROW(args.angle(d.name)) << d.name;
          break;
        case OptionType::Integer:
          EXPECT_NO_THROW(args.integer(d.name)) << d.name;
          break;
        case OptionType::Flag:
          EXPECT_NO_THROW(args.flag(d.name)) << d.name;
          break;
        case OptionType::Paths:
          EXPECT_TRUE(args.paths(d.name).empty()) << d.name;
          break;
        case OptionType::Text:
        case OptionType::Path:
          value = args.text(d.name);
          break;
      }
      const auto choices = choices_of(d);
      if (!choices.empty() && std::string_view(d.default_text) != "None") {
        EXPECT_NE(std::find(choices.begin(), choices.end(), value), choices.end())
            << job->name << ": " << d.name;
      }
    }
  }
}

TEST(Jobs, TheCommandsHelpListsExactlyTheCommandsRows) {
  for (const JobDef* job : jobs()) {
    const std::string help = help_of(job->name);
    ASSERT_NE(help.find(job->summary), std::string::npos) << job->name << "\n" << help;
    std::set<std::string> want{"-h,--help"}, got;
    const std::vector<OptionDef>& rows = job->rows();
    for (size_t i = 0; i < rows.size(); ++i) {
      const OptionDef& d = rows[i];
      if (d.traits & (kPythonOnly | kNeither)) continue;
      // (a positional after a Paths row is its last word: IN... OUT)
      if ((d.traits & kPositional) && i > 0 && rows[i - 1].type == OptionType::Paths) continue;
      want.insert(flag_of(d));
    }
    std::istringstream lines(help);
    for (std::string line; std::getline(lines, line);) {
      std::istringstream words(line);
      std::string first;
      words >> first;
      if (line.rfind("  ", 0) == 0 && !first.empty() && first != "Usage:") got.insert(first);
    }
    EXPECT_EQ(got, want) << job->name << "\n" << help;
  }
}

TEST(Jobs, ArgumentsRefuseUnknownNamesAndWrongTypes) {
  Arguments args(job_named("tiles").rows());
  try {
    args.set("tiles", int64_t{1});
    ADD_FAILURE() << "an unknown name accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "unknown option 'tiles' (expected one of: image, out_dir, viewer"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(args.set("tile", std::string("512")), InternalError);
  EXPECT_EQ(args.integer("tile"), 512);  // the row's default
  EXPECT_FALSE(args.optional_text("src"));
  args.set("tile", int64_t{256}).set("tile", int64_t{128});
  EXPECT_EQ(args.integer("tile"), 128);  // the last one given
  args.set("yaw", 30.0).set("interp", std::string("lanczos3"));
  const ConvertOptions o = args.options();
  EXPECT_EQ(o.yaw, 30);
  EXPECT_EQ(o.interp, Interp::Lanczos3);
  args.set("quality", int64_t{101});
  try {
    args.write();
    ADD_FAILURE() << "quality 101 accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "quality: 101 (expected 1 to 100)");
  }
  EXPECT_THROW(job_named("video"), Error);
}

TEST(Jobs, ReportsAreReadByKey) {
  const Report r = test::run_job("info", Arguments(job_named("info").rows()));
  EXPECT_EQ(test::integer(r, "projections"), static_cast<int64_t>(projection_catalog().size()));
  EXPECT_EQ(report_find(r, "absent"), nullptr);
  const ReportValue s = report_size({3, 2});
  EXPECT_TRUE(s.tuple);
  EXPECT_EQ(std::get<int64_t>(std::get<std::vector<ReportValue>>(s.value)[1].value), 2);
}

}  // namespace
}  // namespace panoproj
