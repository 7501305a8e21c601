#include "tuning/cost.h"

#include <cmath>

namespace scw::tuning {

CostBreakdown ScenarioCost(const RunMetrics& m, const params::CostWeights& w) {
  CostBreakdown c;
  const double mean = m.MeanLapTime();
  c.lap_time = std::isfinite(mean) ? mean : w.lap_time_cap;
  c.sideslip = w.sideslip_weight * m.sideslip_excess_integral;
  c.brake_energy = w.brake_energy_weight * m.esc_brake_energy / 1000.0;
  double progress = m.Progress();
  if (!std::isfinite(c.sideslip) || !std::isfinite(c.brake_energy) || !std::isfinite(c.lap_time)) {
    c.lap_time = w.lap_time_cap;
    c.sideslip = c.brake_energy = 0.0;
    progress = 0.0;
    c.abort = w.abort_base + w.abort_progress_weight;
  } else if (m.aborted()) {
    c.abort = w.abort_base + w.abort_progress_weight * (1.0 - progress);
  }
  c.total = c.lap_time + c.sideslip + c.brake_energy + c.abort;
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
