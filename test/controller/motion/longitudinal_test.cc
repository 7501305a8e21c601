#include "controller/motion/longitudinal.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::controller::motion {
namespace {

LongitudinalModel Model() {
  LongitudinalModel m;
  m.map_speed = {100.0, 400.0, 800.0};
  m.map_throttle = {0.0, 0.5, 1.0};
  m.map_torque = {-20, 100, 300,  //
                  -40, 200, 500,  //
                  -60, 180, 450};
  return m;
}

TEST(LongitudinalTest, EngineMapInversionRoundTrips) {
  LongitudinalController c({}, Model(), 0.01);
  for (double w : {150.0, 400.0, 700.0})
    for (double thr : {0.1, 0.4, 0.75, 0.95}) {
      const double t = c.EngineTorque(w, thr);
      EXPECT_NEAR(c.ThrottleFor(w, t), thr, 1e-12) << w << " " << thr;
    }
  EXPECT_EQ(c.ThrottleFor(400.0, -1000.0), 0.0);
  EXPECT_EQ(c.ThrottleFor(400.0, 1e6), 1.0);
}

TEST(LongitudinalTest, FeedForwardBalancesResistanceAtConstantSpeed) {
  const auto m = Model();
  LongitudinalController c({}, m, 0.01);
  LongitudinalController::State s;
  LongitudinalOutput out;
  for (int k = 0; k < 200; ++k) out = c.Step({0.0, 0.0, 50.0, 600.0, 4, false}, &s);
  const double q = 0.5 * m.air_density * 2500.0;
  const double expected =
      q * m.drag_area + m.rolling_resistance * (m.mass * 9.81 + q * m.downforce_area);
  EXPECT_NEAR(out.force, expected, 1e-6);
  EXPECT_GT(out.throttle, 0.0);
  EXPECT_EQ(out.brake_bar[0], 0.0);
}

TEST(LongitudinalTest, BrakingSplitsByBiasAndRespectsRateLimit) {
  params::LongitudinalParams p;
  const auto m = Model();
  LongitudinalController c(p, m, 0.01);
  LongitudinalController::State s;
  LongitudinalOutput out = c.Step({0.0, 0.0, 40.0, 500.0, 3, false}, &s);
  const double f0 = out.force;
  out = c.Step({-20.0, 0.0, 40.0, 500.0, 3, false}, &s);
  EXPECT_NEAR(out.force, f0 - p.max_force_rate * 0.01, 1e-6);  // rate limited
  for (int k = 0; k < 100; ++k) out = c.Step({-20.0, -20.0, 40.0, 500.0, 3, false}, &s);
  EXPECT_LT(out.force, 0.0);
  EXPECT_EQ(out.throttle, 0.0);
  EXPECT_GT(out.brake_bar[0], 0.0);
  EXPECT_EQ(out.brake_bar[0], out.brake_bar[1]);
  EXPECT_EQ(out.brake_bar[2], out.brake_bar[3]);
  // Front/rear force ratio equals the bias (same radii and gains in this model).
  EXPECT_NEAR(out.brake_bar[0] / out.brake_bar[2], p.brake_bias_front / (1 - p.brake_bias_front),
              1e-9);
}

TEST(LongitudinalTest, FeedbackIsFrozenWhileSlipControlActs) {
  LongitudinalController c({}, Model(), 0.01);
  LongitudinalController::State a, b;
  LongitudinalOutput oa, ob;
  for (int k = 0; k < 50; ++k) {
    oa = c.Step({-5.0, -3.0, 30.0, 500.0, 3, false}, &a);
    ob = c.Step({-5.0, -3.0, 30.0, 500.0, 3, true}, &b);
  }
  EXPECT_LT(oa.force, ob.force);  // feedback asks for more braking; frozen when slip control acts
}

TEST(LongitudinalTest, HoldDuringEscKeepsTheForceFromRisingOnlyWhenDeclared) {
  // The car decelerates harder than asked (ESC braking): the feedback wants more drive.
  const LongitudinalInput esc{1.0, -4.0, 40.0, 600.0, 4, false, true};
  LongitudinalInput no_esc = esc;
  no_esc.esc_active = false;
  params::LongitudinalParams held;
  held.hold_during_esc = true;
  const LongitudinalController car({}, Model(), 0.01), option(held, Model(), 0.01);
  LongitudinalController::State a, b, c;
  LongitudinalOutput oa, ob, oc;
  for (int k = 0; k < 50; ++k) {
    oa = car.Step(esc, &a);     // the car's controller ignores ESC
    ob = car.Step(no_esc, &b);  // ... so both give the same request
    oc = option.Step(esc, &c);  // the option holds the force
  }
  EXPECT_EQ(oa.force, ob.force);
  EXPECT_EQ(oa.throttle, ob.throttle);
  EXPECT_LT(oc.force, oa.force);
  // Held: the force never rises from one step to the next while ESC acts.
  LongitudinalController::State d;
  double last = option.Step(no_esc, &d).force;
  for (int k = 0; k < 50; ++k) {
    const double f = option.Step(esc, &d).force;
    EXPECT_LE(f, last) << k;
    last = f;
  }
}

TEST(LongitudinalTest, NonFiniteInputsStayFinite) {
  LongitudinalController c({}, Model(), 0.01);
  LongitudinalController::State s;
  const double nan = std::nan("");
  const auto out = c.Step({nan, nan, nan, nan, 0, false}, &s);
  EXPECT_TRUE(std::isfinite(out.force));
  EXPECT_TRUE(std::isfinite(out.throttle));
}

}  // namespace
}  // namespace scw::controller::motion
