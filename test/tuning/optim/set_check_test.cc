// scw tune --check-set: which subsystem acts in and decides which scenario, and the warning for a
// subsystem the training set cannot see.
#include "tuning/optim/set_check.h"

#include <gtest/gtest.h>

#include "tuning/sim/scenario.h"

namespace scw::tuning {
namespace {

TEST(SetCheckTest, FindsTheSubsystemThatDecidesAndFlagsOneThatNeverActs) {
  // Grip -18 % that the planner does not know about, one lap: with ABS the lap completes, without
  // it a front wheel locks in a braking zone. TC is switched off in the scenario itself, so it
  // cannot act whatever the parameters.
  const ResolvedScenario sc = Resolve(DefaultScenario(
      {"grip.mu=0.82", "plan_with_nominal_grip=true", "subsystems.tc=false", "laps=1"}));
  const BatchEvaluator ev({sc}, {1.0}, params::CostWeights{}, 2);
  const SetCheck c = CheckSet(ev, sc.stability);
  ASSERT_EQ(c.scenarios.size(), 1u);
  const ScenarioCheck& s = c.scenarios[0];
  EXPECT_GT(s.activations[2], 0) << "ABS acts";
  EXPECT_TRUE(s.decides[2]) << "without ABS: " << s.status_off[2];
  EXPECT_EQ(s.status_off[2], "wheel_lock");
  EXPECT_EQ(s.activations[3], 0);
  EXPECT_FALSE(s.decides[3]);
  EXPECT_EQ(c.acting[3], 0);
  EXPECT_EQ(c.deciding[2], 1);
  const std::string md = SetCheckMarkdown("Training", c, true);
  EXPECT_NE(md.find("warning: TC never acts in the training scenarios"), std::string::npos) << md;
  EXPECT_EQ(md.find("warning: ABS"), std::string::npos) << md;
  EXPECT_NE(md.find("ABS ("), std::string::npos) << md;  // named in "decided by"
  // The same check on two threads and one gives the same numbers.
  const BatchEvaluator one({sc}, {1.0}, params::CostWeights{}, 1);
  const SetCheck c1 = CheckSet(one, sc.stability);
  EXPECT_EQ(c1.scenarios[0].cost_off, s.cost_off);
}

TEST(SetCheckTest, WithoutSubsystemSwitchesOffExactlyOne) {
  const params::StabilityParams p;
  EXPECT_FALSE(WithoutSubsystem(p, 0).ESC.enabled);
  EXPECT_TRUE(WithoutSubsystem(p, 0).countersteer_system.enabled);
  EXPECT_FALSE(WithoutSubsystem(p, 1).countersteer_system.enabled);
  EXPECT_FALSE(WithoutSubsystem(p, 2).SlipControl.ABS.enabled);
  EXPECT_TRUE(WithoutSubsystem(p, 2).SlipControl.TC.enabled);
  EXPECT_FALSE(WithoutSubsystem(p, 3).SlipControl.TC.enabled);
}

}  // namespace
}  // namespace scw::tuning
