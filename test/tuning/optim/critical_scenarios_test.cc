// The critical situations of the default training set (tuning/sim/scenario_set.cc,
// docs/scenarios.md): each fails without stability control, the subsystems the documentation
// credits act with the car's shipped set, and the shipped set survives exactly the ones documented
// as survived; the set as a whole exercises all four subsystems.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test/tuning/optim/default_training.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/set_check.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {
namespace {

params::StabilityParams WithoutAny(params::StabilityParams p) {
  return ApplySubsystemSwitches(std::move(p), {false, false, false, false, false});
}

int Count(const RunMetrics& m, const std::string& which) {
  const int counts[] = {m.esc_count, m.cs_count, m.abs_count, m.tc_count};
  for (std::size_t k = 0; k < kCheckedSubsystems.size(); ++k)
    if (which == kCheckedSubsystems[k]) return counts[k];
  return -1;
}

struct Critical {
  const char* name;
  std::vector<std::string> acts;  // documented in docs/scenarios.md
  bool survived = true;           // with the shipped set
};

class CriticalScenarioTest : public ::testing::TestWithParam<Critical> {};

TEST_P(CriticalScenarioTest, FailsWithoutStabilityControlAndTheCreditedSubsystemsAct) {
  const Critical& c = GetParam();
  const ResolvedScenario sc = Resolve(LoadEntry(DefaultTraining(c.name), ""));
  EXPECT_EQ(sc.spec.kind, "critical");
  const RunMetrics off = RunClosedLoop(sc, WithoutAny(sc.stability));
  EXPECT_TRUE(off.aborted()) << c.name << " must fail without stability control";
  const RunMetrics on = RunClosedLoop(sc, sc.stability);
  EXPECT_EQ(on.status == RunStatus::kCompleted, c.survived)
      << c.name << ": " << RunStatusName(on.status) << " at s = " << on.end_s;
  for (const std::string& s : c.acts) EXPECT_GT(Count(on, s), 0) << c.name << ": " << s;
}

INSTANTIATE_TEST_SUITE_P(
    DefaultTrainingSet, CriticalScenarioTest,
    ::testing::Values(Critical{"power_on_c1_apex", {"ESC", "ABS", "TC"}, false},
                      Critical{"power_on_c1", {"ESC", "CS", "ABS", "TC"}},
                      Critical{"power_on_c3_apex", {"ESC", "CS", "TC"}, false},
                      Critical{"power_on_c3", {"ESC", "CS", "ABS", "TC"}},
                      Critical{"power_on_c5_apex", {"CS", "ABS", "TC"}},
                      Critical{"power_on_c7", {"ESC", "CS", "TC"}, false},
                      Critical{"power_on_c8_apex", {"ESC", "CS", "TC"}, false},
                      Critical{"power_on_c8", {"CS", "TC"}}, Critical{"late_braking_c1", {"ABS"}},
                      Critical{"late_braking_c5", {"ABS"}}, Critical{"late_braking_c7", {"ABS"}},
                      Critical{"late_braking_c8", {"ESC", "ABS", "TC"}},
                      Critical{"wet_braking_c1", {"ABS"}},
                      Critical{"rear_grip_loss_c3", {"ESC", "CS", "TC"}, false},
                      Critical{"rear_grip_loss_c5", {"TC"}},
                      Critical{"rear_grip_loss_c9", {"ESC", "ABS", "TC"}}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(DefaultScenarioSetTest, EachSubsystemDecidesATrainingScenario) {
  // For each of ESC, CS, ABS and TC, disabling it changes the outcome of a training run or its
  // cost by at least 5 % (CheckSet's rule, the one scw tune --check-set and docs/scenarios.md use).
  const ScenarioSet set = ScenarioSet::Default();
  const BatchEvaluator ev = BatchEvaluator::FromEntries(set.training, "", set.cost);
  const SetCheck c = CheckSet(ev, ev.scenarios().front().stability);
  for (std::size_t k = 0; k < kCheckedSubsystems.size(); ++k)
    EXPECT_GT(c.deciding[k], 0) << kCheckedSubsystems[k] << " decides no training scenario";
  // The baseline survives both clean laps (a critical one it may not: see CriticalScenarioTest).
  for (const ScenarioCheck& sc : c.scenarios) {
    if (sc.name.rfind("clean_", 0) == 0) {
      EXPECT_FALSE(sc.base.aborted()) << sc.name;
    }
  }
}

}  // namespace
}  // namespace scw::tuning
