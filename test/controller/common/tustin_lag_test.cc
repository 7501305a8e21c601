#include "controller/common/tustin_lag.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::controller {
namespace {

TEST(TustinLagTest, StepResponseFirstSampleAndSteadyState) {
  const double ts = 0.01;
  const double tau = 0.5;
  const TustinLag lag(tau, ts);
  TustinLag::State s;
  EXPECT_DOUBLE_EQ(lag.Step(1.0, &s), ts / (ts + 2.0 * tau));
  for (int k = 0; k < 2000; ++k) lag.Step(1.0, &s);
  EXPECT_NEAR(s.y_prev, 1.0, 1e-9);
}

TEST(TustinLagTest, MatchesContinuousLagAtTheTimeConstant) {
  const double ts = 0.001;
  const TustinLag lag(0.1, ts);
  TustinLag::State s;
  double y = 0.0;
  for (int k = 0; k < 100; ++k) y = lag.Step(1.0, &s);
  EXPECT_NEAR(y, 1.0 - std::exp(-1.0), 5e-3);
}

}  // namespace
}  // namespace scw::controller
