#include "tuning/optim/tune_study.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <nlopt.hpp>

#include "params/io/atomic_file.h"
#include "params/io/ros2_check.h"
#include "params/io/sha256.h"
#include "params/io/stability_lint.h"
#include "params/io/write.h"
#include "tuning/exec/mpi_backend.h"
#include "tuning/optim/set_check.h"
#include "tuning/sim/prep_cache.h"

namespace scw::tuning {
namespace {

/// How the comparison and the set check name a built-in base.
std::string BaseName(const std::string& base_file) {
  return base_file.empty() ? std::string("the car's shipped parameters (built-in)") : base_file;
}

/// A phase's job count over several batches: `offset` jobs of earlier batches are done.
BatchProgress Offset(const BatchProgress& progress, int offset, int total) {
  if (!progress) return {};
  return [progress, offset, total](int done, int) { progress(offset + done, total); };
}

BatchProgress Jobs(TuneObserver& observer, TunePhase phase, int offset, int total) {
  return [&observer, phase, offset, total](int done, int) {
    observer.OnJobs(phase, offset + done, total);
  };
}

/// ", batch 4" after the algorithm when candidates were evaluated in batches ("" for 1).
std::string BatchNote(int batch) { return batch > 1 ? ", batch " + std::to_string(batch) : ""; }

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

/// The objective of the optimisation (see the header comment): the columns of the evaluation log
/// after the point are the transform arguments, then per training scenario its cost, status and
/// mean lap time.
class TrainingObjective {
 public:
  TrainingObjective(const ParameterSpace& space, const params::StabilityParams& base,
                    const BatchEvaluator& training, const params::CostWeights& cost)
      : space_(space),
        base_(base),
        training_(training),
        invalid_cost_((cost.abort_base + cost.abort_progress_weight + cost.lap_time_cap) *
                      static_cast<double>(std::max<std::size_t>(1, training.scenarios().size()))) {}

  double invalid_cost() const { return invalid_cost_; }

  std::vector<std::string> LogHeader() const {
    std::vector<std::string> extra;
    for (const auto& e : space_.entries()) extra.push_back("x:" + e.Label());
    for (const auto& sc : training_.scenarios()) {
      extra.push_back("cost:" + sc.spec.name);
      extra.push_back("status:" + sc.spec.name);
      extra.push_back("lap:" + sc.spec.name);
    }
    return extra;
  }

  /// Several points at once: the valid sets run as one batch of (set × scenario) jobs.
  std::vector<Evaluation> operator()(const std::vector<std::vector<double>>& points) const {
    std::vector<Evaluation> evs(points.size());
    std::vector<params::StabilityParams> valid_sets;
    std::vector<std::size_t> valid_at;
    for (std::size_t i = 0; i < points.size(); ++i) {
      for (double x : space_.Arguments(points[i]))
        evs[i].columns.push_back(params::FormatDouble(x));
      Problems pr;
      params::StabilityParams p = space_.Decode(points[i], base_, &pr);
      if (!pr.empty()) {
        evs[i].cost = invalid_cost_;
        evs[i].status = "infeasible: " + pr.items()[0].path;
        continue;
      }
      valid_sets.push_back(std::move(p));
      valid_at.push_back(i);
    }
    if (valid_sets.empty()) return evs;
    const std::vector<SetEvaluation> results = training_.Evaluate(valid_sets);
    for (std::size_t v = 0; v < valid_at.size(); ++v) {
      const SetEvaluation& r = results[v];
      Evaluation& ev = evs[valid_at[v]];
      ev.cost = r.total;
      int aborts = 0;
      for (std::size_t k = 0; k < r.runs.size(); ++k) {
        aborts += r.runs[k].aborted();
        ev.columns.push_back(params::FormatDouble(r.costs[k].total));
        ev.columns.push_back(RunStatusName(r.runs[k].status));
        const double lap = r.runs[k].MeanLapTime();
        ev.columns.push_back(std::isnan(lap) ? "nan" : params::FormatDouble(lap));
      }
      ev.status = aborts ? std::to_string(aborts) + " abort(s)" : "ok";
    }
    return evs;
  }

 private:
  const ParameterSpace& space_;
  const params::StabilityParams& base_;
  const BatchEvaluator& training_;
  double invalid_cost_;
};

/// A finding's kind: its text without the numbers in it (the speed at which a hysteresis inverts
/// moves with the values; the kind of problem does not).
std::string FindingKind(const Problem& p) {
  std::string kind = p.path + ":";
  bool number = false;
  for (char c : p.message) {
    const bool digit = (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e';
    if (digit && (number || (c >= '0' && c <= '9'))) {
      if (!number) kind += '#';
      number = true;
      continue;
    }
    number = false;
    kind += c;
  }
  return kind;
}

}  // namespace

std::vector<std::string> NewCheckFindings(const params::StabilityParams& base,
                                          const params::StabilityParams& tuned) {
  std::set<std::string> known;
  for (const auto& p : params::LintStability(base)) known.insert(FindingKind(p));
  std::vector<std::string> out;
  for (const auto& p : params::LintStability(tuned))
    if (!known.count(FindingKind(p))) out.push_back(p.path + ": " + p.message);
  return out;
}

namespace {

/// "label (reason)" for the dimensions `dims` of a sensitivity result.
std::vector<std::string> Described(const SensitivityResult& r, const std::vector<int>& dims) {
  std::vector<std::string> out;
  for (int i : dims) {
    const DimensionSensitivity& d = r.dimensions[static_cast<std::size_t>(i)];
    out.push_back(d.label + " (" + d.reason + ")");
  }
  return out;
}

/// comparison.md's section on what the exported file changes and why.
std::string WhatChangedMarkdown(const TuneReport& r) {
  std::string md = "## What the tuned file changes\n\n";
  md += "- convergence: " + r.convergence + "\n";
  if (!r.screened)
    md += "- frozen before the search: not screened (freezing off)\n";
  else if (r.frozen.empty())
    md +=
        "- frozen before the search: none (every parameter changes some training run at an end "
        "of its range)\n";
  else {
    md += "- frozen before the search at the base value (" + std::to_string(r.frozen.size()) +
          "; no training run changes when the parameter alone moves to either end of its "
          "range, so the training cannot tune it):\n";
    for (const auto& f : r.frozen) md += "  - " + f + "\n";
  }
  if (r.sensitivity_state != SensitivityState::kDone)
    md +=
        "- reverted after the search: **not checked** (the sensitivity did not run); the file "
        "may change parameters no training run responds to\n";
  else if (r.reverted.empty())
    md +=
        "- reverted after the search: none (every changed parameter is exercised around the "
        "best point)\n";
  else {
    md += "- reverted after the search to the base value (" + std::to_string(r.reverted.size()) +
          "; changed by the search, but no training run changes around the best point):\n";
    for (const auto& f : r.reverted) md += "  - " + f + "\n";
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

/// The identity lines of a log ("key: value"); throws ConfigError when the file cannot be read.
std::map<std::string, std::string> ReadIdentity(const std::string& path, bool* found) {
  std::map<std::string, std::string> out;
  std::ifstream in(path, std::ios::binary);
  *found = static_cast<bool>(in);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto colon = line.find(": ");
    if (colon == std::string::npos) continue;
    out[line.substr(0, colon)] = line.substr(colon + 2);
  }
  return out;
}

/// Refuses (ConfigError, every difference) a resume log whose identity file differs from this
/// run's identity `mine`.
void CheckLogIdentity(const std::string& log, const std::string& mine) {
  const std::string path = EvaluationLogIdentityPath(log);
  bool found = false;
  const auto theirs = ReadIdentity(path, &found);
  if (!found)
    throw ConfigError(log, "",
                      "cannot be resumed: its identity file " + path +
                          " is missing (it records the program, settings and inputs that wrote "
                          "the log; logs of scw before the identity file cannot be resumed)");
  std::istringstream in(mine);
  std::string line;
  std::vector<Problem> problems;
  std::set<std::string> seen;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto colon = line.find(": ");
    if (colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon), value = line.substr(colon + 2);
    seen.insert(key);
    const auto it = theirs.find(key);
    if (it == theirs.end())
      problems.push_back({key, "the log's identity does not record it (this run: " + value + ")"});
    else if (it->second != value)
      problems.push_back(
          {key, "the log was written with " + it->second + ", this run has " + value});
  }
  for (const auto& [key, value] : theirs)
    if (!seen.count(key))
      problems.push_back({key, "recorded by the log (" + value + "), unknown to this run"});
  if (!problems.empty()) {
    problems.push_back({"",
                        "refused before anything was written; resume with the settings and "
                        "inputs of the logged run, or start a new run folder"});
    throw ConfigError(path, problems);
  }
}

/// Pins every dimension that the sensitivity found not exercised, and whose key the search moved,
/// at its base value (report->pinned_dims, report->reverted). A revert that would make the set
/// invalid is left out (and said so).
void Revert(const TuneStudy& study, TuneReport* report) {
  const auto& dims = report->sensitivity.dimensions;
  const std::vector<double>& u = report->exported_u;
  params::StabilityParams current =
      study.space().WithPinned(report->pinned_dims).Decode(u, study.base(), nullptr);
  for (std::size_t i = 0; i < dims.size(); ++i) {
    const int dim = static_cast<int>(i);
    if (dims[i].exercised ||
        std::count(report->pinned_dims.begin(), report->pinned_dims.end(), dim))
      continue;
    std::vector<int> trial = report->pinned_dims;
    trial.push_back(dim);
    Problems pr;
    const params::StabilityParams p = study.space().WithPinned(trial).Decode(u, study.base(), &pr);
    if (!pr.empty()) {
      report->reverted.push_back(dims[i].label + " (NOT reverted: the base value would break " +
                                 pr.items()[0].path + ")");
      continue;
    }
    if (params::DifferingKeys(p, current).empty()) continue;  // the search left it at the base
    report->pinned_dims = std::move(trial);
    current = p;
    report->reverted.push_back(dims[i].label + " (" + dims[i].reason + ")");
  }
}

/// A pinned key that a moved reference forced off its base value to keep its ordering or
/// hysteresis: " — moved to V with its reference R to keep their relation", else "".
std::string KeptRelation(const SpaceEntry& e, const params::StabilityParams& base,
                         const params::StabilityParams& tuned) {
  if (e.of.empty()) return "";
  const std::set<std::string> diff = params::DifferingKeys(tuned, base);
  if (!diff.count(e.key)) return "";
  return " — moved with its reference " + e.of + " to keep their relation";
}

/// The best point decoded, and the base and tuned sets compared on the training and held-out
/// scenarios (the phase kCompare up to the files).
void Compare(const TuneStudy& study, const BatchEvaluator& training, TuneObserver& observer,
             controller::planning::ReferenceCache* cache, TuneReport* report) {
  const TuneStudyOptions& o = study.options();
  const ScenarioSet& set = study.scenarios();
  const params::StabilityParams& base = study.base();
  const TuneResult& r = report->optimisation;
  Problems pr;
  const ParameterSpace exported = study.space().WithPinned(report->pinned_dims);
  report->tuned = exported.Decode(report->exported_u, base, &pr);
  if (!pr.empty())
    throw std::runtime_error("internal error: the exported point decodes to an invalid set");
  // Pinned keys that had to follow their reference say so.
  for (auto* list : {&report->frozen, &report->reverted})
    for (auto& item : *list)
      for (const auto& e : exported.entries())
        if (e.pinned && item.rfind(e.Label() + " (", 0) == 0)
          item += KeptRelation(e, base, report->tuned);
  report->new_findings = NewCheckFindings(base, report->tuned);
  const std::set<std::string> changed = params::DifferingKeys(report->tuned, base);
  report->changed.assign(changed.begin(), changed.end());

  const std::vector<std::string> labels = {"baseline", "tuned"};
  const std::vector<params::StabilityParams> both = {base, report->tuned};
  const int n_train = static_cast<int>(both.size() * set.training.size());
  const int total = n_train + static_cast<int>((both.size() + 1) * set.held_out.size());
  observer.OnPhaseBegin(TunePhase::kCompare, total);
  report->training = training.Evaluate(both, Jobs(observer, TunePhase::kCompare, 0, total));
  std::string md = "# scw tune: comparison\n\nbaseline = " + BaseName(o.base_file) +
                   "; tuned = best of " + std::to_string(r.evals) + " evaluations (" + o.algorithm +
                   BatchNote(o.batch) + ", seed " + std::to_string(o.seed) + "), " +
                   std::to_string(changed.size()) + " key(s) changed\n\n";
  md += WhatChangedMarkdown(*report);
  md += ComparisonMarkdown("Training scenarios", training, labels, report->training);
  std::string csv = ComparisonCsv("training", training, labels, report->training, true);
  report->training_change = CompareSets(training, report->training[0], report->training[1]);
  md += "\n" + SetChangeMarkdown("Training", report->training_change);
  if (!set.held_out.empty()) {
    const int n_held = static_cast<int>(set.held_out.size());
    const auto held =
        BatchEvaluator::FromEntries(set.held_out, set.base_dir, set.cost, o.threads,
                                    Jobs(observer, TunePhase::kCompare, n_train, total), cache);
    report->held_out =
        held.Evaluate(both, Jobs(observer, TunePhase::kCompare, n_train + n_held, total));
    md += ComparisonMarkdown("Held-out scenarios (not used for tuning)", held, labels,
                             report->held_out);
    csv += ComparisonCsv("held_out", held, labels, report->held_out, false);
    report->held_out_change = CompareSets(held, report->held_out[0], report->held_out[1]);
    md += "\n" + SetChangeMarkdown("Held-out", report->held_out_change);
  }
  if (report->plant_step.step > 0.0) md += "\n" + PlantStepCheckMarkdown(report->plant_step);
  if (report->sensitivity_state == SensitivityState::kDone)
    md += "\n" + SensitivityMarkdown(report->sensitivity, "the best point of the search");
  report->comparison_markdown = md;
  report->comparison_csv = csv;
}

/// The tuned full and overrides-only params files with their provenance header, checked as the
/// car's node would load them.
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

}  // namespace

std::string EvaluationLogIdentityPath(const std::string& log) {
  const std::string ext = ".csv";
  if (log.size() > ext.size() && log.compare(log.size() - ext.size(), ext.size(), ext) == 0)
    return log.substr(0, log.size() - ext.size()) + ".identity.yaml";
  return log + ".identity.yaml";
}

std::string ConvergenceVerdict(const TuneResult& r, int max_evals) {
  const std::string last = "last improvement of more than " +
                           params::FormatNumber(100.0 * kSignificantImprovement) +
                           " % at evaluation " + std::to_string(r.last_improvement_eval) + " of " +
                           std::to_string(r.evals);
  if (r.stop_reason == "converged") return last + ": converged (the optimiser met its tolerance)";
  if (r.stop_reason == "interrupted" || r.stop_reason == "max_time")
    return last + ": stopped early (" + r.stop_reason + "), not converged";
  const int quiet = r.evals - 1 - r.last_improvement_eval;
  if (r.evals >= 5 && quiet >= r.evals / 5)
    return last + ": converged by this measure (no such improvement in the last " +
           std::to_string(quiet) + " evaluations)";
  return last + ": not converged, raise --max-evals (now " + std::to_string(max_evals) + ")";
}

std::string TuneStudy::LogIdentity(const TuneReport& report, const BatchEvaluator& training) const {
  const TuneStudyOptions& o = options_;
  std::string resolved;
  for (const auto& sc : training.scenarios())
    resolved += params::ToPlainYaml(sc.spec) + params::ToPlainYaml(sc.vehicle);
  std::string frozen = "[";
  for (std::size_t k = 0; k < report.frozen_dims.size(); ++k)
    frozen +=
        (k ? ", " : "") + space_.entries()[static_cast<std::size_t>(report.frozen_dims[k])].Label();
  frozen += "]";
  std::ostringstream id;
  id << "# scw tune: what wrote the evaluation log beside this file. `scw tune --resume` compares "
        "every line\n# with its own before it writes anything, and refuses to continue on any "
        "difference.\n"
     << "format: scw-tune-log 1\n"
     << "program: " << ProgramIdentity() << "\n"
     << "algorithm: " << o.algorithm << "\n"
     << "batch: " << o.batch << "\n"
     << "seed: " << o.seed << "\n"
     << "max_evals: " << o.max_evals << "\n"
     << "search_plant_step: " << params::FormatDouble(o.search_plant_step) << "\n"
     << "search_plant_step_used: " << params::FormatDouble(report.plant_step.used()) << "\n"
     << "freeze_unexercised: " << (o.freeze_unexercised ? "true" : "false") << "\n"
     << "base_sha256: " << io::Sha256Hex(params::ToRosYaml(base_, params::kStabilityNodeKey))
     << "\n"
     << "space_sha256: " << io::Sha256Hex(space_.ToYaml()) << "\n"
     << "scenarios_sha256: " << io::Sha256Hex(scenarios_.ToYaml() + resolved) << "\n"
     << "frozen: " << frozen << "\n";
  return id.str();
}

const char* TunePhaseName(TunePhase phase) {
  switch (phase) {
    case TunePhase::kPrepare:
      return "prepare";
    case TunePhase::kScreen:
      return "screen";
    case TunePhase::kOptimise:
      return "optimise";
    case TunePhase::kCompare:
      return "compare";
    case TunePhase::kSensitivity:
      return "sensitivity";
  }
  return "?";
}

TuneStudy::TuneStudy(params::StabilityParams base, const ParameterSpace& space,
                     ScenarioSet scenarios, TuneStudyOptions options)
    : base_(std::move(base)),
      given_(space),
      scenarios_(std::move(scenarios)),
      options_(std::move(options)),
      space_(given_.WithBase(base_, options_.base_outside, &grown_)),
      u0_(space_.Encode(base_)) {
  CheckTunerAlgorithm(options_.algorithm);
  if (!(options_.search_plant_step >= 0.0 && options_.search_plant_step <= 0.005))
    throw std::invalid_argument("the search plant step must lie in [0, 0.005] s, got " +
                                params::FormatDouble(options_.search_plant_step));
  CheckTunerBatch(options_.algorithm, options_.batch);
  // Evaluation 0 is the base set, and keys the tuner leaves alone keep their base values.
  if (!params::DifferingKeys(space_.Decode(u0_, base_, nullptr), base_).empty())
    throw std::runtime_error("internal error: the start point does not decode to the base set");
}

TuneReport TuneStudy::Run() const {
  TuneObserver none;
  return Run(none);
}

TuneReport TuneStudy::Run(TuneObserver& observer) const {
  const ScenarioSet& set = scenarios_;
  TuneReport report;
  const int n_training = static_cast<int>(set.training.size());
  // With a search step: its evaluator (the preparation is shared with the first) and the base set
  // run at both steps, 4 jobs per scenario in all.
  const double step = options_.search_plant_step;
  const int n_prepare = step > 0.0 ? 4 * n_training : n_training;
  observer.OnPhaseBegin(TunePhase::kPrepare, n_prepare);
  // One preparation cache for every evaluator of the run (training, the search step's, held-out).
  controller::planning::ReferenceCache cache(&PrepCache::Process());
  const BatchEvaluator training =
      BatchEvaluator::FromEntries(set.training, set.base_dir, set.cost, options_.threads,
                                  Jobs(observer, TunePhase::kPrepare, 0, n_prepare), &cache);
  std::optional<BatchEvaluator> coarse;
  report.plant_step.step = step;
  if (step > 0.0 && StepDiffers(training, step)) {
    coarse.emplace(BatchEvaluator::FromEntries(
        WithPlantStep(set.training, step), set.base_dir, set.cost, options_.threads,
        Jobs(observer, TunePhase::kPrepare, n_training, n_prepare), &cache));
    const SetEvaluation fine_base =
        training.Evaluate({base_}, Jobs(observer, TunePhase::kPrepare, 2 * n_training, n_prepare))
            .front();
    const SetEvaluation coarse_base =
        coarse->Evaluate({base_}, Jobs(observer, TunePhase::kPrepare, 3 * n_training, n_prepare))
            .front();
    std::vector<std::string> names;
    for (const auto& sc : training.scenarios()) names.push_back(sc.spec.name);
    report.plant_step = ComparePlantSteps(step, names, fine_base, coarse_base,
                                          options_.search_plant_step_tolerances);
  } else {
    // Every vehicle has that step already: nothing to check, the counted jobs are done.
    for (int done = n_training + 1; done <= n_prepare; ++done)
      observer.OnJobs(TunePhase::kPrepare, done, n_prepare);
  }
  report.threads = training.threads();
  report.ranks = exec::mpi::Ranks();
  observer.OnPhaseEnd(TunePhase::kPrepare, report);

  // The optimiser's evaluator: the search step's where its check passed.
  const BatchEvaluator& search = report.plant_step.used() > 0.0 ? *coarse : training;
  const int n = space_.size();

  // Screen: which dimensions can the training scenarios see at all? Those that cannot are frozen.
  if (options_.freeze_unexercised) {
    const SensitivityPlan plan = PlanSensitivity(space_, u0_, base_, SensitivityMode::kRange);
    const int n_runs = static_cast<int>(plan.sets.size() * search.scenarios().size());
    observer.OnPhaseBegin(TunePhase::kScreen, n_runs);
    report.screening =
        EvaluateSensitivity(search, space_, plan, Jobs(observer, TunePhase::kScreen, 0, n_runs));
    report.screened = true;
    for (int i = 0; i < n; ++i)
      if (!report.screening.dimensions[static_cast<std::size_t>(i)].exercised)
        report.frozen_dims.push_back(i);
    report.frozen = Described(report.screening, report.frozen_dims);
    observer.OnPhaseEnd(TunePhase::kScreen, report);
  }
  std::vector<int> free_dims;
  for (int i = 0; i < n; ++i)
    if (std::find(report.frozen_dims.begin(), report.frozen_dims.end(), i) ==
        report.frozen_dims.end())
      free_dims.push_back(i);
  // Nothing left to tune: the base set is evaluated once, as evaluation 0.
  const bool all_frozen = free_dims.empty();
  if (all_frozen)
    for (int i = 0; i < n; ++i) free_dims.push_back(i);
  const auto expand = [this, &free_dims](const std::vector<double>& v) {
    std::vector<double> u = u0_;
    for (std::size_t k = 0; k < free_dims.size() && k < v.size(); ++k)
      u[static_cast<std::size_t>(free_dims[k])] = v[k];
    return u;
  };
  std::vector<double> v0;
  for (int i : free_dims) v0.push_back(u0_[static_cast<std::size_t>(i)]);

  // The optimiser's space: the frozen dimensions pinned at the base value.
  report.pinned_dims = report.frozen_dims;
  const ParameterSpace search_space = space_.WithPinned(report.frozen_dims);
  const TrainingObjective objective(search_space, base_, search, set.cost);
  TunerOptions to;
  to.algorithm = options_.algorithm;
  to.max_evals = all_frozen ? 1 : options_.max_evals;
  to.max_time_s = options_.max_time_s;
  to.seed = options_.seed;
  to.batch = options_.batch;
  to.log_extra_header = objective.LogHeader();
  for (int i : free_dims)
    to.dimension_names.push_back("u:" + space_.entries()[static_cast<std::size_t>(i)].Label());
  to.stop = options_.stop;
  to.failure_cost = objective.invalid_cost();
  const BatchObjective batch_objective = [&objective,
                                          &expand](const std::vector<std::vector<double>>& vs) {
    std::vector<std::vector<double>> us;
    for (const auto& v : vs) us.push_back(expand(v));
    return objective(us);
  };
  // One point: a batch of one (the evaluator runs one set exactly as it runs a batch).
  const Objective single = [&objective, &expand](const std::vector<double>& v) {
    return objective({expand(v)}).front();
  };

  // Resume: refused before anything is written when the log belongs to another run.
  const std::string identity = LogIdentity(report, training);
  if (!options_.resume_log.empty()) {
    CheckLogIdentity(options_.resume_log, identity);
    TunerOptions verify = to;
    verify.resume_path = options_.resume_log;
    verify.verify_resume = true;
    verify.stop = nullptr;
    verify.max_time_s = 0.0;
    try {
      (void)Tune(v0, single, batch_objective, verify);
    } catch (const ResumeMismatch& e) {
      throw ConfigError(options_.resume_log, "", e.what());
    }
  }
  if (!options_.evaluation_log.empty()) {
    const std::string id_path = EvaluationLogIdentityPath(options_.evaluation_log);
    std::ifstream existing(id_path, std::ios::binary);
    std::ostringstream text;
    text << existing.rdbuf();
    if (!existing || text.str() != identity) io::WriteFileAtomic(id_path, identity);
  }

  to.log_path = options_.evaluation_log;
  to.resume_path = options_.resume_log;
  to.on_progress = [&observer](const Progress& p) { observer.OnEvaluation(p); };
  observer.OnPhaseBegin(TunePhase::kOptimise, to.max_evals);
  try {
    report.optimisation = Tune(v0, single, batch_objective, to);
  } catch (const ResumeMismatch& e) {
    throw ConfigError(options_.resume_log, "", e.what());
  }
  TuneResult& opt = report.optimisation;
  opt.best_u = expand(opt.best_u);
  if (all_frozen) opt.stop_reason = "all_frozen";
  report.convergence = all_frozen ? std::string("nothing to tune: every parameter is frozen")
                                  : ConvergenceVerdict(opt, options_.max_evals);
  observer.OnPhaseEnd(TunePhase::kOptimise, report);

  // Sensitivity around the best point; what no training run responds to goes back to the base.
  report.exported_u = opt.best_u;
  const std::string& stop = opt.stop_reason;
  report.sensitivity_state = options_.sensitivity && stop != "interrupted"
                                 ? SensitivityState::kPending
                                 : SensitivityState::kSkipped;
  if (report.sensitivity_state == SensitivityState::kPending) {
    const SensitivityPlan plan = PlanSensitivity(search_space, opt.best_u, base_);
    const int n_runs = static_cast<int>(plan.sets.size() * training.scenarios().size());
    observer.OnPhaseBegin(TunePhase::kSensitivity, n_runs);
    report.sensitivity = EvaluateSensitivity(training, search_space, plan,
                                             Jobs(observer, TunePhase::kSensitivity, 0, n_runs));
    report.sensitivity_csv = SensitivityCsv(report.sensitivity);
    report.sensitivity_state = SensitivityState::kDone;
    Revert(*this, &report);
    observer.OnPhaseEnd(TunePhase::kSensitivity, report);
  }

  Compare(*this, training, observer, &cache, &report);
  ComposeTunedFiles(*this, &report);
  observer.OnPhaseEnd(TunePhase::kCompare, report);
  return report;
}

std::string TuneStudy::CheckSet(const BatchProgress& progress) const {
  const ScenarioSet& set = scenarios_;
  const int n_scenarios = static_cast<int>(set.training.size() + set.held_out.size());
  SensitivityPlan plan;
  if (options_.sensitivity) plan = PlanSensitivity(space_, u0_, base_);
  const int total = n_scenarios * 6 +  // preparation + 5 runs each
                    static_cast<int>(plan.sets.size() * set.training.size());
  if (progress) progress(0, total);
  int done = 0;
  std::string sensitivity;
  std::string md =
      "# scw tune --check-set\n\nbase = " + BaseName(options_.base_file) +
      "; activations ESC/CS/ABS/TC with the base set; a subsystem decides a scenario when "
      "switching it off turns a completed run into an abort (or the reverse) or changes the "
      "scenario's cost by 5 % or more\n\n";
  controller::planning::ReferenceCache cache(&PrepCache::Process());  // both groups
  for (const auto* group : {&set.training, &set.held_out}) {
    if (group->empty()) continue;
    const int n = static_cast<int>(group->size());
    const auto ev = BatchEvaluator::FromEntries(*group, set.base_dir, set.cost, options_.threads,
                                                Offset(progress, done, total), &cache);
    done += n;
    const auto check = tuning::CheckSet(ev, base_, 0.05, Offset(progress, done, total));
    done += 5 * n;
    const bool training = group == &set.training;
    md += SetCheckMarkdown(training ? "Training scenarios" : "Held-out scenarios", check, training);
    md += "\n";
    if (training && options_.sensitivity) {
      sensitivity = SensitivityMarkdown(
          EvaluateSensitivity(ev, space_, plan, Offset(progress, done, total)), "the base set");
      done += static_cast<int>(plan.sets.size()) * n;
    }
  }
  return md + sensitivity;
}

std::string TuneStudy::ManifestYaml(const TuneReport& report, const TuneRunRecord& record) const {
  const TuneStudyOptions& o = options_;
  const TuneResult& r = report.optimisation;
  // A file as given is hashed by the caller; a built-in input as its printed form.
  const auto hash = [](const std::string& file, const std::string& file_hash, const auto& printed) {
    return file.empty() ? io::Sha256Hex(printed()) : file_hash;
  };
  std::ostringstream man;
  man << "scw_version: " << o.tool_version << "\n"
      << "git_revision: " << o.git_revision << "\n"
      << "date_utc: " << report.provenance.date_utc << "\n"
      << "nlopt_version: " << nlopt::version_major() << "." << nlopt::version_minor() << "."
      << nlopt::version_bugfix() << "\n"
      << "command_line: " << params::QuoteString(record.command_line) << "\n"
      << "base: " << params::QuoteString(o.base_file.empty() ? "built-in" : o.base_file) << "\n"
      << "base_hash: "
      << hash(o.base_file, record.base_sha256,
              [&] { return params::ToRosYaml(base_, params::kStabilityNodeKey); })
      << "\n"
      << "space: " << params::QuoteString(o.space_file.empty() ? "built-in default" : o.space_file)
      << "\n"
      << "space_hash: " << hash(o.space_file, record.space_sha256, [&] { return space_.ToYaml(); })
      << "\n"
      << "base_outside_space: " << (o.base_outside == BaseOutsideSpace::kRefuse ? "refuse" : "grow")
      << "\n"
      << "grown_ranges: " << grown_.size() << "\n"
      << "scenarios: "
      << params::QuoteString(o.scenarios_file.empty() ? "built-in default" : o.scenarios_file)
      << "\n"
      << "scenarios_hash: "
      << hash(o.scenarios_file, record.scenarios_sha256, [&] { return scenarios_.ToYaml(); })
      << "\n"
      << "algorithm: " << o.algorithm << "\n"
      << "batch: " << o.batch << "\n"
      << "seed: " << o.seed << "\n"
      << "max_evals: " << o.max_evals << "\n"
      << "max_time_s: " << params::FormatDouble(o.max_time_s) << "\n"
      << "search_plant_step: " << params::FormatDouble(o.search_plant_step) << "\n"
      << "search_plant_step_check: " << params::QuoteString(report.plant_step.Verdict()) << "\n"
      << "search_plant_step_used: " << params::FormatDouble(report.plant_step.used()) << "\n"
      << "threads: " << report.threads << "\n"
      << "ranks: " << report.ranks << "\n"
      << "threads_per_rank: " << report.threads << "\n"
      << "evaluations: " << r.evals << "\n"
      << "replayed_evaluations: " << r.replayed << "\n"
      << "stop_reason: " << r.stop_reason << "\n"
      << "start_cost: " << params::FormatDouble(r.start_cost) << "\n"
      << "best_cost: " << params::FormatDouble(r.best_cost) << "\n"
      << "best_evaluation: " << r.best_eval << "\n"
      << "baseline_cost: " << params::FormatDouble(report.training[0].total) << "\n"
      << "tuned_cost: " << params::FormatDouble(report.training[1].total) << "\n";
  man << "training_verdict: " << VerdictName(report.training_change.verdict) << "\n";
  if (!report.held_out.empty())
    man << "held_out_baseline_cost: " << params::FormatDouble(report.held_out[0].total) << "\n"
        << "held_out_tuned_cost: " << params::FormatDouble(report.held_out[1].total) << "\n"
        << "held_out_verdict: " << VerdictName(report.held_out_change.verdict) << "\n";
  std::string state = "done";
  if (report.sensitivity_state == SensitivityState::kPending)
    state = "pending";
  else if (report.sensitivity_state == SensitivityState::kSkipped)
    state = o.sensitivity ? "skipped (" + r.stop_reason + ")" : "skipped (--no-sensitivity)";
  man << "sensitivity: " << params::QuoteString(state) << "\n";
  const auto list = [&man](const char* key, const std::vector<std::string>& items) {
    man << key << ":" << (items.empty() ? " []" : "") << "\n";
    for (const auto& item : items) man << "  - " << params::QuoteString(item) << "\n";
  };
  if (report.sensitivity_state == SensitivityState::kDone) {
    man << "sensitivity_sets: " << report.sensitivity.sets << "\n";
    list("not_exercised", report.sensitivity.NotExercised());
  }
  man << "convergence: " << params::QuoteString(report.convergence) << "\n";
  man << "freeze_unexercised: " << (o.freeze_unexercised ? "true" : "false") << "\n";
  list("frozen", report.frozen);
  list("reverted", report.reverted);
  list("new_findings", report.new_findings);
  man << "hash_algorithm: sha256\n";
  man << "changed_keys: " << report.changed.size() << "\n"
      << "wall_time_s: " << params::FormatDouble(record.wall_time_s) << "\n";
  // SHA-256 of the files as written (`sha256sum FILE` prints the same); the inputs above are
  // hashed as files when given, as their printed form when built in.
  man << "files_sha256:\n";
  for (const auto& [file, digest] : record.files_sha256)
    man << "  " << file << ": " << digest << "\n";
  return man.str();
}

SetsEvaluation EvaluateSets(const ScenarioSet& scenarios,
                            const std::vector<params::StabilityParams>& sets,
                            const std::vector<std::string>& labels, int threads,
                            const BatchProgress& progress) {
  const ScenarioSet& set = scenarios;
  // One count: each scenario's preparation and every run are a job.
  const int n_scenarios = static_cast<int>(set.training.size() + set.held_out.size());
  const int total = n_scenarios * static_cast<int>(sets.size() + 1);
  if (progress) progress(0, total);
  int done = 0;
  SetsEvaluation out;
  bool header = true;
  controller::planning::ReferenceCache cache(&PrepCache::Process());  // both groups
  for (const auto* group : {&set.training, &set.held_out}) {
    if (group->empty()) continue;
    const int n = static_cast<int>(group->size());
    const auto ev = BatchEvaluator::FromEntries(*group, set.base_dir, set.cost, threads,
                                                Offset(progress, done, total), &cache);
    done += n;
    const auto res = ev.Evaluate(sets, Offset(progress, done, total));
    done += n * static_cast<int>(sets.size());
    const std::string name = group == &set.training ? "training" : "held_out";
    out.markdown += ComparisonMarkdown(name, ev, labels, res);
    out.csv += ComparisonCsv(name, ev, labels, res, header);
    header = false;
  }
  return out;
}

}  // namespace scw::tuning
