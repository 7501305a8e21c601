// The tuning cost of one run and of a scenario set.
//
//   J_s = T_lap + w_β · ∫ max(0, |β| − β_allow) dt
//         + [clean]    · (w_E · E_ESC + w_ABS · P_ABS + w_TC · C_TC)
//         + [critical] · (w_βmax · max(0, max|β| − β_allow) + w_e · max(0, max|e_lat| − e_allow))
//         + [aborted]  · (P_abort + w_progress · (1 − progress))
//
//   A maneuver scenario (kind: maneuver, tuning/maneuver/maneuver.h) drives no lap: its cost is
//   J_s = w_β · ∫ max(0, |β| − β_allow) dt + w_fail · (n_failed + Σ_failed min(1, miss_c))
//         + [aborted] · (P_abort + w_progress · (1 − progress)),
//   n_failed the standard's pass/fail criteria it failed (RunMetrics::criteria_failed), miss_c the
//   relative amount by which criterion c missed its limit (Σ: RunMetrics::criteria_miss), w_fail
//   = failed_criterion_weight. A maneuver aborts only on a non-finite state (progress 0).
//
//   T_lap:   mean of the completed laps [s]; lap_time_cap if none was completed
//   ∫…dt:    sideslip above the allowed angle [deg·s] (the paper's "sideslip violations")
//   clean scenarios (a lap that should need no intervention): every intervention costs —
//            E_ESC brake energy of ESC interventions [kJ], P_ABS pressure ABS released below
//            the request [bar·s], C_TC throttle TC cut below the request [s]
//   critical scenarios (a fault or grip event the stability control must save): interventions
//            are free; the largest sideslip above the allowed angle [deg] and the largest
//            lateral error above the allowed one [m] (lateral_error_weight, default 0) count
//   abort:   any abort (spin, lateral error, lock/spin, off track, NaN) costs more than any
//            completed run; the earlier the abort (the more distance lost), the higher the cost
//            (graded, so the optimiser sees progress even among failing sets)
//
//   J = Σ_s weight_s · J_s over the scenarios. Always finite: non-finite terms are replaced by the
//   abort cost with zero progress.
#pragma once

#include <string>
#include <vector>

#include "params/schema/cost_params.h"
#include "tuning/sim/metrics.h"

namespace scw::tuning {

struct CostBreakdown {
  double lap_time = 0.0;
  double sideslip = 0.0;
  double brake_energy = 0.0;   ///< ESC brake energy term (clean scenarios)
  double interventions = 0.0;  ///< ABS release and TC cut terms (clean scenarios)
  double max_sideslip = 0.0;   ///< largest-sideslip term (critical scenarios)
  double lateral_error = 0.0;  ///< largest-lateral-error term (critical scenarios)
  double criteria = 0.0;       ///< failed-criteria term (maneuver scenarios)
  double abort = 0.0;
  double total = 0.0;
};

/// `critical`: the scenario's kind is "critical" (see the header comment).
CostBreakdown ScenarioCost(const RunMetrics& m, const params::CostWeights& w,
                           bool critical = false);

/// The cost of a scenario of kind `kind` ("clean", "critical" or "maneuver").
CostBreakdown ScenarioCostOfKind(const RunMetrics& m, const params::CostWeights& w,
                                 const std::string& kind);

/// Σ weights[i] · J_i (weights default to 1).
double TotalCost(const std::vector<CostBreakdown>& per_scenario,
                 const std::vector<double>& weights);

}  // namespace scw::tuning
