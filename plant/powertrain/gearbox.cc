#include "plant/powertrain/gearbox.h"

#include <limits>

#include "plant/powertrain/engine.h"

namespace scw::plant {

GearboxConfig::GearboxConfig(const params::GearboxParams& p)
    : gears(static_cast<int>(p.ratios.size())),
      ratio(p.ratios),
      shift_time(p.shift_time),
      min_time_in_gear(p.min_time_in_gear) {
  for (int g = 0; g < gears; ++g) {
    overall.push_back(p.ratios[g] * p.final_drive_ratio);
    eta.push_back(p.efficiency[g] * p.final_drive_efficiency);
    up.push_back(g + 1 < gears ? RpmToRadPerSec(p.upshift_rpm[g])
                               : std::numeric_limits<double>::infinity());
    down.push_back(g > 0 ? RpmToRadPerSec(p.downshift_rpm[g - 1]) : -1.0);
  }
}

GearboxState Next(const GearboxState& s, double engine_speed, double dt,
                  const GearboxConfig& c) noexcept {
  GearboxState n = s;
  switch (s.phase) {
    case ShiftPhase::kEngaged: {
      const bool may_shift = s.time_in_phase >= c.min_time_in_gear;
      const int g = s.engaged;
      if (may_shift && g < c.gears && engine_speed >= c.up[g - 1]) {
        n.requested = g + 1;
      } else if (may_shift && g > 1 && engine_speed <= c.down[g - 1]) {
        n.requested = g - 1;
      } else {
        n.time_in_phase += dt;
        return n;
      }
      n.phase = ShiftPhase::kShifting;
      n.time_in_phase = 0.0;
      return n;
    }
    case ShiftPhase::kShifting:
      if (s.time_in_phase + dt >= c.shift_time) {
        n.engaged = s.requested;
        n.phase = ShiftPhase::kEngaged;
        n.time_in_phase = 0.0;
      } else {
        n.time_in_phase += dt;
      }
      return n;
  }
  return n;
}

int GearForSpeed(double omega_axle, int initial_gear, const GearboxConfig& c) noexcept {
  if (!(omega_axle > 0.0)) return initial_gear;
  for (int g = 1; g < c.gears; ++g)
    if (omega_axle * c.overall[g - 1] < c.up[g - 1]) return g;
  return c.gears;
}

}  // namespace scw::plant
