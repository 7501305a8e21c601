// What one control tick of the closed loop (tuning/sim/closed_loop.h) produced, as the run's
// observers see it: the lap counter's result, the car's place on the track, the measurement, the
// motion controller's diagnostics, the stability controller's input and output, and the plant's
// tyre outputs of its last step. The observers (tuning/sim/run_observers.h) and the trace
// (tuning/sim/trace_schema.h) read nothing else, so a test can drive them with synthetic signals.
//
// A TickRecord refers to the loop's own objects (no copies per tick): it is valid only during the
// tick that built it, before the plant is stepped again.
//
// Units are SI; signs as in the referenced structs (> 0 left for lateral quantities).
#pragma once

#include <cmath>

#include "controller/motion/motion_controller.h"
#include "controller/stability/stability_controller.h"
#include "plant/sensors/measurement.h"
#include "plant/vehicle/vehicle.h"

namespace scw::tuning {

/// [deg/rad] Degrees per radian: the trace's `_deg` columns, the sideslip abort rule and the
/// sideslip excess integral all convert with this one constant.
inline constexpr double kRadToDeg = 180.0 / M_PI;

struct TickRecord {
  double t = 0.0;  ///< [s] controller time of the tick, tick · tS
  int lap = 0;     ///< laps completed up to and including this tick (LapCounter::laps)
  double s = 0.0;  ///< [m] arc length of the car's CoG projected on the track, in [0, L)
  double n = 0.0;  ///< [m] lateral offset from the centre line, > 0 left
  /// [rad] sideslip angle at the CoG from the measurement, atan2(v_y, max(|v_x|, 1 m/s)) (the
  /// floor keeps it small at crawling speed, where v_y/v_x means nothing).
  double beta = 0.0;
  double speed = 0.0;       ///< [m/s] hypot(v_x, v_y) of the measurement
  unsigned event_mask = 0;  ///< active scenario events: 1 throttle, 2 steer, 4 rear grip, 8 gust
  const plant::Measurement& meas;                  ///< sensors (with noise if enabled)
  const controller::motion::MotionOutput& motion;  ///< held motion output (tracking errors)
  /// What the stability controller was given: the requests after the scenario's faults
  /// (throttle_request, long_fx and steering_request are what the longitudinal controller, a
  /// throttle fault and a steering offset made of them).
  const controller::StabilityInput& input;
  const controller::StabilityOutput& output;  ///< what it commanded (held until the next tick)
  const plant::StepOutputs& plant;            ///< the plant's last step: slips, loads (tyre frame)
};

/// Whether any wheel's ABS or TC state machine is out of kInactive (what counts as "ABS active"
/// and "TC active" in the metrics and the trace).
inline bool AnyActive(const PerWheel<controller::SlipPhase>& phases) {
  for (const auto p : phases)
    if (p != controller::SlipPhase::kInactive) return true;
  return false;
}

}  // namespace scw::tuning
