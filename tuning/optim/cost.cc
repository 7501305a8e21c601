#include "tuning/optim/cost.h"

#include <algorithm>
#include <cmath>

namespace scw::tuning {

CostBreakdown ScenarioCost(const RunMetrics& m, const params::CostWeights& w, bool critical) {
  CostBreakdown c;
  const double mean = m.MeanLapTime();
  c.lap_time = std::isfinite(mean) ? mean : w.lap_time_cap;
  c.sideslip = w.sideslip_weight * m.sideslip_excess_integral;
  if (critical) {
    const double excess = RenderedMetric(m, "max_abs_sideslip_deg").real - w.sideslip_allowed_deg;
    if (w.max_sideslip_weight > 0.0) c.max_sideslip = w.max_sideslip_weight * std::max(0.0, excess);
    if (w.lateral_error_weight > 0.0)
      c.lateral_error = w.lateral_error_weight *
                        std::max(0.0, m.max_abs_lateral_error - w.lateral_error_allowed_m);
  } else {
    c.brake_energy = w.brake_energy_weight * m.esc_brake_energy / 1000.0;
    if (w.abs_release_weight > 0.0 || w.tc_cut_weight > 0.0)
      c.interventions =
          w.abs_release_weight * m.abs_pressure_released + w.tc_cut_weight * m.tc_throttle_cut;
  }
  double progress = m.Progress();
  if (!std::isfinite(c.sideslip) || !std::isfinite(c.brake_energy) || !std::isfinite(c.lap_time) ||
      !std::isfinite(c.interventions) || !std::isfinite(c.max_sideslip) ||
      !std::isfinite(c.lateral_error)) {
    c.lap_time = w.lap_time_cap;
    c.sideslip = c.brake_energy = c.interventions = c.max_sideslip = c.lateral_error = 0.0;
    progress = 0.0;
    c.abort = w.abort_base + w.abort_progress_weight;
  } else if (m.aborted()) {
    c.abort = w.abort_base + w.abort_progress_weight * (1.0 - progress);
  }
  c.total = c.lap_time + c.sideslip + c.brake_energy + c.interventions + c.max_sideslip +
            c.lateral_error + c.abort;
  return c;
}

CostBreakdown ScenarioCostOfKind(const RunMetrics& m, const params::CostWeights& w,
                                 const std::string& kind) {
  if (kind != "maneuver") return ScenarioCost(m, w, kind == "critical");
  CostBreakdown c;
  c.sideslip = w.sideslip_weight * m.sideslip_excess_integral;
  c.criteria = w.failed_criterion_weight * (m.criteria_failed + m.criteria_miss);
  if (!std::isfinite(c.sideslip) || !std::isfinite(c.criteria)) {
    c.sideslip = c.criteria = 0.0;
    c.abort = w.abort_base + w.abort_progress_weight;
  } else if (m.aborted()) {
    c.abort = w.abort_base + w.abort_progress_weight * (1.0 - m.Progress());
  }
  c.total = c.sideslip + c.criteria + c.abort;
  return c;
}

double TotalCost(const std::vector<CostBreakdown>& per_scenario,
                 const std::vector<double>& weights) {
  double j = 0.0;
  for (std::size_t i = 0; i < per_scenario.size(); ++i)
    j += (i < weights.size() ? weights[i] : 1.0) * per_scenario[i].total;
  return j;
}

}  // namespace scw::tuning
