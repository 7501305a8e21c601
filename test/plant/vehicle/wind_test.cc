// Wind reaches the plant (plant::Environment::wind_x/_y): drag and downforce follow the
// longitudinal air speed, a crosswind adds a side force at the centre of pressure, still air is
// bit for bit the nominal step, and air moving with the car exerts no aero force at all.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "params/schema/vehicle_params.h"
#include "plant/vehicle/environment.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant {
namespace {

constexpr double kSpeed = 50.0;  // [m/s]

Environment Wind(double wx, double wy) {
  Environment env;
  env.wind_x = wx;
  env.wind_y = wy;
  return env;
}

// The wind `speed` coming from `from` (rad, relative to the heading psi; 0 = head-on, +pi/2 =
// from the left), in the world frame: the air moves towards the opposite direction.
Environment WindFrom(double psi, double from, double speed) {
  return Wind(-speed * std::cos(psi + from), -speed * std::sin(psi + from));
}

double Sum(const PerWheel<double>& f) { return f[0] + f[1] + f[2] + f[3]; }

// One coasting step at kSpeed from a straight-line start heading psi.
State OneStep(const Vehicle& v, double psi, const Environment* env) {
  State s = v.MakeState({0.0, 0.0, psi, kSpeed});
  if (env) {
    v.Step(Actuators{}, *env, &s);
  } else {
    v.Step(Actuators{}, &s);
  }
  return s;
}

TEST(Wind, StillAirIsBitIdenticalToTheNominalStep) {
  const Vehicle v{params::VehicleParams{}};
  State a = v.MakeState({0.0, 0.0, 0.4, 30.0}), b = a, c = a;
  Actuators u;
  u.throttle = 0.8;
  u.steer_req = 0.05;  // the car slides (v_y != 0): a still-air side force would show here
  for (int k = 0; k < 2000; ++k) {
    v.Step(u, &a);
    v.Step(u, Wind(0.0, 0.0), &b);
    v.Step(u, Wind(-0.0, -0.0), &c);
  }
  EXPECT_GT(std::abs(a.x[kVy]), 0.01);
  for (int i = 0; i < kNumStates; ++i) {
    EXPECT_EQ(a.x[i], b.x[i]) << kStateNames[i];
    EXPECT_EQ(a.x[i], c.x[i]) << kStateNames[i];
  }
  EXPECT_EQ(a.out.a_x, b.out.a_x);
  EXPECT_EQ(a.out.a_y, b.out.a_y);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(a.out.fz[i], b.out.fz[i]);
}

TEST(Wind, NonFiniteWindCountsAsStillAir) {
  const Vehicle v{params::VehicleParams{}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const State a = OneStep(v, 0.0, nullptr);
  for (const Environment& env : {Wind(nan, 0.0), Wind(3.0, inf), Wind(-inf, nan)}) {
    const State b = OneStep(v, 0.0, &env);
    EXPECT_EQ(b.status, kStatusOk);
    for (int i = 0; i < kNumStates; ++i) EXPECT_EQ(a.x[i], b.x[i]) << kStateNames[i];
  }
}

TEST(Wind, HeadwindIncreasesDragAndDownforceTailwindLowersThem) {
  const params::VehicleParams p;
  const Vehicle v{p};
  const double w = 15.0;
  for (double psi : {0.0, 0.5 * std::numbers::pi, -2.0}) {  // any heading: R(psi)^T is applied
    const State still = OneStep(v, psi, nullptr);
    const Environment head_env = WindFrom(psi, 0.0, w),
                      tail_env = WindFrom(psi, std::numbers::pi, w);
    const State head = OneStep(v, psi, &head_env);
    const State tail = OneStep(v, psi, &tail_env);
    // Downforce from the longitudinal air speed u_x = 65 (head) / 35 (tail) m/s; the first step
    // starts without load transfer, so the load sums differ by the downforce alone.
    const double k_lift =
        0.5 * p.aero.air_density * (p.aero.downforce_area_front + p.aero.downforce_area_rear);
    const double ux_head = kSpeed + w, ux_tail = kSpeed - w;
    EXPECT_NEAR(Sum(head.out.fz) - Sum(still.out.fz),
                k_lift * (ux_head * ux_head - kSpeed * kSpeed), 1e-6)
        << psi;
    EXPECT_NEAR(Sum(tail.out.fz) - Sum(still.out.fz),
                k_lift * (ux_tail * ux_tail - kSpeed * kSpeed), 1e-6)
        << psi;
    // More drag decelerates more (the tyre forces at free rolling barely depend on the load).
    EXPECT_LT(head.out.a_x, still.out.a_x - 0.5) << psi;
    EXPECT_GT(tail.out.a_x, still.out.a_x + 0.5) << psi;
    // A pure head/tailwind pushes nothing sideways.
    EXPECT_NEAR(head.out.a_y, still.out.a_y, 1e-9) << psi;
    EXPECT_NEAR(head.x[kYawRate], still.x[kYawRate], 1e-12) << psi;
  }
  // Over two seconds of coasting the headwind slows the car more.
  State still = v.MakeState({0.0, 0.0, 0.0, kSpeed}), head = still;
  for (int k = 0; k < 2000; ++k) {
    v.Step(Actuators{}, &still);
    v.Step(Actuators{}, WindFrom(0.0, 0.0, w), &head);
  }
  EXPECT_LT(head.x[kVx], still.x[kVx] - 1.0);
}

TEST(Wind, CrosswindFromTheLeftPushesRightAndYawsPerTheArm) {
  const double w = 15.0;
  for (double arm : {-0.3, 0.3}) {
    params::VehicleParams p;
    p.aero.side_force_arm = arm;
    const Vehicle v{p};
    for (double psi : {0.0, 0.5 * std::numbers::pi, 2.5}) {
      const State still = OneStep(v, psi, nullptr);
      const Environment left = WindFrom(psi, 0.5 * std::numbers::pi, w);
      const State s = OneStep(v, psi, &left);
      // F_y = 1/2 rho c_Y A w_y |u_r| with w_y = -15 m/s, |u_r| = sqrt(50^2 + 15^2).
      const double side =
          0.5 * p.aero.air_density * p.aero.side_force_area * -w * std::hypot(kSpeed, w);
      EXPECT_LT(s.out.a_y, still.out.a_y);  // pushed to the right
      EXPECT_NEAR(s.out.a_y - still.out.a_y, side / p.chassis.mass, 1e-9) << psi;
      const double dr = s.x[kYawRate] - still.x[kYawRate];
      EXPECT_NEAR(dr, p.simulation.time_step * side * arm / p.chassis.yaw_inertia, 1e-12) << psi;
      // Centre of pressure behind the CoG: the nose turns into the wind (left, r > 0).
      if (arm < 0.0) {
        EXPECT_GT(dr, 0.0);
      } else {
        EXPECT_LT(dr, 0.0);
      }
      // Only the lateral air speed changed: downforce and drag stay as in still air.
      for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(s.out.fz[i], still.out.fz[i], 1e-9);
      EXPECT_NEAR(s.out.a_x, still.out.a_x, 1e-9);
    }
    // Held: the car is first pushed to the right of its still-air path (heading +x: y < 0),
    // then it yaws per the arm: a centre of pressure behind the neutral steer point (-0.3 m;
    // this understeering car's lies between it and the CoG) turns the nose into the wind, one
    // ahead of it away from the wind, which carries the car further downwind.
    State still = v.MakeState({0.0, 0.0, 0.0, kSpeed}), s = still;
    for (int k = 1; k <= 1000; ++k) {
      v.Step(Actuators{}, &still);
      v.Step(Actuators{}, WindFrom(0.0, 0.5 * std::numbers::pi, w), &s);
      if (k == 200) {
        EXPECT_LT(s.x[kVy], still.x[kVy] - 0.02) << arm;
        EXPECT_LT(s.x[kY], still.x[kY] - 0.005) << arm;
      }
    }
    if (arm < 0.0) {
      EXPECT_GT(s.x[kPsi], still.x[kPsi] + 0.002);
    } else {
      EXPECT_LT(s.x[kPsi], still.x[kPsi] - 0.005);
      EXPECT_LT(s.x[kY], still.x[kY] - 0.1);
    }
    EXPECT_EQ(s.status, kStatusOk);
  }
}

TEST(Wind, AirMovingWithTheCarExertsNoAeroForce) {
  params::VehicleParams p;
  const Vehicle v{p};
  params::VehicleParams no_aero = p;
  no_aero.aero.drag_area = 0.0;
  no_aero.aero.downforce_area_front = 0.0;
  no_aero.aero.downforce_area_rear = 0.0;
  no_aero.aero.side_force_area = 0.0;
  const Vehicle bare{no_aero};
  const double psi = 0.3, vy = 2.0;  // sliding sideways: the body velocity is (50, 2)
  State a = v.MakeState({0.0, 0.0, psi, kSpeed}), b = bare.MakeState({0.0, 0.0, psi, kSpeed});
  a.x[kVy] = vy;
  b.x[kVy] = vy;
  // The world-frame velocity of the car = the wind.
  const Environment with_car = Wind(kSpeed * std::cos(psi) - vy * std::sin(psi),
                                    kSpeed * std::sin(psi) + vy * std::cos(psi));
  v.Step(Actuators{}, with_car, &a);
  bare.Step(Actuators{}, &b);
  EXPECT_NEAR(Sum(a.out.fz), p.chassis.mass * p.chassis.gravity, 1e-6);  // no downforce
  EXPECT_NEAR(a.out.a_x, b.out.a_x, 1e-9);                               // no drag
  EXPECT_NEAR(a.out.a_y, b.out.a_y, 1e-9);                               // no side force
  for (int i = 0; i < kNumStates; ++i) EXPECT_NEAR(a.x[i], b.x[i], 1e-9) << kStateNames[i];
}

}  // namespace
}  // namespace scw::plant
