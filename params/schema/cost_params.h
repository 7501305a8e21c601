// Weights of the tuning cost (tuning/optim/cost.h). Plain YAML, section `cost:` of a scenario-set
// file.
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
  double abs_release_weight = 0.002;
  double tc_cut_weight = 0.5;
  double max_sideslip_weight = 0.5;
  double failed_criterion_weight = 100.0;
  double lateral_error_allowed_m = 3.0;
  double lateral_error_weight = 0.0;

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
             .doc = "Cost per kJ of brake energy dissipated by ESC interventions, on clean "
                    "scenarios (kind: clean): an ESC brake pulse on a lap that needed none."});
    v.Field(s.abs_release_weight,
            {.key = "abs_release_weight",
             .unit = "s/(bar*s)",
             .lo = 0.0,
             .hi = 1e6,
             .doc = "Cost per bar·s of brake pressure ABS released below the request, on clean "
                    "scenarios (braking the motion controller asked for and did not get).",
             .optional = true});
    v.Field(s.tc_cut_weight,
            {.key = "tc_cut_weight",
             .unit = "s/s",
             .lo = 0.0,
             .hi = 1e6,
             .doc = "Cost per second of full throttle TC cut below the request, on clean "
                    "scenarios.",
             .optional = true});
    v.Field(s.max_sideslip_weight,
            {.key = "max_sideslip_weight",
             .unit = "s/deg",
             .lo = 0.0,
             .hi = 1e6,
             .doc = "Cost per degree of the largest |β| above sideslip_allowed_deg, on critical "
                    "scenarios (kind: critical): how close the car came to a spin.",
             .optional = true});
    v.Field(s.failed_criterion_weight,
            {.key = "failed_criterion_weight",
             .unit = "s",
             .lo = 0.0,
             .hi = 1e6,
             .doc = "Cost of each failed pass/fail criterion of a maneuver scenario (kind: "
                    "maneuver, docs/maneuvers.md), times 1 + its relative miss (capped at 1): a "
                    "yaw-rate ratio of 45 % against the 35 % limit costs 1.29 x this.",
             .optional = true,
             .omit_default = true});
    v.Field(s.lateral_error_allowed_m,
            {.key = "lateral_error_allowed_m",
             .unit = "m",
             .lo = 0.0,
             .hi = 1e3,
             .doc = "Largest lateral error from the reference that is free on critical scenarios "
                    "(3 m: the paper's simulation studies stop a run beyond it).",
             .optional = true,
             .omit_default = true});
    v.Field(s.lateral_error_weight,
            {.key = "lateral_error_weight",
             .unit = "s/m",
             .lo = 0.0,
             .hi = 1e6,
             .doc = "Cost per metre of the largest lateral error above lateral_error_allowed_m, on "
                    "critical scenarios: a car saved from a spin that ends metres off its line "
                    "is not saved well (0: not counted).",
             .optional = true,
             .omit_default = true});
  }
};

}  // namespace scw::params
