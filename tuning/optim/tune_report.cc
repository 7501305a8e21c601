// The texts of a tune (tune_study_detail.h): comparison.md and the exported params files.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "params/io/ros2_check.h"
#include "params/io/write.h"
#include "tuning/optim/tune_study_detail.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning::detail {
namespace {

int Aborts(const SetEvaluation& e) {
  int n = 0;
  for (const auto& m : e.runs) n += m.aborted();
  return n;
}

void CheckExport(const std::string& text, bool complete, const std::string& path) {
  params::CheckOptions co;
  co.node_key = params::kStabilityNodeKey;
  co.expect_complete = complete;
  const auto rep =
      params::CheckRosParamsText(text, params::DeclaredParams<params::StabilityParams>(), co);
  if (!rep.ok())
    throw std::runtime_error("the export " + path + " fails the ROS 2 params check:\n" +
                             rep.Format(path));
}

/// "within the budget (largest change +0.012 s a lap, no extra activation)" or what breaks it.
std::string BudgetLine(const ObjectiveValue& v, const CleanLapBudget& b) {
  if (v.clean.empty()) return "no clean scenario";
  std::string out;
  if (v.within_budget()) {
    out = "every clean lap within the budget of " + LapBudgetText(b.lap_s) + " a lap";
  } else {
    out = "**over the budget**:";
    for (const auto& c : v.clean)
      if (!c.breach.empty()) out += " " + c.scenario + " " + c.breach + ";";
    out.pop_back();
  }
  if (std::isfinite(v.lap_loss))
    out += " (largest change " + FormatSigned(v.lap_loss, 3) + " s a lap";
  else
    out += " (a clean lap aborts";
  out += v.extra_activations == 0
             ? ", no activation the base set does not have)"
             : ", " + std::to_string(v.extra_activations) + " activations more than the base)";
  return out;
}

/// comparison.md's section on what the exported file changes and why.
std::string WhatChangedMarkdown(const TuneReport& r) {
  std::string md = "## What the tuned file changes\n\n";
  md += "- convergence: " + r.convergence + "\n";
  if (!r.selection.empty()) {
    md += "- selected at the vehicle's step: " + EvaluationName(r.chosen_eval) +
          " (the best within the budget of the search's best points run there):\n";
    for (const auto& s : r.selection) md += "  - " + s + "\n";
  }
  if (!r.screened)
    md += "- frozen before the search: not screened (freezing off)\n";
  else if (r.frozen.empty())
    md +=
        "- frozen before the search: none (every parameter changes some training run at an end "
        "of its range)\n";
  else {
    md += "- frozen before the search at the base value (" + std::to_string(r.frozen.size()) +
          "; no training run changes when the parameter alone moves to either end of its "
          "range):\n";
    for (const auto& f : r.frozen) md += "  - " + f + "\n";
  }
  if (r.sensitivity_state != SensitivityState::kDone) {
    md +=
        "- reverted after the search: **not checked** (the sensitivity did not run); the file "
        "may change parameters no training run responds to\n";
  } else {
    const auto kept = KeptItems(r.revert);
    md += "- reverted after the search, one at a time with the whole set re-evaluated (" +
          std::to_string(r.reverted.size()) + "; " + std::to_string(r.revert.evaluations) +
          " evaluations):" + (r.reverted.empty() ? " none\n" : "\n");
    for (const auto& f : r.reverted) md += "  - " + f + "\n";
    if (!kept.empty()) {
      md +=
          "- not reverted although no single change of it moved a run (it acts together with "
          "others):\n";
      for (const auto& k : kept)
        if (k.find("NOT reverted") == std::string::npos) md += "  - " + k + "\n";
    }
  }
  if (r.new_findings.empty())
    md += "- `scw params check`: no finding the base set does not have\n";
  else {
    md += "- `scw params check`: **" + std::to_string(r.new_findings.size()) +
          " finding(s) the base set does not have**:\n";
    for (const auto& f : r.new_findings) md += "  - " + f + "\n";
  }
  md += "- the tables below evaluate exactly the exported file\n\n";
  return md;
}

}  // namespace

void AnnotateKeptRelations(const TuneStudy& study, TuneReport* report) {
  const ParameterSpace exported = study.space().WithPinned(report->pinned_dims);
  const std::set<std::string> diff = params::DifferingKeys(report->tuned, study.base());
  for (auto* list : {&report->frozen, &report->reverted})
    for (auto& item : *list)
      for (const auto& e : exported.entries())
        if (e.pinned && !e.of.empty() && diff.count(e.key) && item.rfind(e.Label() + " (", 0) == 0)
          item += " — moved with its reference " + e.of + " to keep their relation";
}

std::string AnswerMarkdown(const TuneStudy& study, const TuneReport& r) {
  const TuneStudyOptions& o = study.options();
  const TuneResult& opt = r.optimisation;
  std::string md = "## The answer\n\n";
  md += "- objective: " + r.objective + "\n";
  if (o.objective == ObjectiveKind::kConstrained)
    md += "- stability cost (critical training scenarios): " +
          FormatFixed(r.base_value.stability, 3) + " -> " +
          FormatFixed(r.tuned_value.stability, 3) + "; aborts " +
          std::to_string(Aborts(r.training[0])) + " -> " + std::to_string(Aborts(r.training[1])) +
          " of " + std::to_string(r.training[0].runs.size()) + " training runs\n";
  else
    md += "- training cost: " + FormatFixed(r.training[0].total, 3) + " -> " +
          FormatFixed(r.training[1].total, 3) + "; aborts " +
          std::to_string(Aborts(r.training[0])) + " -> " + std::to_string(Aborts(r.training[1])) +
          "\n";
  md += "- clean laps (training): " + BudgetLine(r.tuned_value, o.budget) + "\n";
  if (!r.held_out.empty())
    md += "- clean laps (held-out): " + BudgetLine(r.held_out_value, o.budget) + "; aborts " +
          std::to_string(Aborts(r.held_out[0])) + " -> " + std::to_string(Aborts(r.held_out[1])) +
          " of " + std::to_string(r.held_out[0].runs.size()) + "\n";
  const std::string step_ms = params::FormatNumber(r.plant_step.used() * 1000.0);
  md += "- search best: merit " + FormatFixed(opt.best_cost, 3) + " at " +
        EvaluationName(opt.best_eval) + " (base " + FormatFixed(opt.start_cost, 3) +
        (r.plant_step.used() > 0 ? ", at the " + step_ms + " ms search step" : std::string()) +
        "); exported: merit " + FormatFixed(r.tuned_value.merit, 3) + " (base " +
        FormatFixed(r.base_value.merit, 3) + ") at the vehicle's step, " +
        std::to_string(r.changed.size()) + " key(s) changed\n";
  if (!r.unexported_gain.empty()) md += "- **" + r.unexported_gain + "**\n";
  if (r.neighbourhood_done) {
    const auto keys = r.neighbourhood.EdgeKeys();
    const int own = OwnEdges(r.neighbourhood);
    md += "- knife edges: ";
    if (r.neighbourhood.edges.empty()) {
      md += "none";
    } else {
      md += "**" + std::to_string(own) + " the set's own**, " +
            std::to_string(static_cast<int>(r.neighbourhood.edges.size()) - own) +
            " where the base set is lost too (";
      for (std::size_t i = 0; i < keys.size(); ++i) md += (i ? ", " : "") + keys[i];
      md += ")";
    }
    md += " in " + std::to_string(r.neighbourhood.neighbours.size()) + " neighbours\n";
    if (o.robust)
      md += "- robust: " + std::to_string(r.neighbourhood_before_robust.edges.size()) +
            " knife edge(s) before, " + std::to_string(r.neighbourhood.edges.size()) + " after " +
            std::to_string(r.robust_rounds) + " round(s) (" + std::to_string(r.robust_evaluations) +
            " evaluations); largest clean-lap change " +
            FormatSigned(r.tuned_value_before_robust.lap_loss, 3) + " -> " +
            FormatSigned(r.tuned_value.lap_loss, 3) + " s a lap\n";
  } else {
    md += "- knife edges: not checked\n";
  }
  return md + "\n";
}

std::string ComparisonReportMarkdown(const TuneStudy& study, const TuneReport& r,
                                     const BatchEvaluator& training,
                                     const BatchEvaluator* held_out) {
  const TuneStudyOptions& o = study.options();
  const std::vector<std::string> labels = {"baseline", "tuned"};
  std::string md = "# scw tune: comparison\n\nbaseline = " + BaseName(o.base_file) +
                   "; tuned = the exported set, from " + std::to_string(r.optimisation.evals) +
                   " evaluations (" + o.algorithm + BatchNote(o.batch) + ", seed " +
                   std::to_string(o.seed) + "), " + std::to_string(r.changed.size()) +
                   " key(s) changed\n\n";
  md += AnswerMarkdown(study, r);
  md += WhatChangedMarkdown(r);
  md += CleanLapMarkdown(r.tuned_value, o.budget, "tuned");
  md += ComparisonMarkdown("Training scenarios", training, labels, r.training);
  md += "\n" + SetChangeMarkdown("Training", r.training_change);
  if (held_out && !r.held_out.empty()) {
    md += "### Held-out clean laps\n\n" + CleanLapMarkdown(r.held_out_value, o.budget, "tuned", 4);
    md += ComparisonMarkdown("Held-out scenarios (not used for tuning)", *held_out, labels,
                             r.held_out);
    md += "\n" + SetChangeMarkdown("Held-out", r.held_out_change);
  }
  if (r.neighbourhood_done) {
    if (o.robust && r.robust_rounds > 0)
      md += "\n" + std::string("## Knife edges before the robust continuation\n\n") +
            NeighbourhoodMarkdown(r.neighbourhood_before_robust, 3);
    md += "\n" + NeighbourhoodMarkdown(r.neighbourhood);
  }
  if (r.plant_step.step > 0.0) md += "\n" + PlantStepCheckMarkdown(r.plant_step);
  if (r.sensitivity_state == SensitivityState::kDone)
    md += "\n" + SensitivityMarkdown(r.sensitivity, "the exported point before the revert");
  return md;
}

std::string ComparisonReportCsv(const TuneReport& r, const BatchEvaluator& training,
                                const BatchEvaluator* held_out) {
  const std::vector<std::string> labels = {"baseline", "tuned"};
  std::string csv = ComparisonCsv("training", training, labels, r.training, true);
  if (held_out && !r.held_out.empty())
    csv += ComparisonCsv("held_out", *held_out, labels, r.held_out, false);
  return csv;
}

void ComposeTunedFiles(const TuneStudy& study, TuneReport* report) {
  const TuneStudyOptions& o = study.options();
  const ScenarioSet& set = study.scenarios();
  const params::StabilityParams& base = study.base();
  const TuneResult& r = report->optimisation;
  TuneProvenance& prov = report->provenance;
  prov.tool_version = o.tool_version;
  prov.git_revision = o.git_revision;
  prov.run_folder = o.run_folder;
  prov.date_utc = o.date_utc ? o.date_utc() : std::string();
  prov.base =
      o.base_file.empty() ? std::string("built-in (the car's shipped parameters)") : o.base_file;
  prov.algorithm = o.algorithm + BatchNote(o.batch);
  prov.seed = o.seed;
  prov.evaluations = r.evals;
  prov.stop_reason = r.stop_reason;
  prov.space = o.space_file.empty() ? std::string("built-in default") : o.space_file;
  prov.dimensions = study.space().size();
  for (const auto& m : study.given_space().BaseMismatches(base))
    prov.grown.push_back(m.label + ": [" + params::FormatNumber(m.lo) + ", " +
                         params::FormatNumber(m.hi) + "] -> [" + params::FormatNumber(m.grown_lo) +
                         ", " + params::FormatNumber(m.grown_hi) + "]");
  prov.objective = report->objective;
  std::string clean = BudgetLine(report->tuned_value, o.budget);
  for (auto& c : clean)
    if (c == '*') c = ' ';
  prov.clean_laps = clean;
  if (report->neighbourhood_done)
    prov.knife_edges =
        report->neighbourhood.edges.empty()
            ? "none in " + std::to_string(report->neighbourhood.neighbours.size()) +
                  " neighbours (each changed key +-10 % of its range, the plant's unknowns)"
            : std::to_string(report->neighbourhood.edges.size()) +
                  " found: see comparison.md before a car run";
  else
    prov.knife_edges = "not checked";
  prov.training_scenarios = static_cast<int>(set.training.size());
  prov.training_before = report->training[0].total;
  prov.training_after = report->training[1].total;
  if (!report->held_out.empty()) {
    prov.held_out_scenarios = static_cast<int>(set.held_out.size());
    prov.held_out_before = report->held_out[0].total;
    prov.held_out_after = report->held_out[1].total;
  }
  prov.changed = report->changed;
  prov.frozen = report->frozen;
  prov.reverted = report->reverted;
  if (report->sensitivity_state != SensitivityState::kDone)
    prov.revert_skipped = o.sensitivity ? "the run was " + r.stop_reason : "--no-sensitivity";
  prov.new_findings = report->new_findings;
  report->tuned_file = params::ToRosYaml(report->tuned, params::kStabilityNodeKey, o.base_keys,
                                         TunedFileHeader(prov, false));
  report->overrides_file = params::ToRosOverrides(report->tuned, base, params::kStabilityNodeKey,
                                                  TunedFileHeader(prov, true));
  namespace fs = std::filesystem;
  CheckExport(report->tuned_file, true, (fs::path(o.run_folder) / kTunedParamsFile).string());
  CheckExport(report->overrides_file, false,
              (fs::path(o.run_folder) / kOverridesParamsFile).string());
}

}  // namespace scw::tuning::detail
