#include "controller/common/interp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "params/schema/stability_params.h"

namespace scw::controller {
namespace {

TEST(InterpTest, InteriorBreakpointsAndLinearExtrapolation) {
  const std::vector<double> xp{0.0, 1.0, 3.0};
  const std::vector<double> fp{0.0, 10.0, 30.0};
  EXPECT_DOUBLE_EQ(Interp(0.5, xp, fp), 5.0);
  EXPECT_DOUBLE_EQ(Interp(1.0, xp, fp), 10.0);
  EXPECT_DOUBLE_EQ(Interp(2.0, xp, fp), 20.0);
  EXPECT_DOUBLE_EQ(Interp(-1.0, xp, fp), -10.0);  // first segment extended, no clamp
  EXPECT_DOUBLE_EQ(Interp(5.0, xp, fp), 50.0);    // last segment extended, no clamp
}

TEST(InterpTest, DegenerateArraysAreTotal) {
  const std::vector<double> one{2.0};
  const std::vector<double> two{1.0, 2.0};
  EXPECT_EQ(Interp(7.0, one, one), 2.0);
  EXPECT_TRUE(std::isnan(Interp(7.0, two, one)));
  EXPECT_TRUE(std::isnan(Interp(7.0, std::vector<double>{}, std::vector<double>{})));
}

TEST(InterpTest, ShippedEscThresholdsExtrapolateAsSpec44) {
  const params::EscParams p;
  auto beta = [&](double v) {
    return Interp(v, p.threshold_velocities, p.beta_threshold_activate);
  };
  auto epsi = [&](double v) {
    return Interp(v, p.threshold_velocities, p.psi_dot_error_threshold_activate);
  };
  auto ebeta = [&](double v) {
    return Interp(v, p.threshold_velocities, p.beta_error_threshold_activate);
  };
  EXPECT_NEAR(beta(7.0), 0.0477, 5e-5);
  EXPECT_NEAR(epsi(7.0), 0.0438, 5e-5);
  EXPECT_NEAR(ebeta(7.0), 0.0797, 5e-5);
  EXPECT_NEAR(beta(70.0), 0.0033, 5e-5);
  EXPECT_NEAR(beta(80.0), -0.0037, 5e-5);  // negative: the extrapolation artefact is kept
  EXPECT_NEAR(ebeta(80.0), 0.0038, 5e-5);
}

}  // namespace
}  // namespace scw::controller
