// The critical situations of the default training set (tuning/scenario_set.cc, docs/scenarios.md):
// each fails without stability control, is survived with the car's shipped set, and the subsystem
// the documentation credits acts; and the set as a whole exercises all four subsystems.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "tuning/closed_loop.h"
#include "tuning/evaluator.h"
#include "tuning/scenario_set.h"

namespace scw::tuning {
namespace {

const ScenarioEntry& Training(const std::string& name) {
  static const ScenarioSet set = ScenarioSet::Default();
  for (const auto& e : set.training)
    if (e.name == name) return e;
  throw std::runtime_error("no training scenario " + name);
}

params::StabilityParams Without(params::StabilityParams p, const std::string& which) {
  if (which == "ESC" || which == "all") p.ESC.enabled = false;
  if (which == "CS" || which == "all") p.countersteer_system.enabled = false;
  if (which == "ABS" || which == "all") p.SlipControl.ABS.enabled = false;
  if (which == "TC" || which == "all") p.SlipControl.TC.enabled = false;
  return p;
}

int Count(const RunMetrics& m, const std::string& which) {
  if (which == "ESC") return m.esc_count;
  if (which == "CS") return m.cs_count;
  if (which == "ABS") return m.abs_count;
  return m.tc_count;
}

struct Critical {
  const char* name;
  std::vector<std::string> acts;  // documented in docs/scenarios.md
};

class CriticalScenarioTest : public ::testing::TestWithParam<Critical> {};

TEST_P(CriticalScenarioTest, FailsWithoutStabilityControlAndTheCreditedSubsystemsSaveIt) {
  const Critical& c = GetParam();
  const ResolvedScenario sc = Resolve(LoadEntry(Training(c.name), ""));
  EXPECT_EQ(sc.spec.kind, "critical");
  const RunMetrics off = RunClosedLoop(sc, Without(sc.stability, "all"));
  EXPECT_TRUE(off.aborted()) << c.name << " must fail without stability control";
  const RunMetrics on = RunClosedLoop(sc, sc.stability);
  ASSERT_EQ(on.status, RunStatus::kCompleted)
      << c.name << ": " << RunStatusName(on.status) << " at s = " << on.end_s;
  for (const std::string& s : c.acts) EXPECT_GT(Count(on, s), 0) << c.name << ": " << s;
}

INSTANTIATE_TEST_SUITE_P(DefaultTrainingSet, CriticalScenarioTest,
                         ::testing::Values(Critical{"power_on_c1", {"ESC", "CS", "TC"}},
                                           Critical{"power_on_c5", {"CS", "TC"}},
                                           Critical{"late_braking_c7", {"ABS"}},
                                           Critical{"wet_braking_c1", {"ABS"}},
                                           Critical{"rear_grip_loss_c5", {"TC"}}),
                         [](const auto& p) { return std::string(p.param.name); });

TEST(DefaultScenarioSetTest, EachSubsystemDecidesATrainingScenario) {
  // Disabling a subsystem turns a completed training run into an abort or changes its cost by at
  // least 5 % (the rule of docs/scenarios.md), for each of ESC, CS, ABS and TC.
  const ScenarioSet set = ScenarioSet::Default();
  const BatchEvaluator ev = BatchEvaluator::FromEntries(set.training, "", set.cost);
  const params::StabilityParams base = ev.scenarios().front().stability;
  const std::vector<std::string> subsystems = {"ESC", "CS", "ABS", "TC"};
  std::vector<params::StabilityParams> sets = {base};
  for (const auto& s : subsystems) sets.push_back(Without(base, s));
  const auto res = ev.Evaluate(sets);
  for (std::size_t k = 0; k < subsystems.size(); ++k) {
    std::string decides;
    for (std::size_t i = 0; i < ev.scenarios().size(); ++i) {
      const RunMetrics& a = res[0].runs[i];
      const RunMetrics& b = res[k + 1].runs[i];
      const double ja = res[0].costs[i].total, jb = res[k + 1].costs[i].total;
      if ((!a.aborted() && b.aborted()) || std::abs(jb - ja) >= 0.05 * ja)
        decides += ev.scenarios()[i].spec.name + " ";
    }
    EXPECT_FALSE(decides.empty()) << subsystems[k] << " decides no training scenario";
  }
  // The baseline survives every training scenario.
  for (std::size_t i = 0; i < ev.scenarios().size(); ++i)
    EXPECT_FALSE(res[0].runs[i].aborted()) << ev.scenarios()[i].spec.name;
}

}  // namespace
}  // namespace scw::tuning
