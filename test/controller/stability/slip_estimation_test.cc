// Slip estimation (spec §2): pure rolling gives zero slip, a locked wheel −100 %, the low-speed
// fade of Appendix B, the reference-speed blend and the quasi-static vertical loads.
#include "controller/stability/slip_estimation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::controller {
namespace {

/// Wheel speeds of pure rolling for the given motion (ω_i = v_x,t,i / r_i(v_x)).
Wheels RollingSpeeds(const SlipEstimator& est, double v_x, double v_y, double yaw_rate,
                     double delta) {
  const auto tyre = TyreVelocities(v_x, v_y, yaw_rate, delta, est.geometry());
  Wheels w{};
  for (std::size_t i = 0; i < 4; ++i) w[i] = tyre[i].longitudinal / est.Radius(i, v_x);
  return w;
}

SlipEstimator::Input Motion(const SlipEstimator& est, double v_x, double v_y, double yaw_rate,
                            double delta) {
  SlipEstimator::Input in;
  in.v_x = v_x;
  in.v_y = v_y;
  in.yaw_rate = yaw_rate;
  in.steering = delta;
  in.wheel_speed = RollingSpeeds(est, v_x, v_y, yaw_rate, delta);
  return in;
}

TEST(SlipEstimationTest, LowSpeedFadeOfAppendixB) {
  EXPECT_EQ(SlipEstimator::LowSpeedFade(2.0, 5.0), 0.0);
  EXPECT_EQ(SlipEstimator::LowSpeedFade(3.0, 5.0), 0.0);
  EXPECT_NEAR(SlipEstimator::LowSpeedFade(4.0, 5.0), 0.0039, 5e-5);
  EXPECT_NEAR(SlipEstimator::LowSpeedFade(4.5, 5.0), 0.10, 5e-4);
  EXPECT_EQ(SlipEstimator::LowSpeedFade(5.0, 5.0), 1.0);
  EXPECT_EQ(SlipEstimator::LowSpeedFade(30.0, 5.0), 1.0);
  EXPECT_EQ(SlipEstimator::LowSpeedFade(-3.0, 5.0), 0.0);
}

TEST(SlipEstimationTest, PureRollingGivesZeroSlip) {
  const SlipEstimator est(params::StabilityParams{});
  for (const auto& [vx, vy, r, d] : {std::tuple{20.0, 0.0, 0.0, 0.0},
                                     {35.0, -0.5, 0.3, 0.05},
                                     {60.0, 0.8, -0.2, -0.03},
                                     {8.0, 0.1, 0.5, 0.2}}) {
    SlipEstimator::State s;
    SlipEstimator::Output out;
    for (int k = 0; k < 50; ++k) out = est.Step(Motion(est, vx, vy, r, d), &s);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(out.slip_pct[i], 0.0, 1e-9) << vx << " " << i;
    EXPECT_NEAR(out.v_ref, vx, 1e-9);
  }
}

TEST(SlipEstimationTest, LockedWheelsGiveMinus100Percent) {
  const SlipEstimator est(params::StabilityParams{});
  SlipEstimator::State s;
  auto in = Motion(est, 25.0, 0.0, 0.0, 0.0);
  in.wheel_speed = {0.0, 0.0, 0.0, 0.0};
  in.front_pressure_max_bar = 30.0;  // braking: reference speed from the state estimate
  SlipEstimator::Output out;
  for (int k = 0; k < 50; ++k) out = est.Step(in, &s);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(out.slip_pct[i], -100.0);
  EXPECT_NEAR(out.blend, 1.0, 1e-12);
}

TEST(SlipEstimationTest, SpinningRearWheelsMeasuredAgainstFrontWheels) {
  const SlipEstimator est(params::StabilityParams{});
  SlipEstimator::State s;
  auto in = Motion(est, 20.0, 0.0, 0.0, 0.0);
  // The state estimate over-reads by 1 m/s; the undriven fronts roll at the true 19 m/s.
  const auto truth = RollingSpeeds(est, 19.0, 0.0, 0.0, 0.0);
  in.wheel_speed = {truth[0], truth[1], truth[2] * 1.2, truth[3] * 1.2};
  SlipEstimator::Output out;
  for (int k = 0; k < 200; ++k) out = est.Step(in, &s);
  EXPECT_LT(out.blend, 1e-6);  // no braking: fronts define v_ref
  EXPECT_NEAR(out.v_ref, 19.0, 0.01);
  EXPECT_NEAR(out.slip_pct[kRL], 20.0, 0.2);
  EXPECT_NEAR(out.slip_pct[kFL], 0.0, 0.1);
}

TEST(SlipEstimationTest, InvalidWheelSpeedsGiveZeroSlip) {
  const SlipEstimator est(params::StabilityParams{});
  SlipEstimator::State s;
  auto in = Motion(est, 25.0, 0.0, 0.0, 0.0);
  in.wheel_speed = {0.0, 0.0, 0.0, 0.0};
  in.wheel_speeds_valid = false;
  const auto out = est.Step(in, &s);
  EXPECT_EQ(out.slip_pct, (Wheels{0.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(out.virtual_slip_pct, (Wheels{0.0, 0.0, 0.0, 0.0}));
  EXPECT_DOUBLE_EQ(out.v_ref, 25.0);
}

TEST(SlipEstimationTest, VirtualSlipsFromEngineSpeed) {
  params::StabilityParams p;
  p.vehicle.drivetrain.gear_ratios = {3.0, 2.0, 1.8, 1.4, 1.2, 1.0};
  const SlipEstimator est(p);
  SlipEstimator::State s;
  auto in = Motion(est, 30.0, 0.0, 0.0, 0.0);
  in.gear = 2;                                        // ratio index 1: 3.0 · 2.0
  in.engine_speed = in.wheel_speed[kRL] * 6.0 * 1.1;  // engine says rears spin 10 % faster
  in.engine_speed_valid = true;
  const auto out = est.Step(in, &s);
  EXPECT_NEAR(out.virtual_slip_pct[kRL], 10.0, 1e-9);
  EXPECT_NEAR(out.virtual_slip_pct[kFL], out.slip_pct[kFL], 1e-12);
  in.gear = 9;  // out of range: all virtual wheel speeds 0
  const auto bad = est.Step(in, &s);
  EXPECT_DOUBLE_EQ(bad.virtual_slip_pct[kRR], -100.0);
  in.engine_speed_valid = false;
  const auto none = est.Step(in, &s);
  EXPECT_EQ(none.virtual_slip_pct[kRL], 0.0);
  EXPECT_EQ(none.virtual_slip_pct[kFR], none.slip_pct[kFR]);
}

TEST(SlipEstimationTest, SlipAnglesFadeAndSign) {
  const SlipEstimator est(params::StabilityParams{});
  SlipEstimator::State s;
  // Sliding to the right (v_y < 0) with no yaw: tyres see a positive slip angle (force to the
  // left).
  const auto out = est.Step(Motion(est, 20.0, -1.0, 0.0, 0.0), &s);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(out.slip_angle[i], std::atan2(1.0, 20.0), 1e-12);
  SlipEstimator::State s2;
  const auto slow = est.Step(Motion(est, 2.0, -1.0, 0.0, 0.0), &s2);
  EXPECT_EQ(slow.slip_angle[kFL], 0.0);
}

TEST(VerticalLoadTest, QuasiStaticModelBalancesForcesAndMoments) {
  const params::StabilityParams p;
  const LoadModel m = LoadModel::From(p);
  const double g = kGravity;
  const Wheels rest = QuasiStaticVerticalLoads(m, 0.0, 0.0, 0.0);
  const double total = rest[0] + rest[1] + rest[2] + rest[3];
  EXPECT_NEAR(total, m.mass * g, 1e-9);
  EXPECT_NEAR((rest[0] + rest[1]) / total, m.geometry.l_rear / m.geometry.wheelbase, 1e-12);
  // Downforce adds ½ρA(−c_L)v² split by the aero balance.
  const Wheels fast = QuasiStaticVerticalLoads(m, 50.0, 0.0, 0.0);
  const double aero = 0.5 * m.air_density * m.area * -m.lift_coeff * 2500.0;
  EXPECT_NEAR(fast[0] + fast[1] + fast[2] + fast[3], m.mass * g + aero, 1e-9);
  EXPECT_NEAR(fast[0] + fast[1] - rest[0] - rest[1], m.front_downforce_share * aero, 1e-9);
  // Braking moves load forward by m·a_x·h/l; total unchanged.
  const Wheels brake = QuasiStaticVerticalLoads(m, 0.0, -10.0, 0.0);
  EXPECT_NEAR(brake[0] + brake[1] - rest[0] - rest[1],
              m.mass * 10.0 * m.cog_height / m.geometry.wheelbase, 1e-9);
  // Left turn (a_y > 0) loads the right wheels; roll moment m·a_y·h is carried.
  const Wheels left = QuasiStaticVerticalLoads(m, 0.0, 0.0, 8.0);
  EXPECT_GT(left[kFR], left[kFL]);
  EXPECT_GT(left[kRR], left[kRL]);
  const double moment = (left[kFR] - left[kFL]) * 0.5 * m.geometry.track_front +
                        (left[kRR] - left[kRL]) * 0.5 * m.geometry.track_rear;
  EXPECT_NEAR(moment, m.mass * 8.0 * m.cog_height, 1e-9);
  // Loads never negative.
  const Wheels lift = QuasiStaticVerticalLoads(m, 0.0, 0.0, 60.0);
  EXPECT_GE(MinElement(lift), 0.0);
}

TEST(VerticalLoadTest, ExternalLoadsReplaceTheEstimate) {
  const SlipEstimator est(params::StabilityParams{});
  SlipEstimator::State s;
  auto in = Motion(est, 20.0, 0.0, 0.0, 0.0);
  in.fz_external = {1000.0, 2000.0, 3000.0, 4000.0};
  in.fz_external_valid = true;
  EXPECT_EQ(est.Step(in, &s).fz, in.fz_external);
}

}  // namespace
}  // namespace scw::controller
