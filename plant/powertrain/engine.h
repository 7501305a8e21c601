// Engine torque map with rev limiter.
//
// Contract
//   T_e(omega_e, throttle) = bilinear interpolation of params::EngineParams::map_torque over
//   (engine speed, throttle), held constant outside the breakpoints; positive torque is faded
//   linearly to 0 between rev_limit and rev_limit + band (rev limiter), negative (drag) torque is
//   kept.
//   Inputs: omega_e engine speed [rad/s] (>= 0), throttle [0..1] (clamped).
//   Output: crankshaft torque [N*m], > 0 drives.
// Source: spec plant-and-track.md §3.1 (sim_vehicle_dynamics engine map), §4.1 (AV-21 map).
// Immutable after construction, allocation-free and noexcept when evaluated.
#pragma once

#include <vector>

#include "params/schema/vehicle_powertrain_params.h"

namespace scw::plant {

class EngineMap {
 public:
  /// Expects validated parameters (sizes consistent).
  explicit EngineMap(const params::EngineParams& p);

  /// Crankshaft torque [N*m] incl. the rev limiter.
  double Torque(double omega_e, double throttle) const noexcept;

  /// Full-throttle torque [N*m] at omega_e (convenience for checks and g-g-v tools).
  double FullLoadTorque(double omega_e) const noexcept { return Torque(omega_e, 1.0); }

 private:
  std::vector<double> speed_;     // [rad/s]
  std::vector<double> throttle_;  // [-]
  std::vector<double> torque_;    // row-major [N*m]
  double limit_ = 0.0;            // [rad/s]
  double inv_band_ = 0.0;         // [s/rad]
};

/// rpm -> rad/s.
inline constexpr double RpmToRadPerSec(double rpm) { return rpm * 0.10471975511965977; }
inline constexpr double RadPerSecToRpm(double w) { return w * 9.549296585513721; }

}  // namespace scw::plant
