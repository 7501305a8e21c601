// Reference manoeuvre of the plant alone (no controller): the workload of `scw bench --plant`
// and of the plant benchmark, and a smoke test of the whole model.
//
// Contract: a deterministic open-loop/speed-feedback programme with a 20 s period, repeated:
//   0-8 s    full throttle limited to ~3 % rear slip, small sine steer (0.01 rad, 0.5 Hz):
//            launch, gear shifts
//   8-10 s   threshold-type braking, 70 bar front / 50 bar rear (delay, lock-up at low speed)
//   10-16 s  speed held near 40 m/s by throttle, 0.05 rad steer: cornering up to the limit
//   16-20 s  slalom, 0.03 rad at 0.8 Hz, throttle 0.7
// ReferenceManeuverInput() is the pure driver law (time and measurement -> actuators);
// RunReferenceManeuver() steps a state for `duration` [s] and summarises the run, on scw's plant
// or on any plant of the plant interface (plant/vehicle/plant_model.h: `scw bench --plant` times
// both plants on it). No wall clock: the caller times it.
#pragma once

#include <algorithm>
#include <cmath>

#include "plant/vehicle/plant_model.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant {

/// Throttle of a simple driver who limits rear-wheel slip (omega r - v)/max(v, 3 m/s) to about
/// `target_slip` (proportional law, full throttle below it). Pure; used by tests and manoeuvres.
double SlipLimitedThrottle(const Measurement& m, double rear_radius, double target_slip,
                           double throttle_max = 1.0) noexcept;

/// Actuator requests of the reference manoeuvre at time t for measurement m.
Actuators ReferenceManeuverInput(double t, const Measurement& m, double rear_radius) noexcept;

struct ManeuverSummary {
  long steps = 0;
  double sim_time = 0.0;    ///< [s]
  double distance = 0.0;    ///< path length [m]
  double max_speed = 0.0;   ///< [m/s]
  double max_abs_ay = 0.0;  ///< [m/s^2]
  unsigned status = 0;      ///< plant::Status bits at the end
};

/// Runs the reference manoeuvre for `duration` [s] on `s` (made by v.MakeState(); from rest by
/// default), on any plant model.
template <PlantModel P>
ManeuverSummary RunReferenceManeuverOn(const P& v, double duration, StateOf<P>* s) noexcept {
  ManeuverSummary sum;
  const double h = v.time_step();
  const long steps = std::lround(duration / h);
  const double t0 = s->time;
  const double radius = v.params().wheels.radius_rear;
  for (long k = 0; k < steps; ++k) {
    const Measurement m = v.Measure(*s);
    v.Step(ReferenceManeuverInput(s->time - t0, m, radius), s);
    const double speed = std::hypot(s->x[kVx], s->x[kVy]);
    sum.distance += speed * h;
    sum.max_speed = std::max(sum.max_speed, speed);
    sum.max_abs_ay = std::max(sum.max_abs_ay, std::abs(s->out.a_y));
  }
  sum.steps = steps;
  sum.sim_time = steps * h;
  sum.status = s->status;
  return sum;
}

/// The same on scw's plant.
ManeuverSummary RunReferenceManeuver(const Vehicle& v, double duration, State* s) noexcept;

}  // namespace scw::plant
