// Human- and machine-readable renderings of run metrics.
#pragma once

#include <string>

#include "tuning/sim/metrics.h"

namespace scw::tuning {

/// `x` with `digits` decimals (printf %.*f), the number format of the human-readable summaries.
std::string FormatFixed(double x, int digits);
/// The same with its sign always written (printf %+.*f): changes, "+0.310".
std::string FormatSigned(double x, int digits);

/// A short multi-line table: status, laps, extremes, interventions.
std::string FormatRunSummary(const std::string& name, const RunMetrics& m);
/// The same as plain YAML (key: value), numbers in shortest round-trip form.
std::string RunSummaryYaml(const std::string& name, const RunMetrics& m);

}  // namespace scw::tuning
