#include "tuning/optim/revert.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "params/io/write.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {
namespace {

/// Why a trial is refused ("" when it is kept).
std::string Refusal(const TuneObjective& objective, const SetEvaluation& current,
                    const ObjectiveValue& current_value, const SetEvaluation& trial,
                    const ObjectiveValue& trial_value, double tolerance) {
  std::vector<std::string> aborted;
  for (std::size_t s = 0; s < trial.runs.size() && s < current.runs.size(); ++s)
    if (!current.runs[s].aborted() && trial.runs[s].aborted())
      aborted.push_back(objective.names()[s] + " (" + RunStatusName(trial.runs[s].status) + ")");
  if (!aborted.empty()) {
    std::string out = "reverting it aborts ";
    for (std::size_t i = 0; i < aborted.size(); ++i) out += (i ? ", " : "") + aborted[i];
    return out;
  }
  if (current_value.within_budget() && !trial_value.within_budget()) {
    std::string out = "reverting it breaks the clean-lap budget:";
    for (const auto& c : trial_value.clean)
      if (!c.breach.empty()) out += " " + c.scenario + " " + c.breach + ";";
    out.pop_back();
    return out;
  }
  const double d = trial_value.merit - current_value.merit;
  if (d > tolerance)
    return "reverting it costs " + FormatSigned(d, 3) + " s of merit, more than the " +
           params::FormatNumber(tolerance) + " s the clean-lap budget allows";
  return "";
}

}  // namespace

RevertResult RevertJointly(const BatchEvaluator& ev, const ParameterSpace& space,
                           const params::StabilityParams& base, const std::vector<double>& u,
                           std::vector<int> pinned,
                           const std::vector<std::pair<int, std::string>>& candidates,
                           const TuneObjective& objective, SetEvaluation current, double tolerance,
                           const BatchProgress& progress) {
  RevertResult r;
  r.pinned = std::move(pinned);
  r.evaluation = std::move(current);
  r.value = objective.Of(r.evaluation);
  params::StabilityParams current_set = space.WithPinned(r.pinned).Decode(u, base, nullptr);
  int done = 0;
  const int total = static_cast<int>(candidates.size());
  for (const auto& [dim, why] : candidates) {
    if (progress) progress(++done, total);
    if (std::count(r.pinned.begin(), r.pinned.end(), dim)) continue;
    RevertDecision d;
    d.dim = dim;
    d.label = space.entries()[static_cast<std::size_t>(dim)].Label();
    std::vector<int> trial_pins = r.pinned;
    trial_pins.push_back(dim);
    Problems pr;
    params::StabilityParams trial = space.WithPinned(trial_pins).Decode(u, base, &pr);
    if (!pr.empty()) {
      d.reason = "NOT reverted: the base value would break " + pr.items()[0].path;
      r.decisions.push_back(std::move(d));
      continue;
    }
    if (params::DifferingKeys(trial, current_set).empty()) continue;  // left at the base
    SetEvaluation e = ev.Evaluate(trial);
    ++r.evaluations;
    const ObjectiveValue v = objective.Of(e);
    d.merit_change = v.merit - r.value.merit;
    const std::string refusal = Refusal(objective, r.evaluation, r.value, e, v, tolerance);
    if (refusal.empty()) {
      d.reverted = true;
      d.reason = why;
      r.pinned = std::move(trial_pins);
      current_set = std::move(trial);
      r.evaluation = std::move(e);
      r.value = v;
    } else {
      d.reason = "kept: " + refusal;
    }
    r.decisions.push_back(std::move(d));
  }
  return r;
}

std::vector<std::string> RevertedItems(const RevertResult& r) {
  std::vector<std::string> out;
  for (const auto& d : r.decisions)
    if (d.reverted) out.push_back(d.label + " (" + d.reason + ")");
  return out;
}

std::vector<std::string> KeptItems(const RevertResult& r) {
  std::vector<std::string> out;
  for (const auto& d : r.decisions)
    if (!d.reverted) out.push_back(d.label + " (" + d.reason + ")");
  return out;
}

}  // namespace scw::tuning
