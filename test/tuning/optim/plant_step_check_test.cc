// The search step's check (tuning/optim/plant_step_check.h) on synthetic runs: each rule at its
// bound and just past it, outcome classes, subsystems acting at one step only, the total cost, and
// the overrides that set the step.
#include "tuning/optim/plant_step_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace scw::tuning {
namespace {

constexpr double kPi = 3.14159265358979323846;

RunMetrics Completed(double lap, double beta_deg) {
  RunMetrics m;
  m.status = RunStatus::kCompleted;
  m.lap_times = {lap};
  m.laps_planned = 1;
  m.distance = m.distance_planned = 1000.0;
  m.max_abs_sideslip = beta_deg * kPi / 180.0;
  m.cs_count = 3;
  return m;
}

RunMetrics Aborted(RunStatus status, double progress) {
  RunMetrics m;
  m.status = status;
  m.laps_planned = 1;
  m.distance_planned = 1000.0;
  m.distance = progress * 1000.0;
  m.max_abs_sideslip = 20.0 * kPi / 180.0;
  m.esc_count = 1;
  return m;
}

SetEvaluation Set(std::vector<RunMetrics> runs, double total) {
  SetEvaluation e;
  e.runs = std::move(runs);
  e.total = total;
  return e;
}

PlantStepCheck Check(const RunMetrics& fine, const RunMetrics& coarse, double fine_total = 100.0,
                     double coarse_total = 100.0) {
  return ComparePlantSteps(0.002, {"s"}, Set({fine}, fine_total), Set({coarse}, coarse_total));
}

TEST(PlantStepCheck, EqualRunsPass) {
  const PlantStepCheck c = Check(Completed(70.0, 4.0), Completed(70.0, 4.0));
  EXPECT_TRUE(c.ran);
  EXPECT_TRUE(c.passed);
  EXPECT_EQ(c.used(), 0.002);
  EXPECT_EQ(c.Verdict(), "passed");
  EXPECT_EQ(c.Passing(), 1);
}

TEST(PlantStepCheck, LapTimeWithinItsBoundPassesAndBeyondFails) {
  EXPECT_TRUE(Check(Completed(70.0, 4.0), Completed(70.09, 4.0)).passed);
  const PlantStepCheck c = Check(Completed(70.0, 4.0), Completed(70.11, 4.0));
  EXPECT_FALSE(c.passed);
  EXPECT_EQ(c.used(), 0.0);
  ASSERT_EQ(c.scenarios.size(), 1u);
  ASSERT_EQ(c.scenarios[0].failures.size(), 1u);
  EXPECT_NE(c.scenarios[0].failures[0].find("lap time"), std::string::npos);
}

TEST(PlantStepCheck, MaxSideslipWithinOneDegreePasses) {
  EXPECT_TRUE(Check(Completed(70.0, 4.0), Completed(70.0, 4.99)).passed);
  const PlantStepCheck c = Check(Completed(70.0, 4.0), Completed(70.0, 5.01));
  EXPECT_FALSE(c.passed);
  EXPECT_NE(c.scenarios[0].failures[0].find("max |beta|"), std::string::npos);
}

TEST(PlantStepCheck, TheAbortRuleThatTripsFirstInASpinMayDifferButNotTheClass) {
  // A spin ends by sideslip at one step and by lateral error at the other: the same outcome.
  EXPECT_TRUE(
      Check(Aborted(RunStatus::kSideslip, 0.26), Aborted(RunStatus::kLateralError, 0.27)).passed);
  EXPECT_EQ(OutcomeClass(RunStatus::kOffTrack), OutcomeClass(RunStatus::kSideslip));
  EXPECT_EQ(OutcomeClass(RunStatus::kWheelLock), OutcomeClass(RunStatus::kWheelSpin));
  // A lock-up is not a spin, and a completed run is not an abort.
  const PlantStepCheck lock =
      Check(Aborted(RunStatus::kSideslip, 0.26), Aborted(RunStatus::kWheelLock, 0.26));
  EXPECT_FALSE(lock.passed);
  EXPECT_NE(lock.scenarios[0].failures[0].find("outcome"), std::string::npos);
  EXPECT_FALSE(Check(Completed(70.0, 4.0), Aborted(RunStatus::kOffTrack, 0.9)).passed);
}

TEST(PlantStepCheck, AbortPointWithinTwoPercentOfTheDistance) {
  EXPECT_TRUE(
      Check(Aborted(RunStatus::kSideslip, 0.260), Aborted(RunStatus::kSideslip, 0.279)).passed);
  EXPECT_FALSE(
      Check(Aborted(RunStatus::kSideslip, 0.260), Aborted(RunStatus::kSideslip, 0.281)).passed);
}

TEST(PlantStepCheck, ASubsystemActingAtOneStepOnlyFails) {
  RunMetrics coarse = Completed(70.0, 4.0);
  coarse.cs_count = 5;  // more activations of one that acts at both: allowed
  EXPECT_TRUE(Check(Completed(70.0, 4.0), coarse).passed);
  coarse.abs_count = 1;  // ABS acts only at the search step
  const PlantStepCheck c = Check(Completed(70.0, 4.0), coarse);
  EXPECT_FALSE(c.passed);
  EXPECT_NE(c.scenarios[0].failures[0].find("ABS acts at one step only"), std::string::npos);
}

TEST(PlantStepCheck, TotalCostWithinOnePercent) {
  EXPECT_TRUE(Check(Completed(70.0, 4.0), Completed(70.0, 4.0), 100.0, 100.99).passed);
  const PlantStepCheck c = Check(Completed(70.0, 4.0), Completed(70.0, 4.0), 100.0, 101.01);
  EXPECT_FALSE(c.passed);
  EXPECT_EQ(c.Passing(), 1);  // every scenario alike, the sum is not
}

TEST(PlantStepCheck, TolerancesAreTheCallersChoice) {
  PlantStepTolerances strict;
  strict.lap_time_s = 0.0;
  const PlantStepCheck c = ComparePlantSteps(0.002, {"s"}, Set({Completed(70.0, 4.0)}, 100.0),
                                             Set({Completed(70.001, 4.0)}, 100.0), strict);
  EXPECT_FALSE(c.passed);
}

TEST(PlantStepCheck, ReportsNameTheStepTheVerdictAndEveryScenario) {
  const PlantStepCheck c = Check(Completed(70.0, 4.0), Completed(70.5, 4.0));
  const std::string line = PlantStepCheckLine(c);
  EXPECT_NE(line.find("2 ms"), std::string::npos) << line;
  EXPECT_NE(line.find("failed"), std::string::npos) << line;
  EXPECT_NE(line.find("own step instead"), std::string::npos) << line;
  const std::string md = PlantStepCheckMarkdown(c);
  EXPECT_NE(md.find("## Search plant step"), std::string::npos);
  EXPECT_NE(md.find("| s | completed / completed |"), std::string::npos) << md;
  PlantStepCheck none;
  EXPECT_EQ(none.Verdict(), "not run");
  EXPECT_EQ(none.used(), 0.0);
}

TEST(PlantStepCheck, TheStepIsAnOverrideAppendedToEveryEntry) {
  std::vector<ScenarioEntry> entries = {{"a", 1.0, "", {"laps=1"}}, {"b", 2.0, "x.yaml", {}}};
  const auto with = WithPlantStep(entries, 0.002);
  ASSERT_EQ(with.size(), 2u);
  EXPECT_EQ(with[0].overrides, (std::vector<std::string>{"laps=1", "plant_step=0.002"}));
  EXPECT_EQ(with[1].overrides, (std::vector<std::string>{"plant_step=0.002"}));
  EXPECT_EQ(with[1].file, "x.yaml");
  EXPECT_EQ(with[1].weight, 2.0);
}

}  // namespace
}  // namespace scw::tuning
