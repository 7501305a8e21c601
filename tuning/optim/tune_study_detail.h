// Internal to the tune study (tune_study.cc, tune_report.cc): the parts of a tune's report that
// are texts — comparison.md and the exported files — composed from the phases' results.
#pragma once

#include <string>
#include <vector>

#include "tuning/optim/tune_study.h"

namespace scw::tuning::detail {

/// How the comparison and the set check name a built-in base.
std::string BaseName(const std::string& base_file);

/// ", batch 4" after the algorithm when candidates were evaluated in batches ("" for 1).
std::string BatchNote(int batch);

/// "label (reason)" for the dimensions `dims` of a sensitivity result.
std::vector<std::string> Described(const SensitivityResult& r, const std::vector<int>& dims);

/// Appends " — moved with its reference R to keep their relation" to each frozen or reverted item
/// whose key a moved reference forced off its base value.
void AnnotateKeptRelations(const TuneStudy& study, TuneReport* report);

/// comparison.csv: the rows of both groups (ComparisonCsv), one header.
std::string ComparisonReportCsv(const TuneReport& r, const BatchEvaluator& training,
                                const BatchEvaluator* held_out);

/// The answer of comparison.md's head, in a few lines: objective, stability cost and aborts base
/// -> tuned, the clean laps against the budget, search best against exported, knife edges.
std::string AnswerMarkdown(const TuneStudy& study, const TuneReport& r);

/// comparison.md without the plots (report.comparison_markdown): the answer, what the file
/// changes and why, the clean laps, the tables and verdicts of both groups, the knife edges, the
/// plant-step check and the sensitivity. `training` and `held_out` (may be null) are the
/// evaluators the tables ran on.
std::string ComparisonReportMarkdown(const TuneStudy& study, const TuneReport& r,
                                     const BatchEvaluator& training,
                                     const BatchEvaluator* held_out);

/// The tuned full and overrides-only params files with their provenance header, checked as the
/// car's node would load them (throws std::runtime_error when a check fails).
void ComposeTunedFiles(const TuneStudy& study, TuneReport* report);

}  // namespace scw::tuning::detail
