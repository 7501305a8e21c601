// The input programs of the standard maneuvers have the standards' shapes (tuning/maneuver/
// programs.h): frequency, dwell and timing of the sine with dwell, the step's ramp, the amplitude
// series with its 270 deg / 300 deg rules, and the brake program's scaling.
#include "tuning/maneuver/programs.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::tuning {
namespace {

TEST(SineWithDwell, TimingOfTheStandard) {
  const SineWithDwell p{0.1, 0.7, 0.5};
  const double period = 1.0 / 0.7;
  EXPECT_DOUBLE_EQ(p.Reversal(), 0.5 * period);
  EXPECT_DOUBLE_EQ(p.DwellStart(), 0.75 * period);  // 1.0714 s
  EXPECT_DOUBLE_EQ(p.Duration(), period + 0.5);     // 1.9286 s: the ideal completion of steer
  EXPECT_NEAR(p.Duration(), 1.928571, 1e-6);
}

TEST(SineWithDwell, ShapeFrequencyAndDwell) {
  const SineWithDwell p{0.1, 0.7, 0.5};
  const double period = 1.0 / 0.7;
  EXPECT_EQ(p.At(-0.01), 0.0);
  EXPECT_EQ(p.At(0.0), 0.0);
  EXPECT_NEAR(p.At(0.25 * period), 0.1, 1e-12);  // first peak, in the first steer's direction
  EXPECT_GT(p.At(p.Reversal() - 1e-6), 0.0);     // the reversal at half a period: 0.7 Hz
  EXPECT_LT(p.At(p.Reversal() + 1e-6), 0.0);
  EXPECT_NEAR(p.At(p.DwellStart() - 1e-9), -0.1, 1e-9);  // reaches the second peak continuously
  for (double t = p.DwellStart(); t < p.DwellStart() + 0.5; t += 0.01)
    EXPECT_EQ(p.At(t), -0.1) << t;                             // held for the 500 ms dwell
  EXPECT_NEAR(p.At(p.DwellStart() + 0.5 + 1e-9), -0.1, 1e-9);  // leaves the dwell continuously
  // The last quarter wave takes a quarter period, then zero for good.
  EXPECT_NEAR(p.At(p.DwellStart() + 0.5 + 0.125 * period), -0.1 * std::sqrt(0.5), 1e-12);
  EXPECT_LT(p.At(p.Duration() - 1e-6), 0.0);
  EXPECT_GT(p.At(p.Duration() - 1e-6), -1e-5);
  EXPECT_EQ(p.At(p.Duration()), 0.0);
  EXPECT_EQ(p.At(p.Duration() + 1.0), 0.0);
  // A right-hand first steer mirrors it.
  const SineWithDwell right{-0.1, 0.7, 0.5};
  for (double t = 0.0; t < 2.0; t += 0.05) EXPECT_EQ(right.At(t), -p.At(t));
}

TEST(StepAndRamp, Shape) {
  EXPECT_EQ(StepSteer(-0.1, 0.02, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(StepSteer(0.05, 0.02, 0.1), 0.01);
  EXPECT_EQ(StepSteer(0.1, 0.02, 0.1), 0.02);
  EXPECT_EQ(StepSteer(3.0, 0.02, 0.1), 0.02);
  EXPECT_EQ(RampSteer(-1.0, 0.2), 0.0);
  EXPECT_DOUBLE_EQ(RampSteer(2.0, 0.2), 0.4);
}

TEST(SineWithDwellFactors, StandardSeriesAndItsCaps) {
  const std::vector<double> standard = {1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 6.5};
  // 6.5 A = 260 deg < 270 deg: continue in 0.5 A steps up to the first that reaches 270 deg.
  std::vector<double> s = SineWithDwellFactors(standard, 40.0, true);
  ASSERT_EQ(s.size(), 12u);
  EXPECT_EQ(s.back(), 7.0);
  EXPECT_EQ(SineWithDwellFactors(standard, 40.0, false), standard);
  // A = 30 deg: 6.5 A = 195 deg; 9.0 A = 270 deg ends the series.
  s = SineWithDwellFactors(standard, 30.0, true);
  EXPECT_EQ(s.back(), 9.0);
  // A = 50 deg: 6.0 A = 300 deg is the last run; 6.5 A would exceed 300 deg.
  s = SineWithDwellFactors(standard, 50.0, true);
  EXPECT_EQ(s.back(), 6.0);
  EXPECT_EQ(s.size(), 10u);
  // A = 48 deg: 6.5 A = 312 deg is replaced by one run at exactly 300 deg.
  s = SineWithDwellFactors(standard, 48.0, true);
  EXPECT_DOUBLE_EQ(s.back(), 300.0 / 48.0);
  EXPECT_EQ(s.size(), 11u);
}

TEST(BrakeProgram, PressuresAndForceScaleWithTheCar) {
  params::VehicleParams v;
  v.chassis.mass = 1000.0;
  v.wheels.radius_front = v.wheels.radius_rear = 0.3;
  v.brakes.torque_gain_front = v.brakes.torque_gain_rear = 30.0;
  v.brakes.max_pressure = 120.0;
  const PerWheel<double> p = BrakePressuresFor(5.0, 0.58, v);
  // p_f = 0.58 · 1000 · 5 · 0.3 / (2 · 30) = 14.5 bar, p_r = 0.42 · ... = 10.5 bar.
  EXPECT_DOUBLE_EQ(p[0], 14.5);
  EXPECT_DOUBLE_EQ(p[1], 14.5);
  EXPECT_DOUBLE_EQ(p[2], 10.5);
  EXPECT_DOUBLE_EQ(p[3], 10.5);
  EXPECT_NEAR(BrakeForceOf(p, v), -5000.0, 1e-9);          // = −m·a
  EXPECT_EQ(BrakePressuresFor(100.0, 0.58, v)[0], 120.0);  // capped at the hydraulics' limit
}

}  // namespace
}  // namespace scw::tuning
