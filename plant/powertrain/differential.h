// Rear differential: locked spool or limited-slip differential (LSD).
//
// Contract
//   Spool: omega_RL = omega_RR; the axle torque acts on both wheels as one rigid body.
//   LSD: open differential (equal input-torque split T_in/2 per wheel) plus a locking torque that
//   moves torque from the faster to the slower wheel:
//     M = tanh((omega_RL - omega_RR) / (2 s)) * max(preload, k |T_in|),
//     k = lsd_lock_drive if T_in >= 0 else lsd_lock_coast,
//   applied as -M on RL and +M on RR [N*m]. s = lsd_speed_scale [rad/s].
// Source: spec plant-and-track.md §2.4 (Open Car Dynamics RWD_LSD, J. Looman).
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "params/schema/vehicle_powertrain_params.h"

namespace scw::plant {

struct DifferentialConfig {
  explicit DifferentialConfig(const params::DifferentialParams& p)
      : spool(p.type == "spool"),
        preload(p.lsd_preload),
        lock_drive(p.lsd_lock_drive),
        lock_coast(p.lsd_lock_coast),
        inv_scale(1.0 / (2.0 * p.lsd_speed_scale)) {}
  bool spool = true;
  double preload = 0.0;
  double lock_drive = 0.0;
  double lock_coast = 0.0;
  double inv_scale = 1.0;
};

/// LSD locking torque M [N*m] (positive when RL turns faster than RR).
inline double LsdTorque(double omega_rl, double omega_rr, double input_torque,
                        const DifferentialConfig& c) noexcept {
  const double k = input_torque >= 0.0 ? c.lock_drive : c.lock_coast;
  const double capacity = std::max(c.preload, k * std::abs(input_torque));
  return std::tanh((omega_rl - omega_rr) * c.inv_scale) * capacity;
}

}  // namespace scw::plant
