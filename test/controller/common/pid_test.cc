#include "controller/common/pid.h"

#include <gtest/gtest.h>

namespace scw::controller {
namespace {

PidGains Gains() {
  return {.kp = 2.0,
          .ki = 10.0,
          .kd = 0.5,
          .integrator_min = -1.0,
          .integrator_max = 1.0,
          .sample_time = 0.01};
}

TEST(PidTest, InactiveOutputsZeroAndResetsIntegrator) {
  const Pid pid(Gains());
  PidState s;
  s.integrator = 0.7;
  EXPECT_EQ(pid.Step(3.0, PidFlags::Gated(false), &s), 0.0);
  EXPECT_EQ(s.integrator, 0.0);
  // The previous input is tracked while inactive: no derivative kick on activation.
  EXPECT_EQ(s.filtered_prev, 3.0);
  const double out = pid.Step(3.0, PidFlags::Gated(true), &s);
  EXPECT_DOUBLE_EQ(out, 2.0 * 3.0 + 10.0 * 3.0 * 0.01);
}

TEST(PidTest, ProportionalIntegralDerivativeTerms) {
  const Pid pid(Gains());
  PidState s;
  const auto on = PidFlags::Gated(true);
  // P = 2·1, I = 10·1·0.01 = 0.1, D = 0.5·(1 − 0)/0.01 = 50.
  EXPECT_DOUBLE_EQ(pid.Step(1.0, on, &s), 2.0 + 0.1 + 50.0);
  // P = 2·1, I = 0.2, D = 0.
  EXPECT_DOUBLE_EQ(pid.Step(1.0, on, &s), 2.0 + 0.2);
}

TEST(PidTest, ConditionalIntegrationHoldsTheIntegratorInsteadOfClamping) {
  PidGains g = Gains();
  g.kp = 0.0;
  g.kd = 0.0;
  g.integrator_min = -0.95;
  g.integrator_max = 0.95;
  const Pid pid(g);
  PidState s;
  const auto on = PidFlags::Gated(true);
  for (int k = 0; k < 9; ++k) pid.Step(1.0, on, &s);  // 9 × 10·1·0.01 = 0.9
  EXPECT_NEAR(s.integrator, 0.9, 1e-12);
  pid.Step(1.0, on, &s);  // candidate 1.0 is outside (−0.95, 0.95): held, not clamped
  EXPECT_NEAR(s.integrator, 0.9, 1e-12);
  pid.Step(-1.0, on, &s);  // back inside: accepted
  EXPECT_NEAR(s.integrator, 0.8, 1e-12);
}

TEST(PidTest, DerivativeFilterPoleFiltersPAndD) {
  PidGains g = Gains();
  g.ki = 0.0;
  g.derivative_filter_pole = 0.5;
  const Pid pid(g);
  PidState s;
  // d = 0.5·0 + 0.5·1 = 0.5; P = 1; D = 0.5·0.5/0.01 = 25.
  EXPECT_DOUBLE_EQ(pid.Step(1.0, PidFlags::Gated(true), &s), 1.0 + 25.0);
}

}  // namespace
}  // namespace scw::controller
