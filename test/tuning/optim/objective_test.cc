// The tune's objectives (tuning/optim/objective.h) on evaluated sets made by hand: the clean-lap
// budget (lap loss, activations, aborts), the exact penalty's ranking, the sum.
#include "tuning/optim/objective.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace scw::tuning {
namespace {

RunMetrics Lap(double t, std::array<int, 4> acts = {0, 0, 0, 0}) {
  RunMetrics m;
  m.lap_times = {t};
  m.laps_planned = 1;
  m.distance = m.distance_planned = 1000.0;
  m.esc_count = acts[0];
  m.cs_count = acts[1];
  m.abs_count = acts[2];
  m.tc_count = acts[3];
  return m;
}

RunMetrics Lost(RunStatus s = RunStatus::kSideslip) {
  RunMetrics m;
  m.status = s;
  m.laps_planned = 1;
  m.distance = 300.0;
  m.distance_planned = 1000.0;
  return m;
}

/// A set on three scenarios: clean, critical, critical; `costs` are J_s.
SetEvaluation Set(const RunMetrics& clean, double c0, const RunMetrics& a, double c1,
                  const RunMetrics& b, double c2) {
  SetEvaluation e;
  e.runs = {clean, a, b};
  for (double c : {c0, c1, c2}) {
    CostBreakdown k;
    k.total = c;
    e.costs.push_back(k);
    e.total += c;
  }
  return e;
}

TuneObjective Objective(const SetEvaluation& base, CleanLapBudget b = {},
                        ObjectiveKind kind = ObjectiveKind::kConstrained) {
  return TuneObjective(kind, b, {"clean", "power_on", "rear_grip"},
                       {"clean", "critical", "critical"}, {}, params::CostWeights{}, base);
}

const SetEvaluation kBase = Set(Lap(69.0, {0, 13, 0, 0}), 69.0, Lost(), 450.0, Lap(72.0), 72.0);

TEST(ObjectiveTest, TheBaseMeetsItsOwnBudgetAndItsMeritIsItsStabilityCost) {
  const TuneObjective o = Objective(kBase);
  const ObjectiveValue& v = o.base_value();
  EXPECT_TRUE(v.within_budget());
  EXPECT_DOUBLE_EQ(v.stability, 522.0);
  EXPECT_DOUBLE_EQ(v.merit, 522.0);
  EXPECT_DOUBLE_EQ(v.lap_loss, 0.0);
  ASSERT_EQ(v.clean.size(), 1u);
  EXPECT_TRUE(v.clean[0].breach.empty());
}

// One row per edge of the budget: what breaks it and what does not.
TEST(ObjectiveTest, TheCleanLapBudgetHasItsEdges) {
  struct Row {
    const char* what;
    RunMetrics clean;
    bool within;
    const char* breach;
  };
  const std::vector<Row> rows = {
      {"faster", Lap(68.9, {0, 13, 0, 0}), true, ""},
      {"at the budget", Lap(69.05, {0, 13, 0, 0}), true, ""},
      {"0.31 s slower (the issue's TC case)", Lap(69.31, {0, 13, 0, 0}), false,
       "+0.310 s a lap over 0.05 s"},
      {"TC acting where the base does not", Lap(69.0, {0, 13, 0, 7}), false, "TC 7 > 0"},
      {"fewer CS activations", Lap(69.0, {0, 11, 0, 0}), true, ""},
      {"a clean lap aborts", Lost(RunStatus::kWheelLock), false, "aborts (wheel_lock)"},
  };
  const TuneObjective o = Objective(kBase);
  for (const Row& r : rows) {
    SCOPED_TRACE(r.what);
    const ObjectiveValue v = o.Of(Set(r.clean, 70.0, Lap(72.0), 72.0, Lap(72.0), 72.0));
    EXPECT_EQ(v.within_budget(), r.within);
    EXPECT_EQ(v.clean[0].breach, r.breach);
  }
}

// The exact penalty: whatever a set saves, outside the budget it ranks behind the base.
TEST(ObjectiveTest, EverySetOutsideTheBudgetRanksBehindTheBaseAndInsideByStability) {
  const TuneObjective o = Objective(kBase);
  const double base = o.base_value().merit;
  const ObjectiveValue saves_all_slow =
      o.Of(Set(Lap(69.31, {0, 13, 0, 7}), 70.0, Lap(72.0), 72.0, Lap(72.0), 72.0));
  const ObjectiveValue saves_all_within =
      o.Of(Set(Lap(69.02, {0, 13, 0, 0}), 69.0, Lap(72.5), 72.5, Lap(72.0), 72.0));
  EXPECT_FALSE(saves_all_slow.within_budget());
  EXPECT_GT(saves_all_slow.merit, base);
  EXPECT_TRUE(saves_all_within.within_budget());
  EXPECT_DOUBLE_EQ(saves_all_within.merit, 144.5);
  EXPECT_LT(saves_all_within.merit, base);
  // The further outside, the worse (the search finds its way back in).
  const ObjectiveValue further =
      o.Of(Set(Lap(69.5, {0, 13, 0, 7}), 70.0, Lap(72.0), 72.0, Lap(72.0), 72.0));
  EXPECT_GT(further.merit, saves_all_slow.merit);
}

TEST(ObjectiveTest, ACleanLapTheBaseLosesConstrainsNothing) {
  const SetEvaluation base = Set(Lost(), 400.0, Lap(72.0), 72.0, Lap(72.0), 72.0);
  const TuneObjective o = Objective(base);
  const ObjectiveValue v =
      o.Of(Set(Lap(75.0, {1, 1, 1, 1}), 75.0, Lap(72.0), 72.0, Lap(72.0), 72.0));
  EXPECT_TRUE(v.within_budget());
  EXPECT_FALSE(v.clean[0].base_completed);
}

TEST(ObjectiveTest, FreeActivationsAndNoBudgetLeaveOnlyTheAborts) {
  CleanLapBudget open;
  open.lap_s = std::numeric_limits<double>::infinity();
  open.interventions = false;
  const TuneObjective o = Objective(kBase, open);
  const ObjectiveValue slow =
      o.Of(Set(Lap(71.0, {0, 13, 0, 7}), 71.0, Lap(72.0), 72.0, Lap(72.0), 72.0));
  EXPECT_TRUE(slow.within_budget());
  EXPECT_DOUBLE_EQ(slow.lap_loss, 2.0);
  EXPECT_EQ(slow.extra_activations, 7);
  EXPECT_FALSE(o.Of(Set(Lost(), 400.0, Lap(72.0), 72.0, Lap(72.0), 72.0)).within_budget());
  EXPECT_NE(o.Describe().find("whatever it takes"), std::string::npos) << o.Describe();
}

TEST(ObjectiveTest, TheSumIsTheWeightedTotalOfEveryScenario) {
  const TuneObjective o = Objective(kBase, {}, ObjectiveKind::kSum);
  const SetEvaluation e = Set(Lap(69.31, {0, 13, 0, 7}), 70.0, Lap(72.0), 72.0, Lap(72.0), 72.0);
  EXPECT_DOUBLE_EQ(o.Of(e).merit, e.total);
  EXPECT_EQ(ObjectiveKindFromName("sum"), ObjectiveKind::kSum);
  EXPECT_EQ(ObjectiveKindFromName("constrained"), ObjectiveKind::kConstrained);
  EXPECT_THROW(ObjectiveKindFromName("pareto"), std::invalid_argument);
}

TEST(ObjectiveTest, TheCleanLapTableSaysWhatBreaksTheBudget) {
  const TuneObjective o = Objective(kBase);
  const ObjectiveValue v =
      o.Of(Set(Lap(69.31, {0, 13, 0, 7}), 70.0, Lap(72.0), 72.0, Lap(72.0), 72.0));
  const std::string md = CleanLapMarkdown(v, o.budget(), "tuned");
  EXPECT_NE(md.find("| clean | 69.000 | 69.310 | +0.310 | 0/13/0/0 -> 0/13/0/7 | **no**: "
                    "+0.310 s a lap over 0.05 s; TC 7 > 0 |"),
            std::string::npos)
      << md;
}

}  // namespace
}  // namespace scw::tuning
