// The held-out verdict (tuning/optim/comparison.h: CompareSets, SetChangeMarkdown): per scenario
// class, against the stated noise threshold.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "tuning/optim/comparison.h"
#include "tuning/optim/evaluator.h"

namespace scw::tuning {
namespace {

RunMetrics Completed(double lap) {
  RunMetrics m;
  m.lap_times = {lap, lap};
  m.laps_planned = 2;
  m.distance_planned = m.distance = 10000.0;
  return m;
}

RunMetrics Aborted(RunStatus s, double progress) {
  RunMetrics m;
  m.status = s;
  m.laps_planned = 2;
  m.distance_planned = 10000.0;
  m.distance = progress * m.distance_planned;
  return m;
}

struct RunAndCost {
  RunMetrics m;
  double cost;
};

SetEvaluation Set(const std::vector<RunAndCost>& runs) {
  SetEvaluation s;
  for (const auto& r : runs) {
    s.runs.push_back(r.m);
    CostBreakdown c;
    c.total = r.cost;
    s.costs.push_back(c);
    s.total += r.cost;
  }
  return s;
}

std::vector<std::string> Names(std::size_t n) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back("s" + std::to_string(i));
  return out;
}

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Issue 47: the simulation is deterministic, so no percentage noise threshold: a change is judged
// in seconds (two 100 Hz steps by default), whatever the cost's size.
TEST(SetChangeTest, AChangeIsJudgedInSecondsNotInPercent) {
  EXPECT_DOUBLE_EQ(kDefaultResolution, 0.02);
  // +0.31 s on a 72 s lap was "no significant change" at 0.5 % of the cost; now it is worse.
  const SetEvaluation base = Set({{Completed(72.0), 72.0}});
  const SetEvaluation slower = Set({{Completed(72.31), 72.31}});
  const SetChange c = CompareSets(Names(1), {}, base, slower);
  EXPECT_EQ(c.scenarios[0].change, CostChange::kWorse);
  EXPECT_EQ(c.verdict, Verdict::kWorse);
  EXPECT_DOUBLE_EQ(c.scenarios[0].threshold, 0.02);
  // Below the resolution: no change; another resolution moves the line.
  EXPECT_EQ(CompareSets(Names(1), {}, base, Set({{Completed(72.01), 72.01}})).verdict,
            Verdict::kNoSignificantChange);
  EXPECT_EQ(CompareSets(Names(1), {}, base, slower, 0.5).verdict, Verdict::kNoSignificantChange);
}

// One row per class edge: outcome before/after → class and the change it forces.
TEST(SetChangeTest, ClassifiesEveryOutcomeChange) {
  struct Row {
    RunMetrics before, after;
    double cost_before, cost_after;
    OutcomeChange outcome;
    CostChange change;
  };
  const std::vector<Row> rows = {
      {Completed(70), Completed(69), 70, 69, OutcomeChange::kCompletedBoth, CostChange::kBetter},
      {Completed(70), Completed(71), 70, 71, OutcomeChange::kCompletedBoth, CostChange::kWorse},
      {Completed(70), Completed(70.01), 70, 70.01, OutcomeChange::kCompletedBoth,
       CostChange::kNoSignificantChange},
      {Aborted(RunStatus::kSideslip, 0.4), Aborted(RunStatus::kSideslip, 0.5), 320, 300,
       OutcomeChange::kAbortedBoth, CostChange::kBetter},
      {Aborted(RunStatus::kSideslip, 0.5), Aborted(RunStatus::kWheelLock, 0.4), 300, 320,
       OutcomeChange::kAbortedBoth, CostChange::kWorse},
      // A new abort is worse and a fixed one better whatever the costs say.
      {Completed(70), Aborted(RunStatus::kOffTrack, 0.99), 70, 70, OutcomeChange::kNewAbort,
       CostChange::kWorse},
      {Aborted(RunStatus::kOffTrack, 0.99), Completed(70), 70, 70, OutcomeChange::kAbortFixed,
       CostChange::kBetter},
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    SCOPED_TRACE(i);
    const auto& r = rows[i];
    const SetChange c =
        CompareSets({"x"}, {}, Set({{r.before, r.cost_before}}), Set({{r.after, r.cost_after}}));
    ASSERT_EQ(c.scenarios.size(), 1u);
    EXPECT_EQ(c.scenarios[0].outcome, r.outcome);
    EXPECT_EQ(c.scenarios[0].change, r.change);
    EXPECT_DOUBLE_EQ(c.scenarios[0].threshold, kDefaultResolution);
  }
}

// Issue 15: a 0.1 % change of the total made of one later abort and one worse scenario was
// reported as "the tuned set improves the cost".
TEST(SetChangeTest, SmallTotalChangeOfALaterAbortAndAWorseScenarioIsNotAnImprovement) {
  const SetEvaluation base = Set({{Completed(60.0), 60.0},
                                  {Aborted(RunStatus::kSideslip, 0.40), 320.0},
                                  {Completed(70.0), 70.0}});
  const SetEvaluation tuned = Set({{Completed(60.01), 60.01},
                                   {Aborted(RunStatus::kSideslip, 0.50), 300.0},
                                   {Completed(89.56), 89.56}});
  const SetChange c = CompareSets(Names(3), {}, base, tuned);
  EXPECT_NEAR((c.total_after - c.total_before) / c.total_before, -0.001, 1e-4);
  EXPECT_EQ(c.total_change, CostChange::kBetter);
  EXPECT_EQ(c.better, 1);
  EXPECT_EQ(c.worse, 1);
  EXPECT_EQ(c.verdict, Verdict::kMixed);
  const std::string md = SetChangeMarkdown("Held-out", c);
  EXPECT_FALSE(Has(md, "improves")) << md;
  EXPECT_TRUE(Has(md, "**Held-out verdict: mixed** (better in 1 scenario, worse in 1 scenario)"))
      << md;
  EXPECT_TRUE(
      Has(md, "Total cost 450.000 -> 449.570: -0.430 (-0.10 %), better (resolution 0.02 s)"))
      << md;
  // The change per class: completed in both (+19.570: 0 better, 1 no change, 1 worse), aborted in
  // both (-20.000, the abort comes later).
  EXPECT_TRUE(Has(md, "| completed in both | 2 | +19.570 | 0 | 1 | 1 |")) << md;
  EXPECT_TRUE(Has(md, "| aborted in both | 1 | -20.000 | 1 | 0 | 0 |")) << md;
  EXPECT_TRUE(Has(md, "sideslip at 50.0 % of the distance (later)")) << md;
  EXPECT_TRUE(Has(md, "no significant change (< 0.020)")) << md;
  EXPECT_TRUE(Has(md, "smaller than 0.02 s, two steps of the 100 Hz controllers")) << md;
}

TEST(SetChangeTest, ChangesBelowTheResolutionAreNoSignificantChange) {
  const SetEvaluation base = Set({{Completed(60.0), 60.0}, {Completed(70.0), 70.0}});
  const SetEvaluation tuned = Set({{Completed(59.99), 59.99}, {Completed(70.005), 70.005}});
  const SetChange c = CompareSets(Names(2), {}, base, tuned);
  EXPECT_EQ(c.verdict, Verdict::kNoSignificantChange);
  EXPECT_EQ(c.better + c.worse, 0);
  EXPECT_TRUE(Has(SetChangeMarkdown("Held-out", c), "**Held-out verdict: no significant change**"));
}

TEST(SetChangeTest, SignificantGainWithNothingWorseImproves) {
  const SetEvaluation base = Set({{Completed(60.0), 60.0}, {Completed(70.0), 70.0}});
  const SetEvaluation tuned = Set({{Completed(59.5), 59.5}, {Completed(70.01), 70.01}});
  const SetChange c = CompareSets(Names(2), {}, base, tuned);
  EXPECT_EQ(c.verdict, Verdict::kImproves);
  EXPECT_TRUE(Has(SetChangeMarkdown("Held-out", c),
                  "**Held-out verdict: the tuned set improves the cost** (better in 1 scenario, "
                  "worse in none)"));
}

// Gains among runs that abort with both sets are real but do not make those scenarios drivable.
TEST(SetChangeTest, AnImprovementOnlyAmongAbortsSaysSo) {
  const SetEvaluation base =
      Set({{Completed(60.0), 60.0}, {Aborted(RunStatus::kSideslip, 0.1), 500.0}});
  const SetEvaluation tuned =
      Set({{Completed(60.0), 60.0}, {Aborted(RunStatus::kSideslip, 0.3), 460.0}});
  const SetChange c = CompareSets(Names(2), {}, base, tuned);
  EXPECT_EQ(c.verdict, Verdict::kImproves);
  const std::string md = SetChangeMarkdown("Held-out", c);
  EXPECT_TRUE(Has(md, "(better in 1 scenario, worse in none; that scenario aborts with both sets"))
      << md;
  EXPECT_TRUE(Has(md, "it does not make it drivable).")) << md;
}

TEST(SetChangeTest, SignificantLossWithNothingBetterIsWorse) {
  const SetEvaluation base = Set({{Completed(60.0), 60.0}, {Completed(70.0), 70.0}});
  const SetEvaluation tuned = Set({{Completed(61.0), 61.0}, {Completed(70.0), 70.0}});
  const SetChange c = CompareSets(Names(2), {}, base, tuned);
  EXPECT_EQ(c.verdict, Verdict::kWorse);
  const std::string md = SetChangeMarkdown("Held-out", c);
  EXPECT_TRUE(Has(md, "the tuned set is WORSE** (worse in 1 scenario, better in 0 scenarios)"));
  EXPECT_TRUE(Has(md, "review before using it on the car"));
}

TEST(SetChangeTest, ANewAbortMakesTheVerdictWorseEvenWhenAnotherAbortIsFixed) {
  const SetEvaluation base =
      Set({{Aborted(RunStatus::kWheelLock, 0.2), 360.0}, {Completed(70.0), 70.0}});
  const SetEvaluation tuned =
      Set({{Completed(60.0), 60.0}, {Aborted(RunStatus::kSideslip, 0.95), 210.0}});
  const SetChange c = CompareSets(Names(2), {}, base, tuned);
  EXPECT_EQ(c.total_change, CostChange::kBetter);
  EXPECT_EQ(c.new_aborts, 1);
  EXPECT_EQ(c.verdict, Verdict::kWorse);
  const std::string md = SetChangeMarkdown("Held-out", c);
  EXPECT_TRUE(Has(md, "(1 scenario completed by the baseline aborts with the tuned set)")) << md;
  EXPECT_TRUE(Has(md, "| completed -> aborted | 1 |")) << md;
  EXPECT_TRUE(Has(md, "| aborted -> completed | 1 |")) << md;
}

// Each scenario's change is below the resolution, but together they exceed it.
TEST(SetChangeTest, SmallGainsThatAddUpBeyondTheResolutionImprove) {
  std::vector<RunAndCost> before, after;
  for (int i = 0; i < 10; ++i) {
    before.push_back({Completed(2.0), 2.0});
    after.push_back({Completed(1.99), 1.99});
  }
  const SetChange c = CompareSets(Names(10), {}, Set(before), Set(after));
  EXPECT_EQ(c.better + c.worse, 0);
  EXPECT_EQ(c.total_change, CostChange::kBetter);
  EXPECT_EQ(c.verdict, Verdict::kImproves);
}

TEST(SetChangeTest, UsesTheEvaluatorsNamesAndWeights) {
  std::vector<ResolvedScenario> scenarios(2);
  scenarios[0].spec.name = "nominal_gg1.1";
  scenarios[1].spec.name = "mu_split_left";
  const BatchEvaluator ev(scenarios, {2.0, 1.0}, params::CostWeights{}, 1);
  SetEvaluation base = Set({{Completed(60.0), 60.0}, {Completed(70.0), 70.0}});
  SetEvaluation tuned = Set({{Completed(59.0), 59.0}, {Completed(70.0), 70.0}});
  base.total = 190.0;
  tuned.total = 188.0;
  const SetChange c = CompareSets(ev, base, tuned);
  ASSERT_EQ(c.scenarios.size(), 2u);
  EXPECT_EQ(c.scenarios[0].scenario, "nominal_gg1.1");
  EXPECT_DOUBLE_EQ(c.scenarios[0].weight, 2.0);
  const std::string md = SetChangeMarkdown("Held-out", c);
  EXPECT_TRUE(Has(md, "cost change (weighted)")) << md;
  EXPECT_TRUE(Has(md, "| completed in both | 2 | -2.000 | 1 | 1 | 0 |")) << md;
  EXPECT_TRUE(Has(md,
                  "| nominal_gg1.1 | completed in both | completed, mean lap 60.000 s | "
                  "completed, mean lap 59.000 s | 60.000 -> 59.000 | -1.000 (-1.67 %) | "
                  "better |"))
      << md;
}

TEST(SetChangeTest, VerdictNamesAreStable) {
  EXPECT_STREQ(VerdictName(Verdict::kImproves), "improves");
  EXPECT_STREQ(VerdictName(Verdict::kNoSignificantChange), "no_significant_change");
  EXPECT_STREQ(VerdictName(Verdict::kWorse), "worse");
  EXPECT_STREQ(VerdictName(Verdict::kMixed), "mixed");
}

TEST(SetChangeTest, MismatchedInputsThrow) {
  const SetEvaluation one = Set({{Completed(60.0), 60.0}});
  const SetEvaluation two = Set({{Completed(60.0), 60.0}, {Completed(70.0), 70.0}});
  EXPECT_THROW(CompareSets(Names(1), {}, one, two), std::invalid_argument);
  EXPECT_THROW(CompareSets(Names(2), {1.0}, two, two), std::invalid_argument);
}

// The distribution of the scenario costs: mean, 90th percentile by nearest rank, worst, aborts;
// by hand for ten scenarios (the 9th smallest is the 90th percentile).
TEST(SetChangeTest, DistributionGivesMeanNinetiethPercentileWorstAndAborts) {
  std::vector<RunAndCost> before, after;
  for (int i = 1; i <= 10; ++i) {
    before.push_back({Completed(60.0), 60.0 + i});
    after.push_back({i == 10 ? Aborted(RunStatus::kSideslip, 0.5) : Completed(60.0),
                     i == 10 ? 300.0 : 60.0 + 0.5 * i});
  }
  const SetChange c = CompareSets(Names(10), {}, Set(before), Set(after));
  const CostDistribution b = Distribution(c, false), t = Distribution(c, true);
  EXPECT_DOUBLE_EQ(b.mean, 65.5);
  EXPECT_DOUBLE_EQ(b.p90, 69.0);
  EXPECT_DOUBLE_EQ(b.worst, 70.0);
  EXPECT_EQ(b.aborts, 0);
  EXPECT_DOUBLE_EQ(t.p90, 64.5);
  EXPECT_DOUBLE_EQ(t.worst, 300.0);
  EXPECT_EQ(t.aborts, 1);
  // One evaluated set alone (`scw evaluate`'s summary) gives the same distribution.
  const CostDistribution alone = Distribution(Set(after));
  EXPECT_DOUBLE_EQ(alone.mean, t.mean);
  EXPECT_DOUBLE_EQ(alone.p90, t.p90);
  EXPECT_DOUBLE_EQ(alone.worst, t.worst);
  EXPECT_EQ(alone.aborts, t.aborts);
  EXPECT_TRUE(
      Has(SetChangeMarkdown("Held-out", c), "| tuned | 86.250 | 64.500 | 300.000 | 1 of 10 |"))
      << SetChangeMarkdown("Held-out", c);
}

}  // namespace
}  // namespace scw::tuning
