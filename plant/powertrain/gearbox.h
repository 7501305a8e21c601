// Sequential gearbox with automatic shifting by engine speed and a torque interruption.
//
// Contract
//   State (GearboxState): engaged gear g_e (1..N, transmits torque), requested gear g_r, phase,
//   time in phase [s]. The measurement exposes both: g_r changes when the shift is decided,
//   g_e changes when the new gear engages after shift_time; in between (phase kShifting) the
//   driveline transmits no torque (torque interruption, clutch/dog ring open).
//   Edges of the pure transition Next(state, engine_speed, dt, config):
//     kEngaged  -> kShifting  up:   t_phase >= min_time_in_gear, g_e < N, omega_e >= up[g_e]
//     kEngaged  -> kShifting  down: t_phase >= min_time_in_gear, g_e > 1, omega_e <= down[g_e]
//     kEngaged  -> kEngaged         otherwise (t_phase += dt)
//     kShifting -> kEngaged         t_phase + dt >= shift_time (g_e = g_r, t_phase = 0)
//     kShifting -> kShifting        otherwise (t_phase += dt)
//   omega_e is the kinematic engine speed (rear-axle speed x i_g(g_e) x i_f) [rad/s].
// Source: spec plant-and-track.md §3.1 (automatic mode of the sim_vehicle_dynamics gearbox).
#pragma once

#include <vector>

#include "params/schema/vehicle_powertrain_params.h"

namespace scw::plant {

enum class ShiftPhase { kEngaged, kShifting };

struct GearboxState {
  int engaged = 1;    ///< gear that transmits torque, 1-based
  int requested = 1;  ///< gear the shift logic asks for, 1-based
  ShiftPhase phase = ShiftPhase::kEngaged;
  double time_in_phase = 0.0;  ///< [s]
};

/// Gearbox constants in SI units, built once from params::GearboxParams.
struct GearboxConfig {
  explicit GearboxConfig(const params::GearboxParams& p);
  int gears = 1;
  std::vector<double> ratio;    ///< i_g, index gear-1
  std::vector<double> overall;  ///< i_g i_f, index gear-1
  std::vector<double> eta;      ///< eta_g eta_f, index gear-1
  std::vector<double> up;       ///< upshift engine speed of gear g at index g-1 [rad/s]
  std::vector<double> down;     ///< downshift engine speed of gear g at index g-1 [rad/s]
  double shift_time = 0.0;
  double min_time_in_gear = 0.0;
};

/// Pure transition (exhaustive over ShiftPhase).
GearboxState Next(const GearboxState& s, double engine_speed, double dt,
                  const GearboxConfig& c) noexcept;

/// Gear whose kinematic engine speed at wheel speed omega_axle [rad/s] is closest to mid-band
/// (used for rolling starts): the lowest gear that is below its upshift speed.
int GearForSpeed(double omega_axle, int initial_gear, const GearboxConfig& c) noexcept;

}  // namespace scw::plant
