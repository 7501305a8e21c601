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
#include "params/io/sha256.h"
#include "params/io/stability_lint.h"
#include "params/io/write.h"
#include "tuning/exec/mpi_backend.h"
#include "tuning/optim/robust.h"
#include "tuning/optim/set_check.h"
#include "tuning/optim/tune_study_detail.h"
#include "tuning/sim/prep_cache.h"

namespace scw::tuning {

namespace detail {

std::string BaseName(const std::string& base_file) {
  return base_file.empty() ? std::string("the car's shipped parameters (built-in)") : base_file;
}

std::string BatchNote(int batch) { return batch > 1 ? ", batch " + std::to_string(batch) : ""; }

std::vector<std::string> Described(const SensitivityResult& r, const std::vector<int>& dims) {
  std::vector<std::string> out;
  for (int i : dims) {
    const DimensionSensitivity& d = r.dimensions[static_cast<std::size_t>(i)];
    out.push_back(d.label + " (" + d.reason + ")");
  }
  return out;
}

}  // namespace detail

namespace {

using detail::BaseName;
using detail::Described;

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

/// The identity lines of a log ("key: value"); `found` false when the file cannot be read.
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

/// Whether a logged run of `algorithm` can be continued with a larger budget: one NLopt phase,
/// whose path does not depend on the budget (a design or an A+B split does).
bool Extendable(const std::string& algorithm) {
  return algorithm.find('+') == std::string::npos && algorithm != "lhs";
}

/// Refuses (ConfigError, every difference) a resume log whose identity file differs from this
/// run's identity `mine`. A larger max_evals than the log's is allowed for an extendable
/// algorithm: returns true then (the run is extended).
bool CheckLogIdentity(const std::string& log, const std::string& mine,
                      const std::string& algorithm) {
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
  bool extended = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto colon = line.find(": ");
    if (colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon), value = line.substr(colon + 2);
    seen.insert(key);
    const auto it = theirs.find(key);
    if (it == theirs.end()) {
      problems.push_back({key, "the log's identity does not record it (this run: " + value + ")"});
      continue;
    }
    if (it->second == value) continue;
    if (key == "max_evals") {
      long long logged = 0, now = 0;
      std::istringstream(it->second) >> logged;
      std::istringstream(value) >> now;
      if (now > logged && Extendable(algorithm)) {
        extended = true;
        continue;
      }
      problems.push_back(
          {key, now > logged
                    ? "the log was written with " + it->second + "; '" + algorithm +
                          "' splits its budget by max_evals, so its run cannot be extended "
                          "(only single-phase NLopt algorithms such as sbplx can)"
                    : "the log was written with " + it->second + ", this run has " + value +
                          " (a resume may raise the budget, never lower it)"});
      continue;
    }
    problems.push_back({key, "the log was written with " + it->second + ", this run has " + value});
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
  return extended;
}

/// The screen file's text: one line per frozen dimension, "label: reason".
std::string ScreenFileText(const SensitivityResult& screening, const std::vector<int>& frozen) {
  std::string out =
      "# scw tune: the dimensions the screen froze before the search (a resume reads them "
      "instead\n# of screening again). label: reason\nfrozen:\n";
  for (int i : frozen) {
    const DimensionSensitivity& d = screening.dimensions[static_cast<std::size_t>(i)];
    out += "  - " + params::QuoteString(d.label) + ": " + params::QuoteString(d.reason) + "\n";
  }
  return out;
}

/// The frozen dimensions a screen file lists (false when it is missing or unreadable, or names
/// a dimension the space does not have).
bool ReadScreenFile(const std::string& path, const ParameterSpace& space, TuneReport* r) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string line;
  std::vector<int> dims;
  std::vector<std::string> items;
  while (std::getline(in, line)) {
    if (line.rfind("  - ", 0) != 0) continue;
    const auto unquote = [](std::string t) {
      if (t.size() >= 2 && t.front() == '"' && t.back() == '"') t = t.substr(1, t.size() - 2);
      std::string out;
      for (std::size_t i = 0; i < t.size(); ++i) {
        if (t[i] == '\\' && i + 1 < t.size()) ++i;
        out += t[i];
      }
      return out;
    };
    const std::string body = line.substr(4);
    const auto sep = body.find("\": ");
    if (sep == std::string::npos) return false;
    const std::string label = unquote(body.substr(0, sep + 1));
    const std::string reason = unquote(body.substr(sep + 3));
    int dim = -1;
    for (int i = 0; i < space.size(); ++i)
      if (space.entries()[static_cast<std::size_t>(i)].Label() == label) dim = i;
    if (dim < 0) return false;
    dims.push_back(dim);
    items.push_back(label + " (" + reason + ")");
  }
  r->frozen_dims = std::move(dims);
  r->frozen = std::move(items);
  r->screened = true;
  return true;
}

}  // namespace

std::vector<std::string> NewCheckFindings(const params::StabilityParams& base,
                                          const params::StabilityParams& tuned) {
  // A finding's kind: its text without the numbers in it (the speed at which a hysteresis inverts
  // moves with the values; the kind of problem does not).
  const auto kind_of = [](const Problem& p) {
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
  };
  std::set<std::string> known;
  for (const auto& p : params::LintStability(base)) known.insert(kind_of(p));
  std::vector<std::string> out;
  for (const auto& p : params::LintStability(tuned))
    if (!known.count(kind_of(p))) out.push_back(p.path + ": " + p.message);
  return out;
}

std::string EvaluationLogIdentityPath(const std::string& log) {
  const std::string ext = ".csv";
  if (log.size() > ext.size() && log.compare(log.size() - ext.size(), ext.size(), ext) == 0)
    return log.substr(0, log.size() - ext.size()) + ".identity.yaml";
  return log + ".identity.yaml";
}

std::string EvaluationLogScreenPath(const std::string& log) {
  const std::string ext = ".csv";
  if (log.size() > ext.size() && log.compare(log.size() - ext.size(), ext.size(), ext) == 0)
    return log.substr(0, log.size() - ext.size()) + ".screen.yaml";
  return log + ".screen.yaml";
}

std::string EvaluationName(int index) {
  return index < 0 ? "another point's search" : "evaluation " + std::to_string(index);
}

std::string ConvergenceVerdict(const TuneResult& r, int max_evals, int dims) {
  const std::string last = "last improvement of more than " +
                           params::FormatNumber(100.0 * kSignificantImprovement) +
                           " % at evaluation " + std::to_string(r.last_improvement_eval) + " of " +
                           std::to_string(r.evals);
  if (r.stop_reason == "converged") return last + ": converged (the optimiser met its tolerance)";
  if (r.stop_reason == "interrupted" || r.stop_reason == "max_time")
    return last + ": stopped early (" + r.stop_reason + "), not converged";
  const int window = 10 * std::max(1, dims);
  const int quiet = r.evals - 1 - r.last_improvement_eval;
  const std::string rule = "the rule: no such improvement in the last 10 x " +
                           std::to_string(dims) + " free dimensions = " + std::to_string(window) +
                           " evaluations";
  if (quiet >= window)
    return last + ": converged by " + rule + " (" + std::to_string(quiet) + " without)";
  if (r.evals - 1 < window)
    return last + ": budget too small to judge convergence (" + rule + "; --max-evals " +
           std::to_string(max_evals) + " is below it)";
  return last + ": not converged (" + rule + "), raise --max-evals (now " +
         std::to_string(max_evals) + ")";
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
        "difference\n# (a larger max_evals continues a single-phase search).\n"
     << "format: scw-tune-log 1\n"
     << "program: " << ProgramIdentity() << "\n"
     << "algorithm: " << o.algorithm << "\n"
     << "batch: " << o.batch << "\n"
     << "seed: " << o.seed << "\n"
     << "max_evals: " << o.max_evals << "\n";
  // The objective (written only when it is not the earlier runs' sum, so their logs still resume).
  if (o.objective != ObjectiveKind::kSum)
    id << "objective: " << ObjectiveKindName(o.objective) << "\n"
       << "lap_budget: " << params::FormatDouble(o.budget.lap_s) << "\n"
       << "clean_interventions: " << (o.budget.interventions ? "true" : "false") << "\n";
  id << "search_plant_step: " << params::FormatDouble(o.SearchPlantStep()) << "\n"
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
    case TunePhase::kSelect:
      return "select";
    case TunePhase::kSensitivity:
      return "sensitivity";
    case TunePhase::kRevert:
      return "revert";
    case TunePhase::kCompare:
      return "compare";
    case TunePhase::kNeighbourhood:
      return "neighbourhood";
    case TunePhase::kRobust:
      return "robust";
    case TunePhase::kExport:
      return "export";
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
  if (!(options_.SearchPlantStep() >= 0.0 && options_.SearchPlantStep() <= 0.005))
    throw std::invalid_argument("the search plant step must lie in [0, 0.005] s, got " +
                                params::FormatDouble(options_.search_plant_step));
  CheckTunerBatch(options_.algorithm, options_.batch);
  if (options_.algorithm == "auglag" && options_.objective != ObjectiveKind::kConstrained)
    throw std::invalid_argument(
        "auglag minimises the stability cost subject to the clean-lap budget: it needs the "
        "constrained objective");
  if (!(options_.budget.lap_s >= 0.0))
    throw std::invalid_argument("the clean-lap budget must be at least 0 s, got " +
                                params::FormatDouble(options_.budget.lap_s));
  if (!(options_.resolution > 0.0 && std::isfinite(options_.resolution)))
    throw std::invalid_argument("the resolution must be a positive number of seconds, got " +
                                params::FormatDouble(options_.resolution));
  if (!(options_.neighbourhood_step > 0.0 && options_.neighbourhood_step <= 0.5))
    throw std::invalid_argument("the neighbourhood step must lie in (0, 0.5], got " +
                                params::FormatDouble(options_.neighbourhood_step));
  // Evaluation 0 is the base set, and keys the tuner leaves alone keep their base values.
  if (!params::DifferingKeys(space_.Decode(u0_, base_, nullptr), base_).empty())
    throw std::runtime_error("internal error: the start point does not decode to the base set");
}

TuneReport TuneStudy::Run() const {
  TuneObserver none;
  return Run(none);
}

namespace {

/// Phase compare: the base set and the exported set on the training, then the held-out scenarios
/// (`held` receives the held-out evaluator), the verdicts at the study's resolution, the clean
/// laps against the budget, and the statement when the search found a gain the export lost.
void CompareWithBase(const TuneStudy& study, const BatchEvaluator& training,
                     std::optional<BatchEvaluator>* held, const TunePrepared& prep,
                     TuneObserver& observer, const TuneObjective& fine_objective,
                     const SetEvaluation& fine_base,
                     const std::optional<SetEvaluation>& tuned_training, TuneReport* report) {
  const TuneStudyOptions& o = study.options();
  const ScenarioSet& set = study.scenarios();
  const params::StabilityParams& base = study.base();
  Problems pr;
  const ParameterSpace exported = study.space().WithPinned(report->pinned_dims);
  report->tuned = exported.Decode(report->exported_u, base, &pr);
  if (!pr.empty())
    throw std::runtime_error("internal error: the exported point decodes to an invalid set");
  report->new_findings = NewCheckFindings(base, report->tuned);
  const std::set<std::string> changed = params::DifferingKeys(report->tuned, base);
  report->changed.assign(changed.begin(), changed.end());

  const std::vector<params::StabilityParams> both = {base, report->tuned};
  const int n_train = static_cast<int>(set.training.size());
  const int n_held = static_cast<int>(set.held_out.size());
  // The base set's training runs are known; the exported set's are when the revert ran.
  const bool known = tuned_training.has_value();
  const int total = (known ? 0 : n_train) + 3 * n_held;
  observer.OnPhaseBegin(TunePhase::kCompare, total);
  report->training = {
      fine_base,
      known ? *tuned_training
            : training.Evaluate({report->tuned}, Jobs(observer, TunePhase::kCompare, 0, total))
                  .front()};
  const int done = known ? 0 : n_train;
  report->training_change =
      CompareSets(training, report->training[0], report->training[1], o.resolution);
  report->tuned_value = fine_objective.Of(report->training[1]);
  if (!set.held_out.empty()) {
    held->emplace(BatchEvaluator::FromEntries(set.held_out, set.base_dir, set.cost, o.threads,
                                              Jobs(observer, TunePhase::kCompare, done, total),
                                              prep.cache.get(), prep.memo));
    report->held_out =
        (*held)->Evaluate(both, Jobs(observer, TunePhase::kCompare, done + n_held, total));
    report->held_out_change =
        CompareSets(**held, report->held_out[0], report->held_out[1], o.resolution);
    const TuneObjective held_objective =
        TuneObjective::For(**held, o.objective, o.budget, report->held_out[0]);
    report->held_out_value = held_objective.Of(report->held_out[1]);
    report->held_out_base_value = held_objective.base_value();
  }
  // A gain the search found and the export does not keep is said, never called "no change".
  const TuneResult& r = report->optimisation;
  const double base_merit = r.start_cost;
  const double gain = base_merit - r.best_cost;
  const double exported_gain = report->base_value.merit - report->tuned_value.merit;
  if (gain >= o.resolution && exported_gain < o.resolution) {
    std::string why;
    if (report->changed.empty())
      why = "the exported file changes no key";
    else
      why = "the exported set gains " +
            params::FormatNumber(std::round(exported_gain * 1e3) / 1e3) + " at the vehicle's step";
    report->unexported_gain =
        "the search found a merit of " + params::FormatNumber(std::round(r.best_cost * 1e3) / 1e3) +
        " against the base's " + params::FormatNumber(std::round(base_merit * 1e3) / 1e3) + " (" +
        EvaluationName(r.best_eval) + "), but " + why +
        ": the search's gain is NOT in the file (see the revert decisions and the selection)";
  }
  observer.OnPhaseEnd(TunePhase::kCompare, *report);
}

/// Phase neighbourhood: the knife-edge check of the exported set on both groups.
NeighbourhoodInput KnifeEdgeInput(const TuneStudy& study, const BatchEvaluator& training,
                                  const BatchEvaluator* held, const TunePrepared& prep,
                                  const TuneReport& report) {
  NeighbourhoodInput in;
  in.scenarios = &study.scenarios();
  in.space = &study.space();
  in.pinned = report.pinned_dims;
  in.base = &study.base();
  in.reference = &study.base();
  in.u = report.exported_u;
  in.training = &training;
  in.held_out = held;
  in.training_centre = &report.training[1];
  in.held_out_centre = held ? &report.held_out[1] : nullptr;
  in.step = study.options().neighbourhood_step;
  in.threads = study.options().threads;
  in.cache = prep.cache.get();
  in.memo = prep.memo;
  return in;
}

void CheckKnifeEdges(const TuneStudy& study, const BatchEvaluator& training,
                     const BatchEvaluator* held, const TunePrepared& prep, TuneObserver& observer,
                     TuneReport* report) {
  const NeighbourhoodInput in = KnifeEdgeInput(study, training, held, prep, *report);
  std::vector<std::string> notes;
  const std::vector<Neighbour> planned = PlanNeighbourhood(in, &notes);
  int runs = 0;
  // A plant neighbour runs the base set beside the exported one.
  for (const auto& nb : planned)
    runs += static_cast<int>(
        (training.scenarios().size() + (held ? held->scenarios().size() : std::size_t{0})) *
        (nb.plant && in.reference ? 2 : 1));
  observer.OnPhaseBegin(TunePhase::kNeighbourhood, runs);
  report->neighbourhood =
      CheckNeighbourhood(in, Jobs(observer, TunePhase::kNeighbourhood, 0, runs));
  report->neighbourhood_done = true;
  observer.OnPhaseEnd(TunePhase::kNeighbourhood, *report);
}

/// Phase robust (options.robust): the training knife edges join the objective and the search
/// continues from the exported point; after each round the comparison and the check run again.
void RunRobust(const TuneStudy& study, const BatchEvaluator& training,
               std::optional<BatchEvaluator>* held, const TunePrepared& prep,
               TuneObserver& observer, const TuneObjective& fine_objective,
               const SetEvaluation& fine_base, TuneReport* report) {
  const TuneStudyOptions& o = study.options();
  report->neighbourhood_before_robust = report->neighbourhood;
  report->tuned_value_before_robust = report->tuned_value;
  std::vector<ActiveEdge> active;
  for (int round = 1; round <= kRobustRounds; ++round) {
    const std::size_t before = active.size();
    AddActiveEdges(report->neighbourhood, training, report->exported_u, &active);
    bool training_edge = false;
    for (const auto& e : report->neighbourhood.edges)
      training_edge |= e.group == "training" && !e.base_also_aborts();
    if (!training_edge || (round > 1 && active.size() == before)) break;
    RobustRoundInput in;
    in.scenarios = &study.scenarios();
    in.space = &study.space();
    in.pinned = report->pinned_dims;
    in.base = &study.base();
    in.start = report->exported_u;
    in.training = &training;
    in.objective = &fine_objective;
    in.active = active;
    in.step = o.neighbourhood_step;
    in.evaluations = std::max(1, o.max_evals / 2);
    in.seed = o.seed;
    if (!o.evaluation_log.empty())
      in.log = (std::filesystem::path(o.evaluation_log).parent_path() /
                ("robust_evaluations_" + std::to_string(round) + ".csv"))
                   .string();
    in.threads = o.threads;
    in.cache = prep.cache.get();
    in.memo = prep.memo;
    in.stop = o.stop;
    in.on_progress = [&observer](const Progress& p) { observer.OnEvaluation(p); };
    observer.OnPhaseBegin(TunePhase::kRobust, in.evaluations);
    const RobustRoundResult r = RunRobustRound(in);
    report->robust_rounds = round;
    report->robust_evaluations += r.search.evals;
    report->exported_u = r.best;
    observer.OnPhaseEnd(TunePhase::kRobust, *report);
    CompareWithBase(study, training, held, prep, observer, fine_objective, fine_base, std::nullopt,
                    report);
    CheckKnifeEdges(study, training, held->has_value() ? &**held : nullptr, prep, observer, report);
    if (r.search.stop_reason == "interrupted") break;
  }
}

}  // namespace

TuneReport TuneStudy::Run(TuneObserver& observer) const {
  TuneReport report;
  const TunePrepared prepared = Prepare(observer, &report);
  Search(prepared, observer, &report);
  Finish(prepared, observer, &report);
  return report;
}

TuneObjective TuneStudy::ObjectiveOn(const BatchEvaluator& ev, const SetEvaluation& base) const {
  return TuneObjective::For(ev, options_.objective, options_.budget, base);
}

std::vector<int> TuneStudy::FreeDimensions(const TuneReport& report, bool* all_frozen) const {
  std::vector<int> free_dims;
  for (int i = 0; i < space_.size(); ++i)
    if (std::find(report.frozen_dims.begin(), report.frozen_dims.end(), i) ==
        report.frozen_dims.end())
      free_dims.push_back(i);
  if (all_frozen) *all_frozen = free_dims.empty();
  // Nothing left to tune: the base set is evaluated once, as evaluation 0.
  if (free_dims.empty())
    for (int i = 0; i < space_.size(); ++i) free_dims.push_back(i);
  return free_dims;
}

TunerOptions TuneStudy::SearchOptions(const TuneReport& report,
                                      const TrainingObjective& objective) const {
  bool all_frozen = false;
  const std::vector<int> free_dims = FreeDimensions(report, &all_frozen);
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
  return to;
}

TunePrepared TuneStudy::Prepare(TuneObserver& observer, TuneReport* report_out) const {
  const ScenarioSet& set = scenarios_;
  const TuneStudyOptions& o = options_;
  TuneReport& report = *report_out;
  TunePrepared prep;
  const int n_training = static_cast<int>(set.training.size());
  // The training scenarios and the base set on them at the vehicle's step; with a search step its
  // evaluator too and the base set there (4 jobs per scenario in all).
  const double step = o.SearchPlantStep();
  const int n_prepare = (step > 0.0 ? 4 : 2) * n_training;
  observer.OnPhaseBegin(TunePhase::kPrepare, n_prepare);
  // One preparation cache for every evaluator of the run (training, the search step's, held-out,
  // the neighbourhood's).
  prep.cache = std::make_shared<controller::planning::ReferenceCache>(&PrepCache::Process());
  prep.memo = std::make_shared<RunMemo>();
  prep.training = std::make_shared<const BatchEvaluator>(BatchEvaluator::FromEntries(
      set.training, set.base_dir, set.cost, o.threads,
      Jobs(observer, TunePhase::kPrepare, 0, n_prepare), prep.cache.get(), prep.memo));
  const BatchEvaluator& training = *prep.training;
  prep.fine_base =
      training.Evaluate({base_}, Jobs(observer, TunePhase::kPrepare, n_training, n_prepare))
          .front();
  report.plant_step.step = step;
  if (step > 0.0 && StepDiffers(training, step)) {
    auto coarse = std::make_shared<const BatchEvaluator>(BatchEvaluator::FromEntries(
        WithPlantStep(set.training, step), set.base_dir, set.cost, o.threads,
        Jobs(observer, TunePhase::kPrepare, 2 * n_training, n_prepare), prep.cache.get(),
        prep.memo));
    prep.coarse_base =
        coarse->Evaluate({base_}, Jobs(observer, TunePhase::kPrepare, 3 * n_training, n_prepare))
            .front();
    std::vector<std::string> names;
    for (const auto& sc : training.scenarios()) names.push_back(sc.spec.name);
    report.plant_step = ComparePlantSteps(step, names, prep.fine_base, prep.coarse_base,
                                          o.search_plant_step_tolerances);
    if (report.plant_step.used() > 0.0) prep.coarse = std::move(coarse);
  } else {
    // Every vehicle has that step already: nothing to check, the counted jobs are done.
    for (int done = 2 * n_training + 1; done <= n_prepare; ++done)
      observer.OnJobs(TunePhase::kPrepare, done, n_prepare);
  }
  report.threads = training.threads();
  report.ranks = exec::mpi::Ranks();
  const TuneObjective fine_objective = ObjectiveOn(training, prep.fine_base);
  report.objective = fine_objective.Describe();
  report.base_value = fine_objective.base_value();
  observer.OnPhaseEnd(TunePhase::kPrepare, report);
  if (o.stop && o.stop->load()) throw TuneInterrupted("during the preparation");

  // Screen: which dimensions can the training scenarios see at all? Those that cannot are frozen.
  // A resume takes them from the log's screen file.
  prep.screen_read = !o.resume_log.empty() && o.freeze_unexercised &&
                     ReadScreenFile(EvaluationLogScreenPath(o.resume_log), space_, &report);
  if (o.freeze_unexercised && !prep.screen_read) {
    const SensitivityPlan plan = PlanSensitivity(space_, u0_, base_, SensitivityMode::kRange);
    const BatchEvaluator& search = prep.search();
    const int n_runs = static_cast<int>(plan.sets.size() * search.scenarios().size());
    observer.OnPhaseBegin(TunePhase::kScreen, n_runs);
    report.screening =
        EvaluateSensitivity(search, space_, plan, Jobs(observer, TunePhase::kScreen, 0, n_runs));
    report.screened = true;
    for (int i = 0; i < space_.size(); ++i)
      if (!report.screening.dimensions[static_cast<std::size_t>(i)].exercised)
        report.frozen_dims.push_back(i);
    report.frozen = Described(report.screening, report.frozen_dims);
    observer.OnPhaseEnd(TunePhase::kScreen, report);
  } else if (prep.screen_read) {
    observer.OnPhaseEnd(TunePhase::kScreen, report);
  }
  if (o.stop && o.stop->load()) throw TuneInterrupted("during the screen");
  bool all_frozen = false;
  const std::vector<int> free_dims = FreeDimensions(report, &all_frozen);
  report.free_dimensions = all_frozen ? 0 : static_cast<int>(free_dims.size());
  report.pinned_dims = report.frozen_dims;
  return prep;
}

void TuneStudy::Search(const TunePrepared& prep, TuneObserver& observer,
                       TuneReport* report_out) const {
  const TuneStudyOptions& o = options_;
  TuneReport& report = *report_out;
  bool all_frozen = false;
  const std::vector<int> free_dims = FreeDimensions(report, &all_frozen);
  const auto expand = [this, &free_dims](const std::vector<double>& v) {
    std::vector<double> u = u0_;
    for (std::size_t k = 0; k < free_dims.size() && k < v.size(); ++k)
      u[static_cast<std::size_t>(free_dims[k])] = v[k];
    return u;
  };
  std::vector<double> v0;
  for (int i : free_dims) v0.push_back(u0_[static_cast<std::size_t>(i)]);

  // The optimiser's space: the frozen dimensions pinned at the base value.
  const ParameterSpace search_space = space_.WithPinned(report.frozen_dims);
  const TuneObjective search_objective = ObjectiveOn(prep.search(), prep.search_base());
  const TrainingObjective objective(search_space, base_, prep.search(), search_objective,
                                    o.algorithm == "auglag");
  TopPoints top(kSelectCandidates);
  TunerOptions to = SearchOptions(report, objective);
  to.on_record = [&top, &expand](int index, const std::vector<double>& v, const Evaluation& ev) {
    if (ev.constraint <= 0.0) top.Add(index, expand(v), ev.cost);  // auglag: within the budget
  };
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
  const std::string identity = LogIdentity(report, *prep.training);
  if (!o.resume_log.empty()) {
    report.extended = CheckLogIdentity(o.resume_log, identity, o.algorithm);
    TunerOptions verify = to;
    verify.resume_path = o.resume_log;
    verify.verify_resume = true;
    verify.stop = nullptr;
    verify.max_time_s = 0.0;
    verify.on_record = nullptr;
    TuneResult replayed;
    try {
      replayed = Tune(v0, single, batch_objective, verify);
    } catch (const ResumeMismatch& e) {
      throw ConfigError(o.resume_log, "", e.what());
    }
    if (replayed.stop_reason != "verified" && o.stop_if_complete)
      throw TuneAlreadyComplete(
          o.resume_log + " already holds the whole run (" + std::to_string(replayed.evals) +
          " evaluations, stop: " + replayed.stop_reason + "); nothing was written. " +
          (replayed.stop_reason == "converged"
               ? std::string("The search converged: a larger budget does not continue it.")
               : "To continue the search, raise --max-evals (e.g. --max-evals " +
                     std::to_string(2 * o.max_evals) + ")."));
  }
  if (!o.evaluation_log.empty()) {
    const std::string id_path = EvaluationLogIdentityPath(o.evaluation_log);
    std::ifstream existing(id_path, std::ios::binary);
    std::ostringstream text;
    text << existing.rdbuf();
    if (!existing || text.str() != identity) io::WriteFileAtomic(id_path, identity);
    if (report.screened && !prep.screen_read)
      io::WriteFileAtomic(EvaluationLogScreenPath(o.evaluation_log),
                          ScreenFileText(report.screening, report.frozen_dims));
  }

  to.log_path = o.evaluation_log;
  to.resume_path = o.resume_log;
  to.on_progress = [&observer](const Progress& p) { observer.OnEvaluation(p); };
  observer.OnPhaseBegin(TunePhase::kOptimise, to.max_evals);
  try {
    report.optimisation = Tune(v0, single, batch_objective, to);
  } catch (const ResumeMismatch& e) {
    throw ConfigError(o.resume_log, "", e.what());
  }
  TuneResult& opt = report.optimisation;
  opt.best_u = expand(opt.best_u);
  if (all_frozen) opt.stop_reason = "all_frozen";
  report.top_points = top.entries();
  report.convergence = all_frozen ? std::string("nothing to tune: every parameter is frozen")
                                  : ConvergenceVerdict(opt, o.max_evals, report.free_dimensions);
  observer.OnPhaseEnd(TunePhase::kOptimise, report);
}

void TuneStudy::Finish(const TunePrepared& prep, TuneObserver& observer,
                       TuneReport* report_out) const {
  const TuneStudyOptions& o = options_;
  TuneReport& report = *report_out;
  const BatchEvaluator& training = *prep.training;
  const int n_training = static_cast<int>(training.scenarios().size());
  const TuneObjective fine_objective = ObjectiveOn(training, prep.fine_base);
  const TuneObjective search_objective = ObjectiveOn(prep.search(), prep.search_base());
  const ParameterSpace search_space = space_.WithPinned(report.frozen_dims);
  const TuneResult& opt = report.optimisation;
  const auto stopped = [&o] { return o.stop && o.stop->load(); };

  // Select: the budget is the car's, judged at the vehicle's step. The best points of a search at
  // a coarser step (within the budget there, the base among them) run at the vehicle's step; the
  // best within the budget there is exported.
  report.chosen_eval = opt.best_eval;
  report.exported_u = opt.best_u;
  std::optional<SetEvaluation> chosen_eval;
  if (o.objective == ObjectiveKind::kConstrained && prep.coarse) {
    std::vector<TopPoint> candidates;
    bool base_in = false;
    for (const auto& e : report.top_points) {
      if (e.cost > search_objective.base_value().merit) continue;  // over the budget there
      candidates.push_back(e);
      base_in = base_in || e.index == 0;
    }
    if (!base_in) candidates.push_back({0, search_objective.base_value().merit, u0_});
    std::vector<params::StabilityParams> sets;
    for (const auto& c : candidates) sets.push_back(search_space.Decode(c.u, base_, nullptr));
    const int n_runs = static_cast<int>(sets.size()) * n_training;
    observer.OnPhaseBegin(TunePhase::kSelect, n_runs);
    const std::vector<SetEvaluation> at_own_step =
        training.Evaluate(sets, Jobs(observer, TunePhase::kSelect, 0, n_runs));
    std::size_t pick = candidates.size();
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const ObjectiveValue v = fine_objective.Of(at_own_step[k]);
      report.selection.push_back(
          EvaluationName(candidates[k].index) + ": merit " +
          params::FormatNumber(std::round(candidates[k].cost * 1000.0) / 1000.0) + " at " +
          params::FormatNumber(report.plant_step.used() * 1000.0) + " ms, " +
          params::FormatNumber(std::round(v.merit * 1000.0) / 1000.0) + " at the vehicle's step" +
          (v.within_budget() ? "" : " (over the budget there)"));
      if (!v.within_budget()) continue;
      if (pick == candidates.size() || v.merit < report.chosen_merit ||
          (v.merit == report.chosen_merit && candidates[k].index < candidates[pick].index)) {
        pick = k;
        report.chosen_merit = v.merit;
      }
    }
    // The base point meets its own budget: something is always within it.
    report.chosen_eval = candidates[pick].index;
    report.exported_u = candidates[pick].u;
    chosen_eval = at_own_step[pick];
    observer.OnPhaseEnd(TunePhase::kSelect, report);
  }

  // Sensitivity around the exported point; what no training run responds to goes back to the base
  // if the whole set, re-evaluated, says it may.
  report.sensitivity_state = o.sensitivity && opt.stop_reason != "interrupted"
                                 ? SensitivityState::kPending
                                 : SensitivityState::kSkipped;
  if (report.sensitivity_state == SensitivityState::kPending) {
    const SensitivityPlan plan = PlanSensitivity(search_space, report.exported_u, base_);
    const int n_runs = static_cast<int>(plan.sets.size()) * n_training;
    observer.OnPhaseBegin(TunePhase::kSensitivity, n_runs);
    report.sensitivity = EvaluateSensitivity(training, search_space, plan,
                                             Jobs(observer, TunePhase::kSensitivity, 0, n_runs));
    report.sensitivity_csv = SensitivityCsv(report.sensitivity);
    report.sensitivity_state = SensitivityState::kDone;
    observer.OnPhaseEnd(TunePhase::kSensitivity, report);

    std::vector<std::pair<int, std::string>> candidates;
    for (int i = 0; i < space_.size(); ++i) {
      const DimensionSensitivity& d = report.sensitivity.dimensions[static_cast<std::size_t>(i)];
      if (!d.exercised) candidates.emplace_back(i, d.reason);
    }
    if (!chosen_eval)
      chosen_eval = training.Evaluate(search_space.Decode(report.exported_u, base_, nullptr));
    report.chosen_merit = fine_objective.Of(*chosen_eval).merit;
    const int n_candidates = static_cast<int>(candidates.size());
    observer.OnPhaseBegin(TunePhase::kRevert, n_candidates);
    const double tolerance = std::isfinite(o.budget.lap_s) ? o.budget.lap_s : kDefaultLapBudget;
    report.revert = RevertJointly(training, space_, base_, report.exported_u, report.pinned_dims,
                                  candidates, fine_objective, *chosen_eval, tolerance,
                                  Jobs(observer, TunePhase::kRevert, 0, n_candidates));
    report.pinned_dims = report.revert.pinned;
    report.reverted = RevertedItems(report.revert);
    for (const auto& kept : KeptItems(report.revert))
      if (kept.find("NOT reverted") != std::string::npos) report.reverted.push_back(kept);
    observer.OnPhaseEnd(TunePhase::kRevert, report);
  }

  // Compare, then the knife edges, then (robust) the continuation; the outputs last.
  std::optional<BatchEvaluator> held;
  std::optional<SetEvaluation> tuned_training;
  if (report.sensitivity_state == SensitivityState::kDone)
    tuned_training = report.revert.evaluation;
  CompareWithBase(*this, training, &held, prep, observer, fine_objective, prep.fine_base,
                  tuned_training, &report);
  if (o.neighbourhood && opt.stop_reason != "interrupted" && !stopped()) {
    CheckKnifeEdges(*this, training, held ? &*held : nullptr, prep, observer, &report);
    if (o.robust && OwnEdges(report.neighbourhood) > 0)
      RunRobust(*this, training, &held, prep, observer, fine_objective, prep.fine_base, &report);
  }
  detail::AnnotateKeptRelations(*this, &report);
  report.comparison_markdown =
      detail::ComparisonReportMarkdown(*this, report, training, held ? &*held : nullptr);
  report.comparison_csv = detail::ComparisonReportCsv(report, training, held ? &*held : nullptr);
  detail::ComposeTunedFiles(*this, &report);
  observer.OnPhaseEnd(TunePhase::kExport, report);
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
      << "objective: " << ObjectiveKindName(o.objective) << "\n"
      << "objective_description: " << params::QuoteString(report.objective) << "\n"
      << "lap_budget_s: " << params::FormatDouble(o.budget.lap_s) << "\n"
      << "clean_interventions_limited: " << (o.budget.interventions ? "true" : "false") << "\n"
      << "resolution_s: " << params::FormatDouble(o.resolution) << "\n"
      << "max_time_s: " << params::FormatDouble(o.max_time_s) << "\n"
      << "search_plant_step: " << params::FormatDouble(o.SearchPlantStep()) << "\n"
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
      << "extended: " << (report.extended ? "true" : "false") << "\n"
      << "exported_evaluation: " << report.chosen_eval << "\n"
      << "baseline_stability: " << params::FormatDouble(report.base_value.stability) << "\n"
      << "tuned_stability: " << params::FormatDouble(report.tuned_value.stability) << "\n"
      << "tuned_lap_loss_s: " << params::FormatDouble(report.tuned_value.lap_loss) << "\n"
      << "tuned_within_budget: " << (report.tuned_value.within_budget() ? "true" : "false") << "\n"
      << "unexported_gain: " << params::QuoteString(report.unexported_gain) << "\n"
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
  if (report.neighbourhood_done) {
    man << "knife_edges: " << report.neighbourhood.edges.size() << "\n"
        << "neighbours: " << report.neighbourhood.neighbours.size() << "\n";
    list("knife_edge_keys", report.neighbourhood.EdgeKeys());
  } else {
    man << "knife_edges: \"not checked\"\n";
  }
  if (o.robust)
    man << "robust_rounds: " << report.robust_rounds << "\n"
        << "robust_evaluations: " << report.robust_evaluations << "\n"
        << "knife_edges_before_robust: " << report.neighbourhood_before_robust.edges.size() << "\n";
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
