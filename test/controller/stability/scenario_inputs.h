// Hand-made controller input samples for the stability-controller tests and the benchmark:
// steady cruise, a left-hand oversteer slide, a braking lock-up and a rear-wheel spin.
#pragma once

#include <cmath>

#include "controller/stability/stability_controller.h"
#include "controller/stability/vehicle_model.h"

namespace scw::controller::testing {

/// Wheel speeds of pure rolling for straight motion at v [m/s].
inline PerWheel<double> RollingWheelSpeeds(const params::StabilityParams& p, double v) {
  const auto& sc = p.tires.front_left.radius.velocity_scaling;
  const double rf = DynamicTyreRadius(p.tires.front_left.radius.radius_20mps, v, sc);
  const double rr = DynamicTyreRadius(p.tires.rear_left.radius.radius_20mps, v, sc);
  return {v / rf, v / rf, v / rr, v / rr};
}

inline StabilityInput Cruise(const params::StabilityParams& p, double t, double v = 30.0) {
  StabilityInput in;
  in.t = t;
  in.v_x = v;
  in.v_y = 0.0;
  in.yaw_rate = 0.0;
  in.a_x = 0.0;
  in.a_y = 0.0;
  in.steering_measured = 0.0;
  in.steering_request = 0.0;
  in.ay_request = 0.0;
  in.brake_request_bar = {0.0, 0.0, 0.0, 0.0};
  in.throttle_request = 0.3;
  in.gear_request = 4;
  in.gear = 4;
  in.engine_speed = 500.0;
  in.wheel_speed = RollingWheelSpeeds(p, v);
  in.brake_measured_bar = {0.0, 0.0, 0.0, 0.0};
  in.brake_temperature_degc = {300.0, 300.0, 250.0, 250.0};
  in.long_fx = 800.0;
  return in;
}

/// Left-hand oversteer: yaw rate above the reference, large negative sideslip.
inline StabilityInput Oversteer(const params::StabilityParams& p, double t, double v = 30.0) {
  StabilityInput in = Cruise(p, t, v);
  const double beta = -0.12;
  in.v_x = v * std::cos(beta);
  in.v_y = v * std::sin(beta);
  in.yaw_rate = 0.8;
  in.a_y = 9.0;
  in.steering_request = 0.05;
  in.steering_measured = 0.05;
  in.ay_request = 9.0;  // κ = 0.01 1/m → ψ̇_ref = 0.3 rad/s
  in.throttle_request = 0.2;
  in.brake_request_bar = {5.0, 5.0, 3.0, 3.0};
  in.long_fx = -2000.0;
  return in;
}

/// Hard braking with the fronts locking progressively (k = steps since the start of braking).
inline StabilityInput Lockup(const params::StabilityParams& p, double t, int k, double v = 40.0) {
  StabilityInput in = Cruise(p, t, v);
  in.a_x = -12.0;
  in.brake_request_bar = {50.0, 50.0, 35.0, 35.0};
  in.brake_measured_bar = {50.0, 50.0, 35.0, 35.0};
  in.throttle_request = 0.0;
  in.long_fx = -15000.0;
  const double lock = std::max(0.0, 1.0 - 0.05 * k);
  const auto w = RollingWheelSpeeds(p, v);
  in.wheel_speed = {w[0] * lock, w[1] * lock, w[2] * 0.97, w[3] * 0.97};
  return in;
}

/// Rear wheels spinning 30 % faster than the ground under a positive drive-force request.
inline StabilityInput RearSpin(const params::StabilityParams& p, double t, double v = 20.0) {
  StabilityInput in = Cruise(p, t, v);
  in.throttle_request = 0.9;
  in.long_fx = 4000.0;
  const auto w = RollingWheelSpeeds(p, v);
  in.wheel_speed = {w[0], w[1], w[2] * 1.3, w[3] * 1.3};
  return in;
}

}  // namespace scw::controller::testing
