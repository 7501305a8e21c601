// Comparison of parameter sets on an evaluator's scenarios (scw tune, scw evaluate): tables,
// the resolution, per-scenario changes and the verdict, the tuned file's header.
#pragma once

#include <string>
#include <vector>

#include "tuning/optim/evaluator.h"

namespace scw::tuning {

/// Side-by-side comparison of parameter sets on the scenarios of an evaluator: per scenario and
/// set the status, mean lap time, max |β|, interventions and cost; then the totals.
/// `labels[i]` names `results[i]` (one SetEvaluation per parameter set).
std::string ComparisonMarkdown(const std::string& title, const BatchEvaluator& ev,
                               const std::vector<std::string>& labels,
                               const std::vector<SetEvaluation>& results);
/// The same data as CSV rows (with a header when `header` is true).
std::string ComparisonCsv(const std::string& group, const BatchEvaluator& ev,
                          const std::vector<std::string>& labels,
                          const std::vector<SetEvaluation>& results, bool header);

/// The smallest change of a scenario's cost that a comparison calls a change [s; per lap for
/// the lap-time term, which is a mean lap]. The closed loop is deterministic: there is no noise to
/// stay above, every difference is real. But the controllers run at 100 Hz, so a lap's end moves
/// in whole 10 ms steps, and a change of one or two steps says nothing about the set: 0.02 s is
/// two steps. An abort is judged as an abort, never by its cost. The same value for the total.
inline constexpr double kDefaultResolution = 0.02;

/// How a scenario's outcome changes from the baseline to the tuned set.
enum class OutcomeChange {
  kCompletedBoth,  ///< completed with both sets
  kAbortedBoth,    ///< aborted with both sets (the cost then mostly measures how far it got)
  kNewAbort,       ///< completed with the baseline, aborted with the tuned set
  kAbortFixed,     ///< aborted with the baseline, completed with the tuned set
};
const char* OutcomeChangeName(OutcomeChange c);  ///< "completed in both", …

enum class CostChange { kBetter, kNoSignificantChange, kWorse };
const char* CostChangeName(CostChange c);  ///< "better", "no significant change", "worse"

/// One scenario: baseline vs tuned.
struct ScenarioChange {
  std::string scenario;
  OutcomeChange outcome = OutcomeChange::kCompletedBoth;
  RunMetrics before, after;                    ///< the baseline's and the tuned set's run
  double weight = 1.0;                         ///< the scenario's weight in the total
  double cost_before = 0.0, cost_after = 0.0;  ///< J_s (unweighted)
  double threshold = 0.0;                      ///< the resolution it was judged with
  /// kNewAbort is always kWorse and kAbortFixed always kBetter; otherwise by the cost change
  /// against the resolution (lower cost = better).
  CostChange change = CostChange::kNoSignificantChange;
};

/// Overall judgement of a tuned set on a group of scenarios.
enum class Verdict {
  kImproves,             ///< some scenario significantly better, none worse, no new abort
  kNoSignificantChange,  ///< no scenario and not the total changes by the resolution or more
  kWorse,                ///< a new abort, or some scenario worse and none better
  kMixed,                ///< significantly better in some scenarios, worse in others
};
/// "improves", "no_significant_change", "worse", "mixed" (e.g. for manifest.yaml).
const char* VerdictName(Verdict v);

struct SetChange {
  std::vector<ScenarioChange> scenarios;
  double total_before = 0.0, total_after = 0.0;  ///< Σ weight · J
  double total_threshold = 0.0;                  ///< the resolution
  CostChange total_change = CostChange::kNoSignificantChange;
  int better = 0, worse = 0, new_aborts = 0;  ///< scenario counts
  /// When no scenario changes significantly, the total decides (many small gains can add up);
  /// otherwise a new abort → kWorse, then better/worse counts as documented at Verdict.
  Verdict verdict = Verdict::kNoSignificantChange;
};

/// Compares the tuned set with the baseline scenario by scenario: a cost change of at least
/// `resolution` [s] is a change (kDefaultResolution). `names` and `weights` are per scenario (as
/// in a BatchEvaluator). Throws std::invalid_argument when the sizes differ.
SetChange CompareSets(const std::vector<std::string>& names, const std::vector<double>& weights,
                      const SetEvaluation& baseline, const SetEvaluation& tuned,
                      double resolution = kDefaultResolution);
SetChange CompareSets(const BatchEvaluator& ev, const SetEvaluation& baseline,
                      const SetEvaluation& tuned, double resolution = kDefaultResolution);

/// The distribution of the unweighted scenario costs of one side of a comparison.
struct CostDistribution {
  double mean = 0.0;
  double p90 = 0.0;  ///< nearest rank: the smallest cost ≥ that of 90 % of the scenarios
  double worst = 0.0;
  int aborts = 0;
};
/// The distribution of `costs` (one per scenario, any order) with `aborts` aborted runs.
CostDistribution Distribution(std::vector<double> costs, int aborts);
/// The baseline's (`after` false) or the tuned set's distribution.
CostDistribution Distribution(const SetChange& c, bool after);
/// The distribution of one evaluated set's scenario costs.
CostDistribution Distribution(const SetEvaluation& e);

/// The verdict as Markdown for comparison.md: one bold line with the overall verdict and the
/// total's change against the resolution, the cost distribution of both sets (mean, 90th
/// percentile, worst, aborts), a table of the change per scenario class, a table
/// per scenario (outcome, cost change, verdict) and the threshold rule. `group` names the
/// scenarios, e.g. "Held-out".
std::string SetChangeMarkdown(const std::string& group, const SetChange& c);

/// Where a tuned params file comes from (scw tune), for the comment header of the exported files.
struct TuneProvenance {
  std::string tool_version;  ///< scw version
  std::string git_revision;  ///< of the workspace that built scw
  std::string run_folder;
  std::string date_utc;  ///< ISO 8601, e.g. 2026-05-04T10:21:07Z
  std::string base;      ///< the base params file, or a description of the built-in set
  std::string algorithm;
  unsigned long long seed = 0;
  int evaluations = 0;
  std::string stop_reason;
  std::string space;               ///< space file or "built-in default"
  int dimensions = 0;              ///< tuned dimensions
  std::vector<std::string> grown;  ///< entries whose range was grown to include the base
  int training_scenarios = 0;      ///< costs: base set ("before") and tuned set ("after")
  double training_before = 0, training_after = 0;
  int held_out_scenarios = 0;  ///< 0: no held-out scenarios (their costs are not printed)
  double held_out_before = 0, held_out_after = 0;
  std::vector<std::string> changed;  ///< dotted keys whose exported value differs from the base
  /// Dimensions frozen at the base value before the search (no training run changes when the
  /// parameter alone moves to either end of its range), and reverted to the base after it (zero
  /// sensitivity at the tuned point); each "label (reason)".
  std::vector<std::string> frozen, reverted;
  /// Why no revert was possible ("" when the sensitivity ran), e.g. "--no-sensitivity".
  std::string revert_skipped;
  /// `scw params check` findings of the tuned set that the base set does not have ("key: text").
  std::vector<std::string> new_findings;
  /// What the search minimised (TuneObjective::Describe), how the exported set meets the clean-lap
  /// budget, and the knife-edge check's result ("" = not printed).
  std::string objective, clean_laps, knife_edges;
};

/// Comment lines (without the leading '#', joined by '\n') for the head of the tuned full file
/// (`overrides` false) or the overrides-only file: tool version, git revision, run folder, date,
/// base, search settings, training and held-out cost before and after, the changed keys and how
/// to load the file on the car.
std::string TunedFileHeader(const TuneProvenance& p, bool overrides);

}  // namespace scw::tuning
