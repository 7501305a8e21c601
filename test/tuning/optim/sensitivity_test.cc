// Parameter sensitivity (issue 16 part 4): the perturbed points around a point of the tuning
// space, and the flag for a parameter the scenario set cannot see.
#include "tuning/optim/sensitivity.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "params/io/write.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning {
namespace {

using params::StabilityParams;

// Two dimensions: the TC activation threshold (8 %, step 0.1 %) and the countersteer gain (1.0,
// step 0.01), both direct.
ParameterSpace TwoDimensions(double tc_hi = 20.0) {
  return ParameterSpace("two", {{"SlipControl.TC.rear.slip_threshold_hold_reduce", -1, 3.0, tc_hi,
                                 params::Scale::kLinear, Transform::kDirect, "", -1},
                                {"countersteer_system.steering_factor", -1, 0.3, 1.5,
                                 params::Scale::kLinear, Transform::kDirect, "", -1}});
}

TEST(SensitivityPlanTest, MovesOneParameterAtATimeByOneStepAndTenPercent) {
  const StabilityParams base;
  const ParameterSpace space = TwoDimensions();
  const SensitivityPlan plan = PlanSensitivity(space, space.Encode(base), base);
  ASSERT_EQ(plan.points.size(), 2u);
  ASSERT_EQ(plan.sets.size(), 9u);  // the centre and 2 × 4 distinct sets
  EXPECT_TRUE(params::DifferingKeys(plan.sets[0], base).empty());
  const std::array<double, 4> tc = {7.2, 7.9, 8.1, 8.8};
  const std::array<double, 4> cs = {0.9, 0.99, 1.01, 1.1};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(plan.points[0][k].kind, PerturbationKind::kEvaluated) << k;
    EXPECT_EQ(plan.points[0][k].value, tc[k]) << k;
    EXPECT_EQ(plan.points[1][k].value, cs[k]) << k;
    // Only the perturbed key differs from the centre.
    const auto changed = params::DifferingKeys(
        plan.sets[static_cast<std::size_t>(plan.points[0][k].set)], plan.sets[0]);
    EXPECT_EQ(changed, std::set<std::string>{"SlipControl.TC.rear.slip_threshold_hold_reduce"});
  }
}

TEST(SensitivityPlanTest, ReportsPerturbationsClampedAtABoundOrDuplicated) {
  const StabilityParams base;
  // The range ends at the base value 8 %: both upward moves sit at the bound.
  const ParameterSpace space = TwoDimensions(8.0);
  const SensitivityPlan plan = PlanSensitivity(space, space.Encode(base), base);
  EXPECT_EQ(plan.points[0][2].kind, PerturbationKind::kAtBound);
  EXPECT_EQ(plan.points[0][3].kind, PerturbationKind::kAtBound);
  EXPECT_EQ(plan.points[0][0].kind, PerturbationKind::kEvaluated);
  EXPECT_EQ(plan.sets.size(), 7u);
  // A 10 % move smaller than the resolution quantises to the same set as one step.
  const ParameterSpace tiny("tiny", {{"countersteer_system.steering_factor", -1, 0.0, 1.5,
                                      params::Scale::kLinear, Transform::kDirect, "", -1}});
  StabilityParams small = base;
  small.countersteer_system.steering_factor = 0.05;  // 10 % = 0.005 < step 0.01
  const SensitivityPlan p2 = PlanSensitivity(tiny, tiny.Encode(small), small);
  EXPECT_NE(p2.points[0][0].kind, PerturbationKind::kEvaluated);
  EXPECT_NE(p2.points[0][3].kind, PerturbationKind::kEvaluated);
  EXPECT_EQ(p2.points[0][1].value, 0.04);
  EXPECT_EQ(p2.points[0][2].value, 0.06);
}

TEST(SensitivityTest, FlagsTheTractionControlThresholdOnASetWithoutTractionControl) {
  // One nominal lap with TC switched off in the scenario: no TC parameter can act, whatever its
  // value. Countersteer acts on every lap of the nominal scenario.
  const ResolvedScenario sc =
      Resolve(DefaultScenario({"gg_scale=1.2", "laps=1", "subsystems.tc=false"}));
  const StabilityParams base;
  const ParameterSpace space = TwoDimensions();
  const std::vector<double> u0 = space.Encode(base);
  const BatchEvaluator two({sc}, {1.0}, params::CostWeights{}, 2);
  const SensitivityResult r = ComputeSensitivity(two, space, u0, base);
  ASSERT_EQ(r.dimensions.size(), 2u);
  EXPECT_EQ(r.sets, 9);
  EXPECT_EQ(r.NotExercised(),
            std::vector<std::string>{"SlipControl.TC.rear.slip_threshold_hold_reduce"});
  const DimensionSensitivity& tc = r.dimensions[0];
  EXPECT_EQ(tc.subsystem, "TC");
  EXPECT_EQ(tc.subsystem_activations, 0);
  EXPECT_EQ(tc.reason, "TC never acted in the centre runs");
  EXPECT_EQ(tc.max_abs_delta[0], 0.0);
  const DimensionSensitivity& cs = r.dimensions[1];
  EXPECT_TRUE(cs.exercised);
  EXPECT_GT(cs.subsystem_activations, 0);
  EXPECT_GT(cs.max_abs_delta[0], 0.0);
  EXPECT_EQ(cs.max_abs_delta[0], std::max(cs.max_abs_delta_completed, cs.max_abs_delta_aborted));

  const std::string md = SensitivityMarkdown(r, "the base set");
  EXPECT_NE(md.find("## Parameter sensitivity"), std::string::npos) << md;
  EXPECT_NE(md.find("| SlipControl.TC.rear.slip_threshold_hold_reduce | 8 | 7.2 / 7.9 / 8.1 / "
                    "8.8 | TC 0 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("**not exercised by this scenario set** (TC never acted in the centre runs)"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("1 of 2 parameters not exercised by this scenario set:** "
                    "SlipControl.TC.rear.slip_threshold_hold_reduce."),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("steering_factor | 1 | 0.9 / 0.99 / 1.01 / 1.1 | CS 0"), std::string::npos);

  // One thread gives the same batch, bit for bit.
  const BatchEvaluator one({sc}, {1.0}, params::CostWeights{}, 1);
  const SensitivityResult r1 = ComputeSensitivity(one, space, u0, base);
  EXPECT_EQ(r1.centre_costs, r.centre_costs);
  for (std::size_t i = 0; i < r.dimensions.size(); ++i) {
    EXPECT_EQ(r1.dimensions[i].delta, r.dimensions[i].delta) << i;
    EXPECT_EQ(r1.dimensions[i].changed, r.dimensions[i].changed) << i;
  }
  EXPECT_EQ(SensitivityMarkdown(r1, "the base set"), md);
  EXPECT_EQ(SensitivityCsv(r1), SensitivityCsv(r));
}

}  // namespace
}  // namespace scw::tuning
