// Actuator delays, lags and limits, seen at the wheel through the whole plant.
#include "plant/actuator/actuators.h"

#include <gtest/gtest.h>

#include <cmath>

#include "params/schema/vehicle_params.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant {
namespace {

TEST(DelayLine, DelaysByExactlyNSamples) {
  DelayLine<double> d(3, 0.0);
  const double in[] = {1, 2, 3, 4, 5};
  const double expect[] = {0, 0, 0, 1, 2};
  for (int k = 0; k < 5; ++k) EXPECT_EQ(d.Shift(in[k]), expect[k]);
  DelayLine<double> none(0, 0.0);
  EXPECT_EQ(none.Shift(7.0), 7.0);
}

// A brake pressure step requested at t = 0 reaches the calliper after the pure delay (0.116 s for
// the EAV24 set: 150 ms total response with the lag and the rate limit), then rises with the lag
// and the rate limit.
TEST(BrakeActuator, PressureStepAppearsAfterTheDelay) {
  const params::VehicleParams p;
  ASSERT_DOUBLE_EQ(p.brakes.delay, 0.116);
  const Vehicle v(p);
  State s = v.MakeState({.speed = 30.0});
  Actuators u;
  u.brake_pressure_req = {40.0, 40.0, 30.0, 30.0};
  const double h = v.time_step();
  double first_time = -1.0, prev = 0.0;
  for (int k = 0; k < 600; ++k) {
    v.Step(u, &s);
    const Measurement m = v.Measure(s);
    if (first_time < 0.0 && m.brake_pressure[kFL] > 0.0) first_time = m.time;
    EXPECT_LE(m.brake_pressure[kFL] - prev, p.brakes.rate_limit * h * (1 + 1e-12));
    prev = m.brake_pressure[kFL];
    EXPECT_LE(m.brake_pressure[kRL], 30.0 + 1e-12);
  }
  // The request enters at step 1 (t = h); the output moves in the step ending delay later.
  EXPECT_NEAR(first_time, p.brakes.delay + h, 0.5 * h);
  EXPECT_NEAR(prev, 40.0, 0.01);
  EXPECT_NEAR(s.out.brake_torque[kFL], 40.0 * p.brakes.torque_gain_front, 1.0);
}

TEST(SteeringActuator, StepAppearsAfterTheDelayAndRespectsLimits) {
  const params::VehicleParams p;
  ASSERT_DOUBLE_EQ(p.steering.delay, 0.03);
  const Vehicle v(p);
  State s = v.MakeState({.speed = 20.0});
  Actuators u;
  u.steer_req = 1.0;  // beyond the lock: clamped
  const double h = v.time_step();
  double first_time = -1.0, prev = 0.0;
  for (int k = 0; k < 1000; ++k) {
    v.Step(u, &s);
    const double a = v.Measure(s).steering_angle;
    if (first_time < 0.0 && a > 0.0) first_time = s.time;
    EXPECT_LE(a - prev, p.steering.rate_limit * h * (1 + 1e-12));
    EXPECT_LE(a, p.steering.max_angle);
    prev = a;
  }
  EXPECT_NEAR(first_time, p.steering.delay + h, 0.5 * h);
  EXPECT_NEAR(prev, p.steering.max_angle, 1e-9);
}

TEST(BrakeActuator, NonFiniteAndNegativeRequestsAreSafe) {
  params::BrakeParams bp;
  bp.delay = 0.0;
  const BrakeActuator b(bp, 0.001);
  BrakeActuatorState s = b.MakeState();
  for (int k = 0; k < 100; ++k) b.Step({NAN, -5.0, 1e9, INFINITY}, &s);
  EXPECT_EQ(s.pressure[0], 0.0);
  EXPECT_EQ(s.pressure[1], 0.0);
  EXPECT_GT(s.pressure[2], 0.0);
  EXPECT_LE(s.pressure[2], bp.max_pressure);
  EXPECT_EQ(s.pressure[3], 0.0);
}

// Brake torque opposes rotation and cannot reverse it: at rest with full brakes nothing moves;
// a slowly rolling car stops and stays stopped with wheels at exactly zero.
TEST(BrakeActuator, BrakeTorqueNeverReversesTheWheel) {
  params::VehicleParams p;
  p.brakes.delay = 0.0;
  const Vehicle v(p);
  State s = v.MakeState({.speed = 2.0});
  Actuators u;
  u.brake_pressure_req = {120.0, 120.0, 120.0, 120.0};
  for (int k = 0; k < 3000; ++k) {
    v.Step(u, &s);
    for (int i = kOmegaFL; i <= kOmegaRR; ++i) ASSERT_GE(s.x[i], 0.0);
  }
  for (int i = kOmegaFL; i <= kOmegaRR; ++i) EXPECT_EQ(s.x[i], 0.0);
  EXPECT_NEAR(s.x[kVx], 0.0, 1e-6);
}

}  // namespace
}  // namespace scw::plant
