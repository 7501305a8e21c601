#include "controller/common/low_pass.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::controller {
namespace {

constexpr double kTs = 0.01;

TEST(LowPassTest, AppendixBPolesAndTimeConstants) {
  EXPECT_NEAR(TimeConstantFromPole(0.7, kTs), 0.028, 0.0005);   // slip-angle filter
  EXPECT_NEAR(TimeConstantFromPole(0.8, kTs), 0.045, 0.0005);   // TC slip filter
  EXPECT_NEAR(TimeConstantFromPole(0.92, kTs), 0.120, 0.0005);  // ESC yaw-rate error
  EXPECT_NEAR(TimeConstantFromPole(0.90, kTs), 0.095, 0.0005);  // ESC sideslip error
  EXPECT_NEAR(PoleFromTimeConstant(0.15, kTs), 0.9355, 5e-5);   // countersteer
  EXPECT_NEAR(PoleFromTimeConstant(0.005, kTs), 0.1353, 5e-5);  // pure-pursuit curvature
  EXPECT_EQ(TimeConstantFromPole(0.0, kTs), 0.0);
  EXPECT_TRUE(std::isinf(TimeConstantFromPole(1.0, kTs)));
  // Round trip.
  EXPECT_NEAR(PoleFromTimeConstant(TimeConstantFromPole(0.83, kTs), kTs), 0.83, 1e-12);
}

TEST(LowPassTest, PoleFormRecursion) {
  const LowPass f(0.8);
  double y = 1.0;
  EXPECT_DOUBLE_EQ(f.Step(0.0, &y), 0.8);
  EXPECT_DOUBLE_EQ(f.Step(0.0, &y), 0.8 * 0.8);
  EXPECT_DOUBLE_EQ(y, 0.64);
}

TEST(LowPassTest, PoleZeroIsPassThroughAndPoleIsClamped) {
  const LowPass pass;
  double y = 3.0;
  EXPECT_EQ(pass.Step(-2.0, &y), -2.0);
  EXPECT_EQ(LowPass(1.7).pole(), 1.0);
  EXPECT_EQ(LowPass(-0.2).pole(), 0.0);
}

TEST(LowPassTest, TimeConstantFormReachesOneMinusOneOverEAfterTau) {
  const double tau = 0.15;
  const LowPass f = LowPass::FromTimeConstant(tau, kTs);
  double y = 0.0;
  for (int k = 0; k < 15; ++k) f.Step(1.0, &y);
  EXPECT_NEAR(y, 1.0 - std::exp(-1.0), 1e-12);
}

}  // namespace
}  // namespace scw::controller
