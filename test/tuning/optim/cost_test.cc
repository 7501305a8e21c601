#include "tuning/optim/cost.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace scw::tuning {
namespace {

RunMetrics Completed(double lap) {
  RunMetrics m;
  m.lap_times = {lap, lap, lap};
  m.laps_planned = 3;
  m.distance = m.distance_planned = 9000.0;
  return m;
}

TEST(CostTest, CompletedRunCostsItsLapTimePlusViolations) {
  params::CostWeights w;
  RunMetrics m = Completed(62.0);
  EXPECT_DOUBLE_EQ(ScenarioCost(m, w).total, 62.0);
  m.sideslip_excess_integral = 1.5;
  m.esc_brake_energy = 50000.0;
  const auto c = ScenarioCost(m, w);
  EXPECT_DOUBLE_EQ(c.sideslip, 1.5 * w.sideslip_weight);
  EXPECT_DOUBLE_EQ(c.brake_energy, 50.0 * w.brake_energy_weight);
  EXPECT_DOUBLE_EQ(c.total, 62.0 + c.sideslip + c.brake_energy);
}

TEST(CostTest, CleanScenariosChargeInterventionsCriticalOnesTheLargestSideslip) {
  params::CostWeights w;
  RunMetrics m = Completed(62.0);
  m.esc_brake_energy = 10000.0;     // 10 kJ
  m.abs_pressure_released = 200.0;  // bar·s
  m.tc_throttle_cut = 0.4;          // s of full throttle
  m.max_abs_sideslip = 9.0 * M_PI / 180.0;
  const CostBreakdown clean = ScenarioCost(m, w, false);
  EXPECT_DOUBLE_EQ(clean.brake_energy, 10.0 * w.brake_energy_weight);
  EXPECT_DOUBLE_EQ(clean.interventions, 200.0 * w.abs_release_weight + 0.4 * w.tc_cut_weight);
  EXPECT_EQ(clean.max_sideslip, 0.0);
  EXPECT_GT(clean.interventions, 0.0);
  const CostBreakdown critical = ScenarioCost(m, w, true);
  EXPECT_EQ(critical.brake_energy, 0.0);
  EXPECT_EQ(critical.interventions, 0.0);
  EXPECT_NEAR(critical.max_sideslip, (9.0 - w.sideslip_allowed_deg) * w.max_sideslip_weight, 1e-12);
  EXPECT_DOUBLE_EQ(critical.total, 62.0 + critical.max_sideslip);
  // Below the allowed angle nothing is charged.
  m.max_abs_sideslip = 0.5 * w.sideslip_allowed_deg * M_PI / 180.0;
  EXPECT_EQ(ScenarioCost(m, w, true).max_sideslip, 0.0);
}

TEST(CostTest, EveryAbortCostsMoreThanASlowCompletedRunAndEarlierIsWorse) {
  params::CostWeights w;
  RunMetrics slow = Completed(w.lap_time_cap - 1.0);
  RunMetrics late = Completed(60.0);
  late.status = RunStatus::kSideslip;
  late.lap_times = {60.0, 60.0};
  late.distance = 8900.0;
  RunMetrics early = late;
  early.lap_times.clear();
  early.distance = 500.0;
  EXPECT_LT(ScenarioCost(slow, w).total, ScenarioCost(late, w).total);
  EXPECT_LT(ScenarioCost(late, w).total, ScenarioCost(early, w).total);
}

TEST(CostTest, AlwaysFinite) {
  params::CostWeights w;
  RunMetrics m = Completed(60.0);
  m.sideslip_excess_integral = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(std::isfinite(ScenarioCost(m, w).total));
  m = Completed(std::nan(""));
  m.status = RunStatus::kNonFinite;
  m.distance = std::nan("");
  EXPECT_TRUE(std::isfinite(ScenarioCost(m, w).total));
}

TEST(CostTest, TotalIsTheWeightedSum) {
  params::CostWeights w;
  const auto a = ScenarioCost(Completed(60.0), w);
  const auto b = ScenarioCost(Completed(70.0), w);
  EXPECT_DOUBLE_EQ(TotalCost({a, b}, {1.0, 2.0}), 200.0);
  EXPECT_DOUBLE_EQ(TotalCost({a, b}, {}), 130.0);
}

TEST(CostTest, ManeuverCostsItsFailedCriteria) {
  params::CostWeights w;
  RunMetrics m;  // a maneuver: no laps
  m.criteria_checked = 24;
  EXPECT_DOUBLE_EQ(ScenarioCostOfKind(m, w, "maneuver").total, 0.0);  // all passed: no lap term
  // Two failed: one by 29 % of its limit (45 % against 35 %), one by more than its limit.
  m.criteria_failed = 2;
  m.criteria_miss = (45.0 - 35.0) / 35.0 + 1.0;
  m.sideslip_excess_integral = 0.5;
  const CostBreakdown c = ScenarioCostOfKind(m, w, "maneuver");
  EXPECT_DOUBLE_EQ(c.criteria, w.failed_criterion_weight * (2.0 + m.criteria_miss));
  EXPECT_DOUBLE_EQ(c.sideslip, 0.5 * w.sideslip_weight);
  EXPECT_EQ(c.lap_time, 0.0);
  EXPECT_DOUBLE_EQ(c.total, c.criteria + c.sideslip);
  m.status = RunStatus::kNonFinite;
  EXPECT_DOUBLE_EQ(ScenarioCostOfKind(m, w, "maneuver").abort,
                   w.abort_base + w.abort_progress_weight);
  // The other kinds are ScenarioCost's.
  const RunMetrics lap = Completed(61.0);
  EXPECT_DOUBLE_EQ(ScenarioCostOfKind(lap, w, "clean").total, ScenarioCost(lap, w).total);
  EXPECT_DOUBLE_EQ(ScenarioCostOfKind(lap, w, "critical").total, ScenarioCost(lap, w, true).total);
}

}  // namespace
}  // namespace scw::tuning
