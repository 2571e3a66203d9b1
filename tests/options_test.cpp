// The conversion options table: every row sets its ConvertOptions field from its type's value,
// refuses bad values naming itself, and is offered by the command for each subcommand it names.
#include "panoproj/options.hpp"
#include "panoproj/limits.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

// A valid value of each row, and the field it must change from the default.
struct Good {
  const char* name;
  OptionValue value;
  bool (*changed)(const ConvertOptions&);
};
const Good kGood[] = {
    {"size", std::string("640x480"),
     [](const ConvertOptions& o) { return o.size == Size{640, 480}; }},
    {"face_size", int64_t{256}, [](const ConvertOptions& o) { return o.face_size == 256; }},
    {"yaw", 12.5, [](const ConvertOptions& o) { return o.yaw == 12.5; }},
    {"pitch", -3.0, [](const ConvertOptions& o) { return o.pitch == -3.0; }},
    {"roll", 1e-9, [](const ConvertOptions& o) { return o.roll == 1e-9; }},
    {"interp", std::string("lanczos3"),
     [](const ConvertOptions& o) { return o.interp == Interp::Lanczos3; }},
    {"threads", int64_t{3}, [](const ConvertOptions& o) { return o.threads == 3; }},
    {"engine", std::string("scalar"),
     [](const ConvertOptions& o) { return o.engine == Engine::Scalar; }},
    {"antialias", std::string("4"),
     [](const ConvertOptions& o) { return o.antialias.has_value(); }},
    {"alpha", true, [](const ConvertOptions& o) { return o.add_alpha && o.edges.soft; }},
    {"fill", std::string("#ff0000"),
     [](const ConvertOptions& o) {
       return o.edges.colour && (*o.edges.colour)[0] == 1.0 && o.edges.soft;
     }},
    {"memory_limit", std::string("2G"),
     [](const ConvertOptions& o) { return o.memory_limit == 2000000000; }},
    {"decode_scale", std::string("4"), [](const ConvertOptions& o) { return o.decode_scale == 4; }},
};

TEST(Options, EveryRowSetsItsFieldAndHasACase) {
  EXPECT_EQ(conversion_options().size(), std::size(kGood));  // a new row needs a case here
  for (const Good& g : kGood) {
    ConvertOptions o;
    EXPECT_FALSE(g.changed(o)) << g.name;
    conversion_option(g.name, kUseConvert | kUseFiles).set(o, g.value);
    EXPECT_TRUE(g.changed(o)) << g.name;
  }
}

TEST(Options, SizesTakeEitherXAndASquare) {
  EXPECT_EQ(parse_size("640x480"), (Size{640, 480}));
  EXPECT_EQ(parse_size("640X480"), (Size{640, 480}));
  EXPECT_EQ(parse_size("1024"), (Size{1024, 1024}));
  for (const char* bad : {"x5", "5x", "-5", "+5", "5x-5", "0", "5x5x5", "", "5.0", "five"})
    EXPECT_THROW(parse_size(bad), Error) << bad;
}

TEST(Options, MemoryLimitsTakeDecimalAndBinaryUnits) {
  EXPECT_EQ(parse_memory_limit("4G"), 4000000000);
  EXPECT_EQ(parse_memory_limit("4GB"), 4000000000);
  EXPECT_EQ(parse_memory_limit("4GiB"), int64_t{4} << 30);
  EXPECT_EQ(parse_memory_limit("512MiB"), int64_t{512} << 20);
  EXPECT_EQ(parse_memory_limit("1mib"), int64_t{1} << 20);
  EXPECT_THROW(parse_memory_limit("2KiB"), Error);  // (under 1M)
  EXPECT_EQ(parse_memory_limit("1000000"), 1000000);
  auto message = [](const char* text) -> std::string {
    try {
      parse_memory_limit(text);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(message("999999"), "memory limit: 999999 (expected at least 1M: a job needs more)");
  EXPECT_EQ(
      message("1e19"),
      "memory limit: 1e19 (expected at most 9E18 bytes; leave it out for the memory available)");
  EXPECT_EQ(message("4GiBB"),
            "memory limit: 4GiBB (expected a size such as 4G, 4GiB, 512M or 800000000)");
  EXPECT_EQ(message("lots"),
            "memory limit: lots (expected a size such as 4G, 4GiB, 512M or 800000000)");
}

TEST(Options, BadValuesNameTheOption) {
  auto error_of = [](const char* name, OptionValue v) -> std::string {
    ConvertOptions o;
    try {
      conversion_option(name, kUseConvert | kUseFiles).set(o, v);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_of("size", std::string("0x5")),
            "size: 0x5 (expected WxH with positive integers, e.g. 2048x1024, or N for a square)");
  EXPECT_EQ(error_of("threads", int64_t{1} << 40), "threads: 1099511627776 (expected 0 for all cores, or 1 to 1024)");
  EXPECT_NE(error_of("interp", std::string("cubic")).find("cubic"), std::string::npos);
  EXPECT_NE(error_of("memory_limit", std::string("lots")).find("memory limit: lots"), std::string::npos);
  EXPECT_EQ(error_of("decode_scale", std::string("3")), "--decode-scale 3 (expected auto, 1, 2, 4 or 8)");
  // A name a call does not take, and a value of another type (a front end's bug).
  EXPECT_THROW(conversion_option("interp", kUseMaps), Error);
  try {
    conversion_option("zoom", kUseConvert);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(
                  "unknown option 'zoom' (expected one of: size, face_size, yaw, pitch, roll, ", 0),
              0u);
  }
  ConvertOptions o;
  EXPECT_THROW(conversion_option("yaw", kUseConvert).set(o, std::string("10")), InternalError);
}

// The command offers each row on each subcommand the row names, and no other.
TEST(Options, TheCommandOffersEachRowWhereTheTableSays) {
  auto help = [](const char* sub) {
    std::string out;
    const std::unique_ptr<FILE, int (*)(FILE*)> p(popen((std::string(PANOPROJ_CLI) + " " + sub + " --help").c_str(), "r"),
                                                 pclose);
    char buf[4096];
    while (p && std::fgets(buf, sizeof buf, p.get())) out += buf;
    return out;
  };
  for (auto [sub, use] : {std::pair{"convert", kUseConvert | kUseFiles}, {"maps", +kUseMaps}, {"accuracy", +kUseAccuracy}}) {
    const std::string text = help(sub);
    for (const OptionDef& d : conversion_options()) {
      const bool offered = text.find(flag_of(d) + " ") != std::string::npos;
      // (accuracy has sweep lists of its own under --interp, --engine and --antialias)
      if (d.use & use) {
        EXPECT_TRUE(offered) << sub << " " << flag_of(d);
      } else if (use != kUseAccuracy) {
        EXPECT_FALSE(offered) << sub << " " << flag_of(d);
      }
    }
  }
}

}  // namespace
}  // namespace panoproj
