#include "tuning/optim/comparison.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "params/io/csv.h"
#include "params/io/write.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {

std::string ComparisonMarkdown(const std::string& title, const BatchEvaluator& ev,
                               const std::vector<std::string>& labels,
                               const std::vector<SetEvaluation>& results) {
  std::string out = "### " + title + "\n\n";
  out +=
      "| scenario | set | status | mean lap [s] | max abs beta [deg] | max lat. err. [m] | "
      "ESC/CS/ABS/TC [count] | cost |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (std::size_t k = 0; k < ev.scenarios().size(); ++k)
    for (std::size_t s = 0; s < results.size(); ++s) {
      const RunMetrics& m = results[s].runs[k];
      const double lap = m.MeanLapTime();
      out +=
          "| " + ev.scenarios()[k].spec.name + " | " + labels[s] + " | " + RunStatusName(m.status) +
          (m.aborted() ? " (" + FormatFixed(100.0 * m.Progress(), 0) + " %)" : std::string()) +
          " | " + (std::isfinite(lap) ? FormatFixed(lap, 3) : std::string("-")) + " | " +
          FormatFixed(RenderedMetric(m, "max_abs_sideslip_deg").real, 2) + " | " +
          FormatFixed(m.max_abs_lateral_error, 2) + " | " + std::to_string(m.esc_count) + "/" +
          std::to_string(m.cs_count) + "/" + std::to_string(m.abs_count) + "/" +
          std::to_string(m.tc_count) + " | " + FormatFixed(results[s].costs[k].total, 3) + " |\n";
    }
  // Per set: the total, and the distribution over the scenarios (unweighted scenario costs: what a
  // set does in its bad cases, which a total can hide) with the subsystems' activations summed.
  out +=
      "\n| set | total cost | mean cost | 90th percentile | worst | aborts | ESC/CS/ABS/TC "
      "[count] |\n| --- | --- | --- | --- | --- | --- | --- |\n";
  for (std::size_t s = 0; s < results.size(); ++s) {
    const CostDistribution d = Distribution(results[s]);
    long long esc = 0, cs = 0, abs = 0, tc = 0;
    for (const RunMetrics& m : results[s].runs) {
      esc += m.esc_count;
      cs += m.cs_count;
      abs += m.abs_count;
      tc += m.tc_count;
    }
    out += "| " + labels[s] + " | " + FormatFixed(results[s].total, 3) + " | " +
           FormatFixed(d.mean, 3) + " | " + FormatFixed(d.p90, 3) + " | " +
           FormatFixed(d.worst, 3) + " | " + std::to_string(d.aborts) + " of " +
           std::to_string(results[s].runs.size()) + " | " + std::to_string(esc) + "/" +
           std::to_string(cs) + "/" + std::to_string(abs) + "/" + std::to_string(tc) + " |\n";
  }
  return out + "\n";
}

namespace {
/// The RunMetrics columns of the comparison CSV (names, units and conversions: RunMetrics::Visit).
constexpr std::string_view kComparisonColumns[] = {kProgressKey,
                                                   kMeanLapTimeKey,
                                                   "max_abs_sideslip_deg",
                                                   "max_abs_lateral_error_m",
                                                   "esc_count",
                                                   "cs_count",
                                                   "abs_count",
                                                   "tc_count",
                                                   "esc_brake_energy_J"};

std::string CsvNumber(double x) {
  return std::isnan(x) ? std::string("nan") : params::FormatDouble(x);
}
}  // namespace

std::string ComparisonCsv(const std::string& group, const BatchEvaluator& ev,
                          const std::vector<std::string>& labels,
                          const std::vector<SetEvaluation>& results, bool header) {
  std::string out;
  if (header) {
    out += "group,scenario,set,status";
    for (std::string_view c : kComparisonColumns) out += "," + std::string(c);
    out += ",cost,total_cost\n";
  }
  for (std::size_t k = 0; k < ev.scenarios().size(); ++k)
    for (std::size_t s = 0; s < results.size(); ++s) {
      const RunMetrics& m = results[s].runs[k];
      out += io::CsvField(group) + "," + io::CsvField(ev.scenarios()[k].spec.name) + "," +
             io::CsvField(labels[s]) + "," + RunStatusName(m.status);
      for (std::string_view c : kComparisonColumns) {
        const MetricValue v = RenderedMetric(m, c);
        out += "," + (v.is_integer ? std::to_string(v.integer) : CsvNumber(v.real));
      }
      out += "," + CsvNumber(results[s].costs[k].total) + "," + CsvNumber(results[s].total) + "\n";
    }
  return out;
}

namespace {
std::string Count(int n, const char* what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}
}  // namespace

std::string TunedFileHeader(const TuneProvenance& p, bool overrides) {
  std::string out = "Tuned by scw tune " + p.tool_version + " (git " + p.git_revision + ") on " +
                    p.date_utc + "\n";
  out += "run folder: " + p.run_folder + "\n";
  out += "base: " + p.base + "\n";
  out += "search: " + p.algorithm + ", seed " + std::to_string(p.seed) + ", " +
         Count(p.evaluations, "evaluation") + " (stop: " + p.stop_reason + "); space " + p.space +
         ", " + Count(p.dimensions, "dimension") + "\n";
  for (const auto& g : p.grown) out += "  range grown to include the base: " + g + "\n";
  if (!p.objective.empty()) out += "objective: " + p.objective + "\n";
  if (!p.clean_laps.empty()) out += "clean laps: " + p.clean_laps + "\n";
  if (!p.knife_edges.empty()) out += "knife edges: " + p.knife_edges + "\n";
  out += "cost (lower is better): base -> tuned\n";
  out += "  training (" + Count(p.training_scenarios, "scenario") +
         "): " + FormatFixed(p.training_before, 3) + " -> " + FormatFixed(p.training_after, 3) +
         "\n";
  if (p.held_out_scenarios > 0)
    out += "  held-out (" + Count(p.held_out_scenarios, "scenario") +
           ", not used for tuning): " + FormatFixed(p.held_out_before, 3) + " -> " +
           FormatFixed(p.held_out_after, 3) + "\n";
  if (p.changed.empty()) {
    out += "changed keys: none (the tuned set equals the base)\n";
  } else {
    out += "changed keys (" + std::to_string(p.changed.size()) + "):";
    std::string line;
    for (std::size_t i = 0; i < p.changed.size(); ++i) {
      const std::string item = " " + p.changed[i] + (i + 1 < p.changed.size() ? "," : "");
      if (!line.empty() && line.size() + item.size() > 90) {
        out += line + "\n ";
        line.clear();
      }
      line += item;
    }
    out += line + "\n";
  }
  const auto list = [&out](const std::string& title, const std::vector<std::string>& items) {
    if (items.empty()) return;
    out += title + " (" + std::to_string(items.size()) + "), kept at the base value:\n";
    for (const auto& item : items) out += "  " + item + "\n";
  };
  list("frozen before the search: no training run changes when the parameter alone spans its range",
       p.frozen);
  list("reverted after the search, each with the whole set re-evaluated", p.reverted);
  if (!p.revert_skipped.empty())
    out += "not checked for untested changes after the search (" + p.revert_skipped +
           "): run the sensitivity before using this file\n";
  for (const auto& f : p.new_findings) out += "NEW params check finding: " + f + "\n";
  out +=
      "Tuned values are rounded to their schema resolution (within one step of the base: the base "
      "value);\nevery other key is the base value.\n";
  if (overrides)
    out +=
        "Overrides only: load AFTER the base file (later params files win), e.g.\n"
        "  --ros-args --params-file base.yaml --params-file stability_overrides.yaml";
  else
    out +=
        "Complete params file: load it INSTEAD of the base file, e.g.\n"
        "  --ros-args --params-file stability_tuned.yaml";
  return out;
}

const char* OutcomeChangeName(OutcomeChange c) {
  switch (c) {
    case OutcomeChange::kCompletedBoth:
      return "completed in both";
    case OutcomeChange::kAbortedBoth:
      return "aborted in both";
    case OutcomeChange::kNewAbort:
      return "completed -> aborted";
    case OutcomeChange::kAbortFixed:
      return "aborted -> completed";
  }
  return "?";
}

const char* CostChangeName(CostChange c) {
  switch (c) {
    case CostChange::kBetter:
      return "better";
    case CostChange::kNoSignificantChange:
      return "no significant change";
    case CostChange::kWorse:
      return "worse";
  }
  return "?";
}

const char* VerdictName(Verdict v) {
  switch (v) {
    case Verdict::kImproves:
      return "improves";
    case Verdict::kNoSignificantChange:
      return "no_significant_change";
    case Verdict::kWorse:
      return "worse";
    case Verdict::kMixed:
      return "mixed";
  }
  return "?";
}

namespace {
CostChange Judge(double before, double after, double threshold) {
  const double d = after - before;
  if (!(std::abs(d) >= threshold)) return CostChange::kNoSignificantChange;  // NaN: no claim
  return d < 0 ? CostChange::kBetter : CostChange::kWorse;
}
}  // namespace

SetChange CompareSets(const std::vector<std::string>& names, const std::vector<double>& weights,
                      const SetEvaluation& baseline, const SetEvaluation& tuned,
                      double resolution) {
  const std::size_t n = names.size();
  if (baseline.runs.size() != n || tuned.runs.size() != n || baseline.costs.size() != n ||
      tuned.costs.size() != n || (!weights.empty() && weights.size() != n))
    throw std::invalid_argument("CompareSets: the scenario counts of the inputs differ");
  SetChange out;
  for (std::size_t k = 0; k < n; ++k) {
    ScenarioChange c;
    c.scenario = names[k];
    c.before = baseline.runs[k];
    c.after = tuned.runs[k];
    c.weight = weights.empty() ? 1.0 : weights[k];
    c.cost_before = baseline.costs[k].total;
    c.cost_after = tuned.costs[k].total;
    c.threshold = resolution;
    const bool a0 = c.before.aborted(), a1 = c.after.aborted();
    c.outcome = a0 ? (a1 ? OutcomeChange::kAbortedBoth : OutcomeChange::kAbortFixed)
                   : (a1 ? OutcomeChange::kNewAbort : OutcomeChange::kCompletedBoth);
    if (c.outcome == OutcomeChange::kNewAbort)
      c.change = CostChange::kWorse;
    else if (c.outcome == OutcomeChange::kAbortFixed)
      c.change = CostChange::kBetter;
    else
      c.change = Judge(c.cost_before, c.cost_after, c.threshold);
    out.better += c.change == CostChange::kBetter;
    out.worse += c.change == CostChange::kWorse;
    out.new_aborts += c.outcome == OutcomeChange::kNewAbort;
    out.scenarios.push_back(std::move(c));
  }
  out.total_before = baseline.total;
  out.total_after = tuned.total;
  out.total_threshold = resolution;
  out.total_change = Judge(out.total_before, out.total_after, out.total_threshold);
  if (out.new_aborts > 0)
    out.verdict = Verdict::kWorse;
  else if (out.better == 0 && out.worse == 0)
    out.verdict = out.total_change == CostChange::kBetter  ? Verdict::kImproves
                  : out.total_change == CostChange::kWorse ? Verdict::kWorse
                                                           : Verdict::kNoSignificantChange;
  else if (out.worse == 0)
    out.verdict = Verdict::kImproves;
  else if (out.better == 0)
    out.verdict = Verdict::kWorse;
  else
    out.verdict = Verdict::kMixed;
  return out;
}

SetChange CompareSets(const BatchEvaluator& ev, const SetEvaluation& baseline,
                      const SetEvaluation& tuned, double resolution) {
  std::vector<std::string> names;
  for (const auto& sc : ev.scenarios()) names.push_back(sc.spec.name);
  return CompareSets(names, ev.weights(), baseline, tuned, resolution);
}

namespace {

/// "-0.400 (-0.10 %)"
std::string Delta(double before, double after) {
  std::string out = FormatSigned(after - before, 3);
  if (before != 0.0)
    out += " (" + FormatSigned(100.0 * (after - before) / std::abs(before), 2) + " %)";
  return out;
}

std::string Outcome(const RunMetrics& m) {
  if (!m.aborted()) {
    const double lap = m.MeanLapTime();
    return std::isfinite(lap) ? "completed, mean lap " + FormatFixed(lap, 3) + " s"
                              : std::string("completed");
  }
  return std::string(RunStatusName(m.status)) + " at " + FormatFixed(100.0 * m.Progress(), 1) +
         " % of the distance";
}

std::string Scenarios(int n) { return Count(n, "scenario"); }
}  // namespace

CostDistribution Distribution(std::vector<double> costs, int aborts) {
  CostDistribution d;
  d.aborts = aborts;
  if (costs.empty()) return d;
  std::sort(costs.begin(), costs.end());
  double sum = 0.0;
  for (double x : costs) sum += x;
  d.mean = sum / static_cast<double>(costs.size());
  // Nearest rank: the smallest cost that at least 90 % of the scenarios do not exceed.
  const auto rank = static_cast<std::size_t>(std::ceil(0.9 * static_cast<double>(costs.size())));
  d.p90 = costs[std::max<std::size_t>(rank, 1) - 1];
  d.worst = costs.back();
  return d;
}

CostDistribution Distribution(const SetChange& c, bool after) {
  std::vector<double> costs;
  int aborts = 0;
  for (const auto& s : c.scenarios) {
    costs.push_back(after ? s.cost_after : s.cost_before);
    aborts += (after ? s.after : s.before).aborted();
  }
  return Distribution(std::move(costs), aborts);
}

CostDistribution Distribution(const SetEvaluation& e) {
  std::vector<double> costs;
  int aborts = 0;
  for (const auto& c : e.costs) costs.push_back(c.total);
  for (const auto& m : e.runs) aborts += m.aborted();
  return Distribution(std::move(costs), aborts);
}

std::string SetChangeMarkdown(const std::string& group, const SetChange& c) {
  std::string out = "**" + group + " verdict: ";
  switch (c.verdict) {
    case Verdict::kImproves: {
      int among_aborts = 0;
      for (const auto& s : c.scenarios)
        among_aborts += s.change == CostChange::kBetter && s.outcome == OutcomeChange::kAbortedBoth;
      out +=
          "the tuned set improves the cost** (better in " + Scenarios(c.better) + ", worse in none";
      if (c.better > 0 && among_aborts == c.better)
        out += c.better == 1 ? "; that scenario aborts with both sets: the tuned set gets further "
                               "or fails more gently, it does not make it drivable"
                             : "; all of them abort with both sets: the tuned set gets further "
                               "or fails more gently, it does not make them drivable";
      out += ").\n";
      break;
    }
    case Verdict::kNoSignificantChange:
      out +=
          "no significant change** (no scenario and not the total changes by the resolution of " +
          FormatFixed(c.total_threshold, 2) + " s or more).\n";
      break;
    case Verdict::kWorse:
      out += "the tuned set is WORSE** (";
      if (c.new_aborts > 0)
        out += Scenarios(c.new_aborts) + " completed by the baseline " +
               (c.new_aborts == 1 ? "aborts" : "abort") + " with the tuned set";
      else if (c.worse > 0)
        out += "worse in " + Scenarios(c.worse) + ", better in " + Scenarios(c.better);
      else
        out += "the total cost rises by more than the resolution";
      out +=
          "): possible over-fitting to the training scenarios; review before using it on the "
          "car.\n";
      break;
    case Verdict::kMixed:
      out += "mixed** (better in " + Scenarios(c.better) + ", worse in " + Scenarios(c.worse) +
             "): review the worse ones before using the set on the car.\n";
      break;
  }
  out += "\nTotal cost " + FormatFixed(c.total_before, 3) + " -> " + FormatFixed(c.total_after, 3) +
         ": " + Delta(c.total_before, c.total_after) + ", " + CostChangeName(c.total_change) +
         " (resolution " + FormatFixed(c.total_threshold, 2) + " s).\n\n";
  // The distribution over the scenarios (unweighted scenario costs): what a set does in its bad
  // cases, which a total can hide (a robust set is judged by its worst draws).
  out +=
      "| set | mean cost | 90th percentile | worst | aborts |\n| --- | --- | --- | --- | --- |\n";
  for (const bool after : {false, true}) {
    const CostDistribution d = Distribution(c, after);
    out += std::string("| ") + (after ? "tuned" : "baseline") + " | " + FormatFixed(d.mean, 3) +
           " | " + FormatFixed(d.p90, 3) + " | " + FormatFixed(d.worst, 3) + " | " +
           std::to_string(d.aborts) + " of " + std::to_string(c.scenarios.size()) + " |\n";
  }
  out += "\n";

  bool weighted = false;
  for (const auto& s : c.scenarios) weighted = weighted || s.weight != 1.0;
  out += std::string("| scenario class | scenarios | cost change") +
         (weighted ? " (weighted)" : "") +
         " | better | no significant change | worse |\n| --- | --- | --- | --- | --- | --- |\n";
  for (OutcomeChange oc : {OutcomeChange::kCompletedBoth, OutcomeChange::kAbortedBoth,
                           OutcomeChange::kNewAbort, OutcomeChange::kAbortFixed}) {
    int n = 0, counts[3] = {0, 0, 0};
    double delta = 0.0;
    for (const auto& s : c.scenarios) {
      if (s.outcome != oc) continue;
      ++n;
      ++counts[static_cast<int>(s.change)];
      delta += s.weight * (s.cost_after - s.cost_before);
    }
    if (n == 0) continue;
    out += std::string("| ") + OutcomeChangeName(oc) + " | " + std::to_string(n) + " | " +
           FormatSigned(delta, 3) + " | " + std::to_string(counts[0]) + " | " +
           std::to_string(counts[1]) + " | " + std::to_string(counts[2]) + " |\n";
  }
  out +=
      "\n| scenario | class | baseline | tuned | cost | change | verdict |\n"
      "| --- | --- | --- | --- | --- | --- | --- |\n";
  for (const auto& s : c.scenarios) {
    std::string tuned = Outcome(s.after);
    if (s.outcome == OutcomeChange::kAbortedBoth) {
      const double p0 = s.before.Progress(), p1 = s.after.Progress();
      if (p1 != p0) tuned += p1 > p0 ? " (later)" : " (earlier)";
    }
    out +=
        "| " + s.scenario + " | " + OutcomeChangeName(s.outcome) + " | " + Outcome(s.before) +
        " | " + tuned + " | " + FormatFixed(s.cost_before, 3) + " -> " +
        FormatFixed(s.cost_after, 3) + " | " + Delta(s.cost_before, s.cost_after) + " | " +
        CostChangeName(s.change) +
        (s.change == CostChange::kNoSignificantChange ? " (< " + FormatFixed(s.threshold, 3) + ")"
                                                      : std::string()) +
        " |\n";
  }
  out +=
      "\nResolution: the simulation is deterministic, so every difference is real; a change "
      "of a scenario's cost (seconds, per lap for the lap time) smaller than " +
      FormatFixed(c.total_threshold, 2) +
      " s, two steps of the 100 Hz controllers, is called no significant change, and so is "
      "the total's. A scenario the baseline completes and the tuned set aborts is always "
      "worse, the reverse always better.\n\n";
  return out;
}

}  // namespace scw::tuning
