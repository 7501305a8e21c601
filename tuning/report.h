// Human- and machine-readable renderings of run metrics.
#pragma once

#include <string>

#include "tuning/metrics.h"

namespace scw::tuning {

/// A short multi-line table: status, laps, extremes, interventions.
std::string FormatRunSummary(const std::string& name, const RunMetrics& m);
/// The same as plain YAML (key: value), numbers in shortest round-trip form.
std::string RunSummaryYaml(const std::string& name, const RunMetrics& m);

}  // namespace scw::tuning

#include <vector>

#include "tuning/evaluator.h"

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
};

/// Comment lines (without the leading '#', joined by '\n') for the head of the tuned full file
/// (`overrides` false) or the overrides-only file: tool version, git revision, run folder, date,
/// base, search settings, training and held-out cost before and after, the changed keys and how
/// to load the file on the car.
std::string TunedFileHeader(const TuneProvenance& p, bool overrides);

}  // namespace scw::tuning
