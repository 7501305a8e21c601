#include "tuning/optim/training_objective.h"

#include <algorithm>
#include <cmath>

#include "params/io/write.h"

namespace scw::tuning {

TrainingObjective::TrainingObjective(const ParameterSpace& space,
                                     const params::StabilityParams& base,
                                     const BatchEvaluator& training, const TuneObjective& objective,
                                     bool split)
    : space_(space),
      base_(base),
      training_(training),
      objective_(objective),
      split_(split),
      invalid_cost_((training.cost().abort_base + training.cost().abort_progress_weight +
                     training.cost().lap_time_cap) *
                        static_cast<double>(std::max<std::size_t>(1, training.scenarios().size())) +
                    (constrained() ? objective.base_value().merit : 0.0)) {}

std::vector<std::string> TrainingObjective::LogHeader() const {
  std::vector<std::string> extra;
  for (const auto& e : space_.entries()) extra.push_back("x:" + e.Label());
  for (const auto& sc : training_.scenarios()) {
    extra.push_back("cost:" + sc.spec.name);
    extra.push_back("status:" + sc.spec.name);
    extra.push_back("lap:" + sc.spec.name);
  }
  if (constrained()) {
    extra.push_back("stability");
    extra.push_back("lap_loss");
    extra.push_back("violation");
  }
  return extra;
}

TrainingObjective::Pending TrainingObjective::Decode(
    const std::vector<std::vector<double>>& points) const {
  Pending p;
  p.evaluations.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (double x : space_.Arguments(points[i]))
      p.evaluations[i].columns.push_back(params::FormatDouble(x));
    Problems pr;
    params::StabilityParams set = space_.Decode(points[i], base_, &pr);
    if (!pr.empty()) {
      p.evaluations[i].cost = invalid_cost_;
      p.evaluations[i].constraint = split_ ? 1e6 : 0.0;
      p.evaluations[i].status = "infeasible: " + pr.items()[0].path;
      continue;
    }
    p.sets.push_back(std::move(set));
    p.at.push_back(i);
  }
  return p;
}

std::vector<Evaluation> TrainingObjective::Complete(
    Pending pending, const std::vector<SetEvaluation>& results) const {
  std::vector<Evaluation> evs = std::move(pending.evaluations);
  for (std::size_t v = 0; v < pending.at.size(); ++v) {
    const SetEvaluation& r = results[v];
    Evaluation& ev = evs[pending.at[v]];
    int aborts = 0;
    for (std::size_t k = 0; k < r.runs.size(); ++k) {
      aborts += r.runs[k].aborted();
      ev.columns.push_back(params::FormatDouble(r.costs[k].total));
      ev.columns.push_back(RunStatusName(r.runs[k].status));
      const double lap = r.runs[k].MeanLapTime();
      ev.columns.push_back(std::isfinite(lap) ? params::FormatDouble(lap) : "nan");
    }
    std::string status = aborts ? std::to_string(aborts) + " abort(s)" : "";
    if (constrained()) {
      const ObjectiveValue value = objective_.Of(r);
      ev.cost = split_ ? value.stability : value.merit;
      if (split_) ev.constraint = value.violation;
      ev.columns.push_back(params::FormatDouble(value.stability));
      ev.columns.push_back(params::FormatDouble(value.lap_loss));
      ev.columns.push_back(params::FormatDouble(value.violation));
      if (!value.within_budget()) status += std::string(status.empty() ? "" : "; ") + "over budget";
    } else {
      ev.cost = r.total;
    }
    ev.status = status.empty() ? "ok" : status;
  }
  return evs;
}

std::vector<Evaluation> TrainingObjective::operator()(
    const std::vector<std::vector<double>>& points) const {
  Pending p = Decode(points);
  if (p.sets.empty()) return std::move(p.evaluations);
  const std::vector<SetEvaluation> results = training_.Evaluate(p.sets);
  return Complete(std::move(p), results);
}

void TopPoints::Add(int index, const std::vector<double>& u, double cost) {
  entries_.push_back({index, cost, u});
  std::stable_sort(entries_.begin(), entries_.end(), [](const TopPoint& a, const TopPoint& b) {
    return a.cost != b.cost ? a.cost < b.cost : a.index < b.index;
  });
  if (entries_.size() > keep_) entries_.pop_back();
}

}  // namespace scw::tuning
