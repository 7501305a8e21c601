// Parse (tuning/sweep/sweep_spec.h): --vary, --config, the whole argument list, the worker
// arguments that rebuild a definition, --trace-at conditions. Pure text, nothing runs.
#include "tuning/sweep/sweep_spec.h"

#include <gtest/gtest.h>

#include <string>
#include <tuple>
#include <vector>

#include "test/common/error_of.h"

namespace scw::tuning::sweep {
namespace {

using Values = std::vector<std::string>;

TEST(SweepParseTest, VaryList) {
  const SweepAxis a = ParseVary("gg_scale=1.0, 1.1,1.25");
  EXPECT_EQ(a.key, "gg_scale");
  EXPECT_EQ(a.values, (Values{"1.0", "1.1", "1.25"}));
  // Commas inside brackets belong to a list value.
  const SweepAxis b = ParseVary("grip.wheel_mu_x=[0.8, 1, 0.8, 1],[1,1,1,1]");
  EXPECT_EQ(b.values, (Values{"[0.8, 1, 0.8, 1]", "[1,1,1,1]"}));
  EXPECT_EQ(ParseVary("subsystems.esc=true,false").values, (Values{"true", "false"}));
  EXPECT_EQ(ParseVary("gg_scale=1.3").values, (Values{"1.3"}));
}

TEST(SweepParseTest, VaryRangeIsInclusiveWithTheArgumentsDecimals) {
  EXPECT_EQ(ParseVary("gg_scale=1.0:0.05:1.2").values, (Values{"1", "1.05", "1.1", "1.15", "1.2"}));
  // The stop is reached despite rounding (0.1 is not exact in binary).
  EXPECT_EQ(ParseVary("gg_scale=1.0:0.1:1.6").values.size(), 7u);
  EXPECT_EQ(ParseVary("gg_scale=1.0:0.1:1.6").values.back(), "1.6");
  // A stop between steps is not exceeded; descending ranges work.
  EXPECT_EQ(ParseVary("laps=1:2:6").values, (Values{"1", "3", "5"}));
  EXPECT_EQ(ParseVary("gg_scale=1.5:-0.25:1").values, (Values{"1.5", "1.25", "1"}));
  EXPECT_EQ(ParseVary("gg_scale=1.2:0.1:1.2").values, (Values{"1.2"}));
}

TEST(SweepParseTest, BadVaryNamesTheArgumentAndTheRule) {
  const std::pair<const char*, const char*> bad[] = {
      {"gg_scale", "key=v1,v2"},
      {"=1,2", "key=v1,v2"},
      {"gg_scale=", "key=v1,v2"},
      {"gg_scale=1:0:2", "must not be 0"},
      {"gg_scale=2:0.1:1", "sign"},
      {"gg_scale=1:x:2", "three finite numbers"},
      {"gg_scale=1,,2", "value 2 is empty"},
      {"gg_scale=0:1e-9:1", "more than"},
      {"config=a,b", "--config"},
  };
  for (const auto& [arg, rule] : bad) {
    const std::string msg = ErrorOf([&] { ParseVary(arg); });
    EXPECT_NE(msg.find(std::string("--vary ") + arg), std::string::npos) << arg << ": " << msg;
    EXPECT_NE(msg.find(rule), std::string::npos) << arg << ": " << msg;
  }
}

TEST(SweepParseTest, Config) {
  const SweepConfig c = ParseConfig("none:subsystems.esc=false, subsystems.cs=false");
  EXPECT_EQ(c.name, "none");
  EXPECT_EQ(c.overrides, (Values{"subsystems.esc=false", "subsystems.cs=false"}));
  EXPECT_TRUE(ParseConfig("esc+cs").overrides.empty());
  EXPECT_TRUE(ParseConfig("esc+cs:").overrides.empty());
  for (const char* arg : {":subsystems.esc=false", "no good:x=1", "a:subsystems.esc", "a:=1"}) {
    const std::string msg = ErrorOf([&] { ParseConfig(arg); });
    EXPECT_NE(msg.find(std::string("--config ") + arg), std::string::npos) << arg << ": " << msg;
  }
}

TEST(SweepParseTest, ArgumentsBecomeTheDefinitionInOrder) {
  SweepArguments a;
  a.scenario = "params/scenarios/default.yaml";
  a.overrides = {"laps=1", "motion.raceline=centerline"};
  a.stability = "params/stability/default.yaml";
  a.vary = {"gg_scale=1.0:0.1:1.2", "subsystems.cs=true,false"};
  a.configs = {"none:subsystems.esc=false,subsystems.cs=false", "all"};
  a.stop_at_first_abort = true;
  const SweepDefinition d = ParseSweepArguments(a);
  EXPECT_EQ(d.scenario_file, a.scenario);
  EXPECT_EQ(d.base_overrides, a.overrides);
  EXPECT_EQ(d.stability_file, a.stability);
  EXPECT_TRUE(d.stop_at_first_abort);
  ASSERT_EQ(d.axes.size(), 2u);
  EXPECT_EQ(d.axes[0].key, "gg_scale");  // the first --vary is the series axis
  EXPECT_EQ(d.axes[0].values, (Values{"1", "1.1", "1.2"}));
  EXPECT_EQ(d.axes[1].values, (Values{"true", "false"}));
  ASSERT_EQ(d.configs.size(), 2u);
  EXPECT_EQ(d.configs[0].name, "none");
  EXPECT_EQ(d.configs[0].overrides, (Values{"subsystems.esc=false", "subsystems.cs=false"}));
  EXPECT_EQ(d.configs[1].name, "all");

  // Nothing given: no axes, no configurations (ExpandSweep adds "default").
  const SweepDefinition empty = ParseSweepArguments({});
  EXPECT_TRUE(empty.axes.empty());
  EXPECT_TRUE(empty.configs.empty());
  EXPECT_FALSE(empty.stop_at_first_abort);
}

TEST(SweepParseTest, ArgumentsReportEveryMalformedVaryAndConfigAtOnce) {
  SweepArguments a;
  a.vary = {"gg_scale=1:0:2", "laps=1,2", "gg_scale"};
  a.configs = {"ok:laps=1", "a:subsystems.esc", "no good"};
  try {
    (void)ParseSweepArguments(a);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "scw sweep");
    ASSERT_EQ(e.problems().size(), 4u) << e.what();
    // Each problem is named after its argument as given, in the order given.
    EXPECT_EQ(e.problems()[0].path, "--vary gg_scale=1:0:2");
    EXPECT_NE(e.problems()[0].message.find("must not be 0"), std::string::npos);
    EXPECT_EQ(e.problems()[1].path, "--vary gg_scale");
    EXPECT_NE(e.problems()[1].message.find("key=v1,v2"), std::string::npos);
    EXPECT_EQ(e.problems()[2].path, "--config a:subsystems.esc");
    EXPECT_NE(e.problems()[2].message.find("override 'subsystems.esc'"), std::string::npos);
    EXPECT_EQ(e.problems()[3].path, "--config no good");
    const std::string what = e.what();
    EXPECT_NE(what.find("scw sweep: --vary gg_scale=1:0:2: the step"), std::string::npos) << what;
  }
}

// The worker processes get the definition as `scw sweep` arguments: parsed back, they give the
// same grid (ranges arrive expanded, list values keep their brackets).
TEST(SweepParseTest, TraceConditionsGroupByKeyInTheOrderFirstGiven) {
  const std::vector<SweepAxis> axes = {{"gg_scale", {"1", "1.1"}}, {"laps", {"1", "2"}}};
  const auto c =
      ParseTraceConditions(axes, {"laps=2", "config=esc", "laps=1", "gg_scale=1.10", "config=cs"});
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].axis, 1);
  EXPECT_EQ(c[0].values, (Values{"2", "1"}));
  EXPECT_EQ(c[1].axis, -1);  // the configuration name
  EXPECT_EQ(c[1].values, (Values{"esc", "cs"}));
  EXPECT_EQ(c[2].axis, 0);
  EXPECT_EQ(c[2].values, (Values{"1.10"}));
  EXPECT_TRUE(ParseTraceConditions(axes, {}).empty());
}

TEST(SweepParseTest, BadTraceConditionsAreAllNamed) {
  const std::vector<SweepAxis> axes = {{"gg_scale", {"1"}}};
  try {
    (void)ParseTraceConditions(axes, {"gg_scale", "=1", "laps=", "laps=1", "gg_scale=1"});
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.problems().size(), 4u) << e.what();
    EXPECT_EQ(e.problems()[0].path, "--trace-at gg_scale");
    EXPECT_NE(e.problems()[0].message.find("key=value"), std::string::npos);
    EXPECT_EQ(e.problems()[1].path, "--trace-at =1");
    EXPECT_EQ(e.problems()[2].path, "--trace-at laps=");
    EXPECT_EQ(e.problems()[3].path, "--trace-at laps=1");
    EXPECT_NE(e.problems()[3].message.find("neither config nor a varied key (config, gg_scale)"),
              std::string::npos)
        << e.problems()[3].message;
  }
}

TEST(SweepParseTest, ValuesCompareAsNumbersWhenBothAreNumbers) {
  const std::tuple<const char*, const char*, bool> rows[] = {
      {"1", "1.0", true},     {"1", "1e0", true},     {"100", "1e2", true},
      {"+1.5", "1.50", true}, {"1", "1.0001", false}, {"0.01", "0.010", true},
      {"esc", "esc", true},   {"esc", "ESC", false},  {"[1,1]", "[1, 1]", false},
      {"true", "true", true}, {"1", "one", false},    {"-0", "0", true},
  };
  for (const auto& [have, want, same] : rows)
    EXPECT_EQ(SameSweepValue(have, want), same) << have << " vs " << want;
}

}  // namespace
}  // namespace scw::tuning::sweep
