// Weights of the tuning cost (tuning/cost.h). Plain YAML, section `cost:` of a scenario-set file.
#pragma once

#include "params/schema/field.h"

namespace scw::params {

struct CostWeights {
  double sideslip_allowed_deg = 5.0;
  double sideslip_weight = 2.0;
  double abort_base = 200.0;
  double abort_progress_weight = 200.0;
  double lap_time_cap = 120.0;
  double brake_energy_weight = 0.02;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.sideslip_allowed_deg,
            {.key = "sideslip_allowed_deg",
             .unit = "deg",
             .lo = 0.0,
             .hi = 45.0,
             .doc = "|β| below this is free; above it the excess is integrated over time."});
    v.Field(s.sideslip_weight,
            {.key = "sideslip_weight",
             .unit = "s/(deg*s)",
             .lo = 0.0,
             .hi = 1e6,
             .doc = "Cost (in seconds of lap time) per deg·s of sideslip above the allowed "
                    "value."});
    v.Field(s.abort_base, {.key = "abort_base",
                           .unit = "s",
                           .lo = 0.0,
                           .hi = 1e9,
                           .doc = "Penalty of any aborted run (spin, off track, lock, NaN…); "
                                  "larger than any plausible lap time so that every completed "
                                  "run ranks better than any abort."});
    v.Field(s.abort_progress_weight,
            {.key = "abort_progress_weight",
             .unit = "s",
             .lo = 0.0,
             .hi = 1e9,
             .doc = "Extra penalty × (1 − fraction of the planned distance driven): an earlier "
                    "abort costs more."});
    v.Field(s.lap_time_cap, {.key = "lap_time_cap",
                             .unit = "s",
                             .lo = 1.0,
                             .hi = 1e6,
                             .doc = "Lap-time term of a run that completed no lap."});
    v.Field(s.brake_energy_weight,
            {.key = "brake_energy_weight",
             .unit = "s/kJ",
             .lo = 0.0,
             .hi = 1e6,
             .doc = "Small cost per kJ of brake energy dissipated by ESC interventions "
                    "(discourages needless braking)."});
  }
};

}  // namespace scw::params
