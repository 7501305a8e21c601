#include "tuning/optim/tune_study.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <nlopt.hpp>

#include "params/io/ros2_check.h"
#include "params/io/sha256.h"
#include "params/io/write.h"
#include "tuning/optim/set_check.h"
#include "tuning/sim/parallel/mpi_backend.h"

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

/// The best point decoded, and the base and tuned sets compared on the training and held-out
/// scenarios (the phase kCompare up to the files).
void Compare(const TuneStudy& study, const BatchEvaluator& training, TuneObserver& observer,
             TuneReport* report) {
  const TuneStudyOptions& o = study.options();
  const ScenarioSet& set = study.scenarios();
  const params::StabilityParams& base = study.base();
  const TuneResult& r = report->optimisation;
  Problems pr;
  report->tuned = study.space().Decode(r.best_u, base, &pr);
  if (!pr.empty())
    throw std::runtime_error("internal error: the best point decodes to an invalid set");
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
  md += ComparisonMarkdown("Training scenarios", training, labels, report->training);
  std::string csv = ComparisonCsv("training", training, labels, report->training, true);
  report->training_change = CompareSets(training, report->training[0], report->training[1]);
  md += "\n" + SetChangeMarkdown("Training", report->training_change);
  if (!set.held_out.empty()) {
    const int n_held = static_cast<int>(set.held_out.size());
    const auto held =
        BatchEvaluator::FromEntries(set.held_out, set.base_dir, set.cost, o.threads,
                                    Jobs(observer, TunePhase::kCompare, n_train, total));
    report->held_out =
        held.Evaluate(both, Jobs(observer, TunePhase::kCompare, n_train + n_held, total));
    md += ComparisonMarkdown("Held-out scenarios (not used for tuning)", held, labels,
                             report->held_out);
    csv += ComparisonCsv("held_out", held, labels, report->held_out, false);
    report->held_out_change = CompareSets(held, report->held_out[0], report->held_out[1]);
    md += "\n" + SetChangeMarkdown("Held-out", report->held_out_change);
  }
  if (report->plant_step.step > 0.0) md += "\n" + PlantStepCheckMarkdown(report->plant_step);
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

const char* TunePhaseName(TunePhase phase) {
  switch (phase) {
    case TunePhase::kPrepare:
      return "prepare";
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
  const BatchEvaluator training =
      BatchEvaluator::FromEntries(set.training, set.base_dir, set.cost, options_.threads,
                                  Jobs(observer, TunePhase::kPrepare, 0, n_prepare));
  std::optional<BatchEvaluator> coarse;
  report.plant_step.step = step;
  if (step > 0.0 && StepDiffers(training, step)) {
    coarse.emplace(BatchEvaluator::FromEntries(
        WithPlantStep(set.training, step), set.base_dir, set.cost, options_.threads,
        Jobs(observer, TunePhase::kPrepare, n_training, n_prepare)));
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
  report.ranks = mpi::Ranks();
  observer.OnPhaseEnd(TunePhase::kPrepare, report);

  // The optimiser's evaluator: the search step's where its check passed.
  const BatchEvaluator& search = report.plant_step.used() > 0.0 ? *coarse : training;
  const TrainingObjective objective(space_, base_, search, set.cost);
  TunerOptions to;
  to.algorithm = options_.algorithm;
  to.max_evals = options_.max_evals;
  to.max_time_s = options_.max_time_s;
  to.seed = options_.seed;
  to.batch = options_.batch;
  to.log_path = options_.evaluation_log;
  to.resume_path = options_.resume_log;
  to.log_extra_header = objective.LogHeader();
  for (const auto& e : space_.entries()) to.dimension_names.push_back("u:" + e.Label());
  to.stop = options_.stop;
  to.failure_cost = objective.invalid_cost();
  to.on_progress = [&observer](const Progress& p) { observer.OnEvaluation(p); };
  const BatchObjective batch_objective = [&objective](const std::vector<std::vector<double>>& u) {
    return objective(u);
  };
  // One point: a batch of one (the evaluator runs one set exactly as it runs a batch).
  const Objective single = [&objective](const std::vector<double>& u) {
    return objective({u}).front();
  };
  observer.OnPhaseBegin(TunePhase::kOptimise, options_.max_evals);
  report.optimisation = Tune(u0_, single, batch_objective, to);
  observer.OnPhaseEnd(TunePhase::kOptimise, report);

  Compare(*this, training, observer, &report);
  ComposeTunedFiles(*this, &report);
  const std::string& stop = report.optimisation.stop_reason;
  report.sensitivity_state =
      options_.sensitivity && stop != "interrupted" && stop != "resume_mismatch"
          ? SensitivityState::kPending
          : SensitivityState::kSkipped;
  observer.OnPhaseEnd(TunePhase::kCompare, report);
  if (report.sensitivity_state == SensitivityState::kSkipped) return report;

  const SensitivityPlan plan = PlanSensitivity(space_, report.optimisation.best_u, base_);
  const int n_runs = static_cast<int>(plan.sets.size() * training.scenarios().size());
  observer.OnPhaseBegin(TunePhase::kSensitivity, n_runs);
  report.sensitivity = EvaluateSensitivity(training, space_, plan,
                                           Jobs(observer, TunePhase::kSensitivity, 0, n_runs));
  report.comparison_markdown += "\n" + SensitivityMarkdown(report.sensitivity, "the tuned set");
  report.sensitivity_csv = SensitivityCsv(report.sensitivity);
  report.sensitivity_state = SensitivityState::kDone;
  observer.OnPhaseEnd(TunePhase::kSensitivity, report);
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
  for (const auto* group : {&set.training, &set.held_out}) {
    if (group->empty()) continue;
    const int n = static_cast<int>(group->size());
    const auto ev = BatchEvaluator::FromEntries(*group, set.base_dir, set.cost, options_.threads,
                                                Offset(progress, done, total));
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
  if (report.sensitivity_state == SensitivityState::kDone) {
    const std::vector<std::string> not_exercised = report.sensitivity.NotExercised();
    man << "sensitivity_sets: " << report.sensitivity.sets << "\n"
        << "not_exercised:" << (not_exercised.empty() ? " []" : "") << "\n";
    for (const auto& label : not_exercised) man << "  - " << params::QuoteString(label) << "\n";
  }
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
  for (const auto* group : {&set.training, &set.held_out}) {
    if (group->empty()) continue;
    const int n = static_cast<int>(group->size());
    const auto ev = BatchEvaluator::FromEntries(*group, set.base_dir, set.cost, threads,
                                                Offset(progress, done, total));
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
