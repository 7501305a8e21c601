// Expand (tuning/sweep/sweep_plan.h): the grid's run order, every run's scenario (override
// order), the shared resolutions, validation. Builds scenarios only; nothing runs.
#include "tuning/sweep/sweep_plan.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "params/io/write.h"
#include "test/common/error_of.h"

namespace scw::tuning::sweep {
namespace {

namespace fs = std::filesystem;

TEST(SweepGridTest, ConfigsTimesCartesianProductWithTheFirstAxisInnermost) {
  const std::vector<SweepAxis> axes = {{"gg_scale", {"1.0", "1.1", "1.2"}},
                                       {"grip.rear_mu_y", {"0.8", "1.0"}},
                                       {"laps", {"1", "2"}}};
  const auto g = ExpandGrid(axes, 2);
  ASSERT_EQ(g.size(), 2u * 3u * 2u * 2u);
  // Every combination exactly once.
  std::set<std::vector<int>> seen;
  for (const auto& p : g) {
    std::vector<int> key = p.value;
    key.push_back(p.config);
    EXPECT_TRUE(seen.insert(key).second);
  }
  // Series: contiguous blocks of the first axis in the given order, same other values.
  ASSERT_EQ(g.back().series, 2 * 2 * 2 - 1);
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(g[i].value[0], static_cast<int>(i % 3));
    EXPECT_EQ(g[i].series, static_cast<int>(i / 3));
    EXPECT_EQ(g[i].config, static_cast<int>(i / 12));
  }
  // Last axis faster than the second.
  EXPECT_EQ(g[3].value[2], 1);
  EXPECT_EQ(g[3].value[1], 0);
  EXPECT_EQ(g[6].value[1], 1);
  // No axes: one run per configuration, each its own series.
  const auto none = ExpandGrid({}, 3);
  ASSERT_EQ(none.size(), 3u);
  EXPECT_EQ(none[2].series, 2);
  EXPECT_EQ(none[2].config, 2);
}

TEST(SweepValidateTest, BadKeysAndValuesNameTheArgument) {
  SweepDefinition d;
  d.axes = {ParseVary("gg_sclae=1,2"), ParseVary("gg_scale=1.0,abc"), ParseVary("laps=1,1")};
  d.configs = {ParseConfig("esc:subsystems.ecs=false"), ParseConfig("x"), ParseConfig("x")};
  const std::string msg = ErrorOf([&] { ValidateSweep(d); });
  EXPECT_NE(msg.find("--vary gg_sclae=1,2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean gg_scale"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--vary gg_scale=1.0,abc"), std::string::npos) << msg;
  EXPECT_NE(msg.find("abc"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--vary laps=1,1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--config esc:subsystems.ecs=false"), std::string::npos) << msg;
  EXPECT_NE(msg.find("used twice"), std::string::npos) << msg;
}

TEST(SweepGridTest, AnAxisWithoutValuesHasNoRuns) {
  EXPECT_TRUE(ExpandGrid({{"gg_scale", {"1", "2"}}, {"laps", {}}}, 2).empty());
  EXPECT_TRUE(ExpandGrid({{"gg_scale", {"1", "2"}}}, 0).empty());
}

TEST(SweepExpandTest, RunsInGridOrderWithTheirPointsAndScenarios) {
  SweepDefinition d;
  d.base_overrides = {"laps=2", "gg_scale=1.1"};
  d.axes = {ParseVary("grip.rear_mu_y=0.8,1.0"), ParseVary("limit_fraction=0.6,0.7")};
  d.configs = {ParseConfig("a:laps=3"), ParseConfig("b")};
  const SweepPlan plan = ExpandSweep(d);
  const auto grid = ExpandGrid(d.axes, 2);
  ASSERT_EQ(plan.runs.size(), grid.size());
  ASSERT_EQ(plan.runs.size(), 8u);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const PlannedRun& run = plan.runs[i];
    EXPECT_EQ(run.point.config, grid[i].config) << i;
    EXPECT_EQ(run.point.value, grid[i].value) << i;
    EXPECT_EQ(run.point.series, grid[i].series) << i;
    // The base overrides, then the configuration's, then the axes'.
    EXPECT_EQ(run.spec.laps, run.point.config == 0 ? 3 : 2) << i;
    EXPECT_EQ(run.spec.gg_scale, 1.1) << i;
    EXPECT_EQ(run.spec.grip.rear_mu_y, run.point.value[0] == 0 ? 0.8 : 1.0) << i;
    EXPECT_EQ(run.spec.limit_fraction, run.point.value[1] == 0 ? 0.6 : 0.7) << i;
    EXPECT_EQ(params::ToPlainYaml(run.spec), params::ToPlainYaml(PointScenario(d, run.point)));
  }
  EXPECT_EQ(plan.axes()[0].key, "grip.rear_mu_y");
  ASSERT_EQ(plan.configs.size(), 2u);
  EXPECT_EQ(plan.configs[1].name, "b");
  EXPECT_EQ(plan.source, "built-in");
  EXPECT_EQ(plan.base_dir, "");
}

TEST(SweepExpandTest, AnAxisOverridesTheConfigurationAndTheBase) {
  SweepDefinition d;
  d.base_overrides = {"laps=2"};
  d.axes = {ParseVary("laps=4,5")};
  d.configs = {ParseConfig("a:laps=3")};
  const SweepPlan plan = ExpandSweep(d);
  ASSERT_EQ(plan.runs.size(), 2u);
  EXPECT_EQ(plan.runs[0].spec.laps, 4);
  EXPECT_EQ(plan.runs[1].spec.laps, 5);
}

TEST(SweepExpandTest, NoConfigurationIsOneNamedDefault) {
  SweepDefinition d;
  d.axes = {ParseVary("gg_scale=1.0,1.2")};
  const SweepPlan plan = ExpandSweep(d);
  ASSERT_EQ(plan.configs.size(), 1u);
  EXPECT_EQ(plan.configs[0].name, "default");
  EXPECT_TRUE(plan.configs[0].overrides.empty());
  EXPECT_TRUE(plan.definition.configs.empty());  // the definition stays as given
  ASSERT_EQ(plan.runs.size(), 2u);
  EXPECT_EQ(plan.runs[1].spec.gg_scale, 1.2);

  // No axes either: one run of the base scenario.
  const SweepPlan single = ExpandSweep({});
  ASSERT_EQ(single.runs.size(), 1u);
  EXPECT_TRUE(single.runs[0].point.value.empty());
}

TEST(SweepExpandTest, RunTimeKeysShareAResolution) {
  // subsystems.*, abort.*, laps and name are read by the closed loop only: one resolution per
  // gg_scale value (a planning key), numbered in the order of first use.
  SweepDefinition d;
  d.axes = {ParseVary("abort.max_lateral_error=100,0.01"), ParseVary("gg_scale=1.0,1.2"),
            ParseVary("laps=1,2")};
  d.configs = {ParseConfig("all"), ParseConfig("none:subsystems.esc=false,subsystems.cs=false")};
  const SweepPlan plan = ExpandSweep(d);
  ASSERT_EQ(plan.runs.size(), 16u);
  ASSERT_EQ(plan.resolutions.size(), 2u);
  std::set<int> used;
  for (const auto& run : plan.runs) {
    const int expected = run.point.value[1];  // gg_scale 1.0 comes first in run order
    EXPECT_EQ(run.resolution, expected);
    EXPECT_EQ(plan.resolutions[static_cast<std::size_t>(run.resolution)].gg_scale,
              run.spec.gg_scale);
    used.insert(run.resolution);
  }
  EXPECT_EQ(used.size(), 2u);
  // The stored scenario of a resolution is that of its first run.
  EXPECT_EQ(params::ToPlainYaml(plan.resolutions[0]), params::ToPlainYaml(plan.runs[0].spec));
}

TEST(SweepExpandTest, DeterministicAndTheStabilityFileBecomesAbsolute) {
  SweepDefinition d;
  d.base_overrides = {"laps=1"};
  d.stability_file = "params/stability/default.yaml";
  d.axes = {ParseVary("gg_scale=1.0:0.1:1.3"), ParseVary("subsystems.cs=true,false")};
  d.configs = {ParseConfig("x:subsystems.esc=false"), ParseConfig("y")};
  const SweepPlan a = ExpandSweep(d);
  const SweepPlan b = ExpandSweep(d);
  ASSERT_EQ(a.runs.size(), 16u);
  ASSERT_EQ(a.runs.size(), b.runs.size());
  for (std::size_t i = 0; i < a.runs.size(); ++i) {
    EXPECT_EQ(a.runs[i].point.value, b.runs[i].point.value);
    EXPECT_EQ(a.runs[i].resolution, b.runs[i].resolution);
    EXPECT_EQ(params::ToPlainYaml(a.runs[i].spec), params::ToPlainYaml(b.runs[i].spec));
    EXPECT_EQ(a.runs[i].spec.stability, fs::absolute(d.stability_file).string());
  }
  EXPECT_EQ(a.resolutions.size(), 4u);
}

TEST(SweepExpandTest, BadDefinitionsThrowBeforeAnyRun) {
  SweepDefinition d;
  d.axes = {ParseVary("gg_scale=1.0,abc")};
  const std::string msg = ErrorOf([&] { (void)ExpandSweep(d); });
  EXPECT_NE(msg.find("scw sweep: --vary gg_scale=1.0,abc: gg_scale"), std::string::npos) << msg;
  SweepDefinition twice;
  twice.axes = {ParseVary("laps=1,2"), ParseVary("laps=3")};
  EXPECT_NE(ErrorOf([&] { (void)ExpandSweep(twice); }).find("key 'laps' is varied twice"),
            std::string::npos);
  SweepDefinition bad_set;
  bad_set.base_overrides = {"lapz=1"};
  EXPECT_NE(ErrorOf([&] { (void)ExpandSweep(bad_set); }).find("lapz"), std::string::npos);
}

}  // namespace
}  // namespace scw::tuning::sweep
