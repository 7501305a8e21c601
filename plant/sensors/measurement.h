// What the controllers read from the plant (and what is logged).
//
// Contract: all quantities in SI units unless the name says otherwise, ISO 8855 axes (x forward,
// y left, z up), yaw rate > 0 = turning left, steering > 0 = left, wheel order FL, FR, RL, RR.
//   position x, y [m] and heading psi [rad] in the world (ENU-like) frame: for the motion
//     controllers (pure pursuit, MPC); in the real car these come from the localisation.
//   v_x, v_y [m/s]: CoG velocity in the body frame (the car's optical velocity sensor / estimator).
//   yaw_rate [rad/s]; a_x, a_y [m/s^2]: body-frame specific force (accelerometer at the CoG,
//     no gravity on flat ground), taken from the last step's forces.
//   wheel_speed [rad/s] (angular speed, multiply by the rolling radius for m/s).
//   steering_angle [rad]: actual road-wheel angle.
//   brake_pressure [bar]: actual calliper pressure.
//   gear (engaged, transmits torque) and gear_request (changes when the shift is decided; differs
//     from gear during the torque interruption); engine_speed [rad/s].
//   wheel_load [N]: vertical tyre loads (logging; not measured on the real car).
//   throttle [0..1]: throttle applied to the engine (after the request clamp).
//   status: plant::Status bits (0 = ok).
// Source: controller I/O of the paper's node, spec plant-and-track.md §3.4.
#pragma once

#include "params/schema/per_wheel.h"

namespace scw::plant {

struct Measurement {
  double time = 0.0;                  ///< [s] simulation time of the sample
  double x = 0.0;                     ///< [m]
  double y = 0.0;                     ///< [m]
  double psi = 0.0;                   ///< [rad]
  double v_x = 0.0;                   ///< [m/s]
  double v_y = 0.0;                   ///< [m/s]
  double yaw_rate = 0.0;              ///< [rad/s]
  double a_x = 0.0;                   ///< [m/s^2]
  double a_y = 0.0;                   ///< [m/s^2]
  PerWheel<double> wheel_speed{};     ///< [rad/s]
  double steering_angle = 0.0;        ///< [rad]
  PerWheel<double> brake_pressure{};  ///< [bar]
  int gear = 1;
  int gear_request = 1;
  double engine_speed = 0.0;      ///< [rad/s]
  PerWheel<double> wheel_load{};  ///< [N]
  double throttle = 0.0;          ///< [-]
  unsigned status = 0;
};

}  // namespace scw::plant
