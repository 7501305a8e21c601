#include "tuning/optim/objective.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tuning/sim/run_summary.h"

namespace scw::tuning {

const char* ObjectiveKindName(ObjectiveKind k) {
  return k == ObjectiveKind::kConstrained ? "constrained" : "sum";
}

ObjectiveKind ObjectiveKindFromName(const std::string& name) {
  if (name == "constrained") return ObjectiveKind::kConstrained;
  if (name == "sum") return ObjectiveKind::kSum;
  throw std::invalid_argument("unknown objective '" + name +
                              "' (constrained: the stability cost within the clean-lap budget; "
                              "sum: the weighted sum of every scenario's cost)");
}

std::array<int, 4> Activations(const RunMetrics& m) {
  return {m.esc_count, m.cs_count, m.abs_count, m.tc_count};
}

std::string LapBudgetText(double lap_s) {
  if (!std::isfinite(lap_s)) return "none";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", lap_s);
  return buf;
}

TuneObjective::TuneObjective(ObjectiveKind kind, CleanLapBudget budget,
                             std::vector<std::string> names, std::vector<std::string> kinds,
                             std::vector<double> weights, params::CostWeights cost,
                             SetEvaluation base)
    : kind_(kind),
      budget_(budget),
      names_(std::move(names)),
      kinds_(std::move(kinds)),
      weights_(std::move(weights)),
      cost_(cost),
      base_(std::move(base)) {
  const std::size_t n = names_.size();
  if (kinds_.size() != n || (!weights_.empty() && weights_.size() != n) || base_.runs.size() != n ||
      base_.costs.size() != n)
    throw std::invalid_argument("TuneObjective: the scenario counts of the inputs differ");
  if (!(budget_.lap_s >= 0.0))
    throw std::invalid_argument("the clean-lap budget must be >= 0 s, got " +
                                FormatFixed(budget_.lap_s, 3));
  base_value_ = Of(base_);
}

TuneObjective TuneObjective::For(const BatchEvaluator& ev, ObjectiveKind kind,
                                 CleanLapBudget budget, SetEvaluation base) {
  std::vector<std::string> names, kinds;
  for (const auto& sc : ev.scenarios()) {
    names.push_back(sc.spec.name);
    kinds.push_back(sc.spec.kind);
  }
  return TuneObjective(kind, budget, std::move(names), std::move(kinds), ev.weights(), ev.cost(),
                       std::move(base));
}

TuneObjective TuneObjective::WithBudget(CleanLapBudget budget) const {
  return TuneObjective(kind_, budget, names_, kinds_, weights_, cost_, base_);
}

bool TuneObjective::has_clean() const {
  return std::count(kinds_.begin(), kinds_.end(), "clean") > 0;
}

ObjectiveValue TuneObjective::Of(const SetEvaluation& e) const {
  ObjectiveValue v;
  v.total = e.total;
  if (!e.invalid.empty() || e.runs.size() != names_.size()) {
    // A rejected set never ran: it costs what the evaluator charged, and is outside any budget.
    v.stability = v.merit = e.total;
    v.violation = std::numeric_limits<double>::infinity();
    v.lap_loss = std::numeric_limits<double>::infinity();
    return v;
  }
  bool any_lap = false;
  for (std::size_t s = 0; s < names_.size(); ++s) {
    const double w = weights_.empty() ? 1.0 : weights_[s];
    if (kinds_[s] != "clean") {
      v.stability += w * e.costs[s].total;
      continue;
    }
    CleanLapCheck c;
    c.scenario = names_[s];
    const RunMetrics& b = base_.runs[s];
    const RunMetrics& m = e.runs[s];
    c.base_completed = !b.aborted();
    c.completed = !m.aborted();
    c.base_lap = b.MeanLapTime();
    c.lap = m.MeanLapTime();
    c.activations = Activations(m);
    c.base_activations = Activations(b);
    if (c.base_completed) {
      std::string breach;
      if (!c.completed) {
        c.violation += cost_.lap_time_cap;
        breach = "aborts (" + std::string(RunStatusName(m.status)) + ")";
        v.lap_loss = std::numeric_limits<double>::infinity();
      } else {
        c.lap_loss = c.lap - c.base_lap;
        // The largest change, faster laps included (a front's axis); 0 without a clean lap.
        v.lap_loss = any_lap ? std::max(v.lap_loss, c.lap_loss) : c.lap_loss;
        any_lap = true;
        if (c.lap_loss > budget_.lap_s) {
          c.violation += c.lap_loss - budget_.lap_s;
          breach = FormatSigned(c.lap_loss, 3) + " s a lap over " + LapBudgetText(budget_.lap_s);
        }
      }
      for (std::size_t k = 0; k < 4; ++k) {
        const int extra = c.activations[k] - c.base_activations[k];
        if (extra <= 0) continue;
        v.extra_activations += extra;
        if (!budget_.interventions) continue;
        c.violation += kActivationViolation * extra;
        breach += std::string(breach.empty() ? "" : "; ") + kSubsystemNames[k] + " " +
                  std::to_string(c.activations[k]) + " > " + std::to_string(c.base_activations[k]);
      }
      c.breach = breach;
    }
    v.violation += c.violation;
    v.clean.push_back(std::move(c));
  }
  if (kind_ == ObjectiveKind::kSum)
    v.merit = e.total;
  else
    v.merit = v.violation > 0.0
                  ? v.stability + base_value_.stability + kViolationSlope * v.violation
                  : v.stability;
  return v;
}

std::string TuneObjective::Describe() const {
  if (kind_ == ObjectiveKind::kSum)
    return "the weighted sum of every training scenario's cost (clean laps included)";
  std::string out = "the stability cost of the critical training scenarios";
  if (!has_clean()) return out + " (no clean scenario: no clean-lap budget)";
  std::vector<std::string> parts;
  if (std::isfinite(budget_.lap_s))
    parts.push_back("no clean lap slower than the base set's by more than " +
                    LapBudgetText(budget_.lap_s));
  if (budget_.interventions)
    parts.push_back("no subsystem acting more often on a clean lap than with the base set");
  if (parts.empty()) return out + " (no clean-lap budget: whatever it takes to survive)";
  out += ", subject to: ";
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? ", " : "") + parts[i];
  return out;
}

std::string CleanLapMarkdown(const ObjectiveValue& v, const CleanLapBudget& budget,
                             const std::string& set_label, int level) {
  std::string out =
      std::string(static_cast<std::size_t>(level), '#') +
      " Clean laps against the base set (budget " + LapBudgetText(budget.lap_s) + " a lap" +
      (budget.interventions ? ", no more activations" : ", activations free") + ")\n\n";
  if (v.clean.empty()) return out + "No clean scenario.\n\n";
  out += "| scenario | base lap [s] | " + set_label +
         " lap [s] | change [s/lap] | ESC/CS/ABS/TC base -> " + set_label +
         " | within budget |\n| --- | --- | --- | --- | --- | --- |\n";
  const auto counts = [](const std::array<int, 4>& a) {
    return std::to_string(a[0]) + "/" + std::to_string(a[1]) + "/" + std::to_string(a[2]) + "/" +
           std::to_string(a[3]);
  };
  for (const auto& c : v.clean) {
    const auto lap = [](bool done, double t) {
      return done ? FormatFixed(t, 3) : std::string("-");
    };
    out += "| " + c.scenario + " | " + lap(c.base_completed, c.base_lap) + " | " +
           lap(c.completed, c.lap) + " | " +
           (std::isfinite(c.lap_loss) ? FormatSigned(c.lap_loss, 3) : std::string("-")) + " | " +
           counts(c.base_activations) + " -> " + counts(c.activations) + " | " +
           (!c.base_completed  ? std::string("not constrained (the base aborts)")
            : c.breach.empty() ? std::string("yes")
                               : "**no**: " + c.breach) +
           " |\n";
  }
  return out + "\n";
}

}  // namespace scw::tuning
