// The tuning cost of one run and of a scenario set.
//
//   J_s = T_lap + w_β · ∫ max(0, |β| − β_allow) dt  + w_E · E_ESC
//         + [aborted] · (P_abort + w_progress · (1 − progress))
//
//   T_lap:   mean of the completed laps [s]; lap_time_cap if none was completed
//   ∫…dt:    sideslip above the allowed angle [deg·s] (the paper's "sideslip violations")
//   E_ESC:   brake energy of ESC interventions [kJ] (a small weight: do not brake needlessly)
//   abort:   any abort (spin, lateral error, lock/spin, off track, NaN) costs more than any
//            completed run; the earlier the abort, the higher the cost (graded, so the optimiser
//            sees progress even among failing sets)
//
//   J = Σ_s weight_s · J_s over the scenarios. Always finite: non-finite terms are replaced by the
//   abort cost with zero progress.
#pragma once

#include <vector>

#include "params/schema/cost_params.h"
#include "tuning/metrics.h"

namespace scw::tuning {

struct CostBreakdown {
  double lap_time = 0.0;
  double sideslip = 0.0;
  double brake_energy = 0.0;
  double abort = 0.0;
  double total = 0.0;
};

CostBreakdown ScenarioCost(const RunMetrics& m, const params::CostWeights& w);

/// Σ weights[i] · J_i (weights default to 1).
double TotalCost(const std::vector<CostBreakdown>& per_scenario,
                 const std::vector<double>& weights);

}  // namespace scw::tuning
