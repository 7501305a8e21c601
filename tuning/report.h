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

}  // namespace scw::tuning
