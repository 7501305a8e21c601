// Steady-state g-g-v limits of the plant, found by simulating the plant itself.
//
// Contract: for each speed v [m/s] three quasi-steady manoeuvres are simulated on a copy of the
// vehicle whose brake and steering actuators are made ideal (no delay, no lag, no rate limit;
// the steering lock stays), so that the limits reflect tyres, loads, aero and powertrain only:
//   lateral:   constant speed v (throttle/brake speed controller), slow steering ramp to the left;
//              result = max over 50 ms windows of mean a_y that are quasi-steady (|v_x - v| <= 2 %
//              v, mean yaw acceleration <= 0.3 rad/s^2), before the car departs from steady
//              cornering (a_y drop, sideslip > 0.25 rad). This is the a_x = 0 point of the g-g
//              diagram as tyres, loads (incl. downforce) and balance allow it: the copy used here
//              has no aero drag and no rolling resistance (downforce unchanged), so holding v
//              needs only the small cornering drag and neither power nor drag compensation bounds
//              the result (they are in `traction_max`). At low speed the steering lock may bound
//              a_y (`lateral_lock_limited`).
//   braking:   straight line from v + dv, per-wheel ideal slip controller (integral on the relaxed
//              slip) at target slip kappa*; result = mean deceleration -a_x while |v_x - v| <= 2 %
//              v, maximised over kappa* in {3 .. 12 %}.
//   traction:  straight line from v - dv, full throttle with an ideal rear slip limiter, gears
//              automatic; result = mean a_x while passing v outside gear shifts, maximised over
//              the target slip (0 when v is above the reachable top speed).
// Accelerations are body-frame specific forces [m/s^2] (accelerometer), so braking includes drag
// and traction is net of drag, as a velocity-profile solver needs them. Deterministic and pure.
#pragma once

#include "params/schema/vehicle_params.h"

namespace scw::plant {

struct GgvPoint {
  double speed = 0.0;                 ///< [m/s]
  double lateral_max = 0.0;           ///< max |a_y| in steady cornering [m/s^2]
  double braking_max = 0.0;           ///< max deceleration (positive) [m/s^2]
  double traction_max = 0.0;          ///< max forward acceleration [m/s^2]
  bool lateral_lock_limited = false;  ///< the steering lock, not the tyres, bounded lateral_max
};

/// Limits at one speed (throws scw::ConfigError for invalid parameters). What `scw vehicle gg`
/// prints, speed by speed: a check of the planner's quasi-steady envelope
/// (controller/planning/envelope.h) against the simulated plant, not its source.
GgvPoint ComputeGgvPoint(const params::VehicleParams& p, double speed);

}  // namespace scw::plant
