// The workflows of `scw tune` and `scw evaluate` as library calls: the CLI maps its options onto
// them, shows their progress and writes what they return.
//
// TuneStudy — the main job. Constructed from what is already loaded (the base set, the search
// space as given, the scenario set) and the settings; the constructor fits the space to the base
// (TuneStudy::space()) and checks the settings, so that every problem with the inputs is found
// before anything runs or a folder is made. Run(observer) goes through these phases, each a unit
// of its own (the header named beside it) with its contract:
//
//   prepare       resolve the training scenarios (racing line, velocity profile); with a search
//                 plant step a second evaluator at that step, and the base set on both decides
//                 whether the optimiser may use it (plant_step_check.h; report.plant_step). The
//                 base set's evaluations fix the objective (objective.h: the stability cost
//                 within the clean-lap budget by default, options.objective / options.budget).
//   screen        (options.freeze_unexercised) each dimension alone moved to each end of its
//                 range, one batch at the search step (sensitivity.h, kRange); a dimension that
//                 changes no run, bit for bit, is FROZEN at the base point (report.frozen). A
//                 resume takes the frozen set from the log's screen file instead of screening
//                 again.
//   (resume)      the log's identity file must equal this run's (a larger max_evals is allowed
//                 for the single-phase NLopt algorithms: the run is extended) and the whole log
//                 must replay; otherwise ConfigError naming every difference, before anything is
//                 written. A log that already holds the whole run (its search ended within it)
//                 with options.stop_if_complete throws TuneAlreadyComplete, writing nothing.
//   optimise      Tune() (tuner.h) from the base point over the free dimensions, at the search
//                 step; the objective is the merit of objective.h (a set that breaks a schema rule
//                 costs more than any set that runs). Every evaluation is appended to the log.
//   select        (kConstrained with a search step) the 8 best points of the search within the
//                 budget, the base point among them, run at the vehicle's own step; the best
//                 within the budget there is the point exported (the budget is the car's: judged
//                 at the step the comparison runs at).
//   sensitivity   the one-at-a-time sensitivity around that point on the training scenarios at
//                 the vehicle's step (sensitivity.h); skipped by options.sensitivity = false or
//                 an interrupted search.
//   revert        the dimensions the sensitivity finds not exercised, reverted to the base ONE AT A
//                 TIME WITH THE WHOLE SET RE-EVALUATED (revert.h): a revert that aborts a run,
//                 breaks the budget or costs more than the budget is undone, with the reason.
//   compare       the base set ("baseline") and the exported set ("tuned") on the training, then
//                 the held-out scenarios: tables, verdicts at options.resolution (comparison.h),
//                 the clean laps against the budget.
//   neighbourhood (options.neighbourhood) the exported set with each changed key moved by ±10 %
//                 of its range and the plant's unknowns at their draw bounds, on both groups: a
//                 completed run that aborts is a knife edge (neighbourhood.h). With
//                 options.robust the knife edges found join the objective and the search
//                 continues (phase "robust", below).
//   export        the tuned full and overrides-only params files with their provenance header,
//                 both checked as the car's ROS 2 node would load them, and comparison.md. The
//                 outputs are complete at OnPhaseEnd(kExport, report).
//
// Stop: options.stop (scw tune's SIGINT flag) ends the optimisation after the current evaluation
// (or batch); the best set so far then goes through the comparison as usual, with stop reason
// "interrupted", and the sensitivity is skipped.
//
// Determinism: the same inputs, seed and budget give the same report bit for bit, for any thread
// count and number of MPI ranks (the tuner, the evaluator and the sensitivity are deterministic);
// a wall-time limit (max_time_s > 0) makes the stop depend on the machine's speed. The date of the
// tuned files' header comes from options.date_utc, the only clock that reaches the report.
//
// Errors: the constructor throws std::invalid_argument for an unknown algorithm or a batch the
// algorithm cannot take, ConfigError for a base outside the space under BaseOutsideSpace::kRefuse
// (naming the key); Run throws std::runtime_error when the tuner does (the evaluation log cannot be
// written, the resume log diverges from this problem) or an exported file fails the ROS 2 params
// check, and passes on what an observer throws.
//
// EvaluateSets — `scw evaluate`: given parameter sets side by side on the training and held-out
// scenarios. TuneStudy::CheckSet — `scw tune --check-set`: which subsystems and parameters the
// scenario set can see around the study's base point.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "params/schema/stability_params.h"
#include "tuning/optim/comparison.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/neighbourhood.h"
#include "tuning/optim/objective.h"
#include "tuning/optim/plant_step_check.h"
#include "tuning/optim/revert.h"
#include "tuning/optim/sensitivity.h"
#include "tuning/optim/space.h"
#include "tuning/optim/training_objective.h"
#include "tuning/optim/tuner.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {

/// File names of a tune's outputs inside its run folder (they appear in the tuned files' header
/// and in the messages of the export check).
inline constexpr const char* kTunedParamsFile = "stability_tuned.yaml";
inline constexpr const char* kOverridesParamsFile = "stability_overrides.yaml";

struct TuneStudyOptions {
  // The search (scw tune's options of the same names).
  std::string algorithm = "sbplx";  ///< see TunerOptions::algorithm
  int batch = 1;                    ///< candidates per objective call ("lhs" algorithms)
  int max_evals = 240;              ///< evaluation budget (docs/tuning-benchmark.md)
  double max_time_s = 0.0;          ///< wall-time limit (0: none)
  unsigned long long seed = 1;
  int threads = 0;  ///< worker threads per process of every evaluator (0: all cores)
  BaseOutsideSpace base_outside = BaseOutsideSpace::kGrow;
  /// What the search minimises (objective.h): the stability cost within the clean-lap budget
  /// (default), or the weighted sum of the earlier tunes.
  ObjectiveKind objective = ObjectiveKind::kConstrained;
  CleanLapBudget budget;  ///< kConstrained's clean-lap budget (--lap-budget)
  /// The smallest scenario-cost change the comparison calls a change [s] (comparison.h).
  double resolution = kDefaultResolution;
  bool sensitivity = true;  ///< the parameter sensitivity after the optimisation (and CheckSet)
  /// The knife-edge check of the exported set (neighbourhood.h), and its key step.
  bool neighbourhood = true;
  double neighbourhood_step = kNeighbourhoodStep;
  /// Robust in the small: the knife edges the check finds join the objective and the search
  /// continues from the exported point (options.max_evals / 2 evaluations per round, at most
  /// kRobustRounds rounds), then revert and check again.
  bool robust = false;
  /// Freeze the dimensions the training scenarios cannot see before the search (phase kScreen).
  bool freeze_unexercised = true;
  /// The plant step the optimiser evaluates candidates with [s] (0: each vehicle's own step);
  /// used only where the check on the base set passes (plant_step_check.h). The comparison, the
  /// sensitivity and the exported files' provenance always run at the vehicle's own step.
  /// < 0 (default): automatic — 0 for the constrained objective, whose clean-lap budget of a few
  /// hundredths of a second is finer than what a coarser step keeps (a search at 2 ms found sets
  /// that abort a clean lap at 1 ms), kDefaultSearchPlantStep for the sum. SearchPlantStep() gives
  /// the step used.
  double search_plant_step = -1.0;
  double SearchPlantStep() const {
    return search_plant_step >= 0.0
               ? search_plant_step
               : (objective == ObjectiveKind::kSum ? kDefaultSearchPlantStep : 0.0);
  }
  PlantStepTolerances search_plant_step_tolerances;

  // Streaming (the tuner writes and reads these files while it runs).
  std::string evaluation_log;               ///< CSV log of every evaluation ("" = none)
  std::string resume_log;                   ///< earlier log to replay first ("" = none)
  const std::atomic<bool>* stop = nullptr;  ///< set it to end the optimisation early
  /// A resume whose log already holds the whole run throws TuneAlreadyComplete (nothing written)
  /// instead of comparing and exporting again.
  bool stop_if_complete = false;

  // Provenance: only printed (tuned files' header, comparison Markdown, manifest), never read.
  std::string base_file;       ///< the base params file ("" = the built-in shipped set)
  std::string space_file;      ///< the space file ("" = the built-in default)
  std::string scenarios_file;  ///< the scenario set file ("" = the built-in default)
  /// Keys the base file sets: its optional keys stay in the full export (params::ToRosYaml).
  std::set<std::string> base_keys;
  std::string run_folder;  ///< where the outputs go (header, messages)
  std::string tool_version, git_revision;
  /// The date (ISO 8601 UTC) of the tuned files' header and the manifest, asked once when the
  /// outputs are composed (after the comparison); empty: no date.
  std::function<std::string()> date_utc;
};

/// Rounds of the robust continuation (options.robust).
inline constexpr int kRobustRounds = 2;
/// The search's best points (TuneReport::top_points) the select phase runs at the vehicle's step
/// when the search ran at a coarser one.
inline constexpr std::size_t kSelectCandidates = 8;

enum class TunePhase {
  kPrepare,
  kScreen,
  kOptimise,
  kSelect,
  kSensitivity,
  kRevert,
  kCompare,
  kNeighbourhood,
  kRobust,
  kExport,
};
/// "prepare", "screen", "optimise", "select", "sensitivity", "revert", "compare",
/// "neighbourhood", "robust", "export".
const char* TunePhaseName(TunePhase phase);

/// The sensitivity's state in a report.
enum class SensitivityState {
  kPending,  ///< not run yet (a report handed to OnPhaseEnd before kSensitivity)
  kDone,
  kSkipped,  ///< options.sensitivity is false, or the run was interrupted
};

/// What a TuneStudy returns: everything `scw tune` writes, as values and as texts.
struct TuneReport {
  // prepare
  int threads = 0;  ///< worker threads per process of the evaluators
  int ranks = 1;    ///< MPI ranks computing runs
  /// The search step's check (options.search_plant_step); its used() step is the one the
  /// optimisation ran with.
  PlantStepCheck plant_step;
  // screen
  bool screened = false;            ///< the screen ran (options.freeze_unexercised)
  SensitivityResult screening;      ///< the range screen around the base point (screened only)
  std::vector<std::string> frozen;  ///< labels of the frozen dimensions, "label (reason)"
  std::vector<int> frozen_dims;     ///< their indices in space()
  // objective
  std::string objective;  ///< TuneObjective::Describe()
  /// The base set on the training scenarios at the vehicle's step, and its objectives.
  ObjectiveValue base_value;
  // optimise
  TuneResult optimisation;  ///< best point and cost, start cost, evaluations, stop reason
  int free_dimensions = 0;  ///< dimensions the search moved (not frozen)
  bool extended = false;    ///< a resume that raised the budget of the logged run
  /// The best evaluations of the search (cost order, at most 8), for the select phase.
  std::vector<TopPoint> top_points;
  /// "last improvement of more than 0.5 % at evaluation 177 of 180: not converged, raise
  /// --max-evals" (ConvergenceVerdict).
  std::string convergence;
  // select
  /// The evaluation of the search whose point is exported (before the revert), and its merit at
  /// the vehicle's step; `selection` one line per point tried ("" when nothing was selected: the
  /// search's best is taken as it is).
  int chosen_eval = -1;
  double chosen_merit = 0.0;
  std::vector<std::string> selection;
  // sensitivity
  SensitivityState sensitivity_state = SensitivityState::kPending;
  SensitivityResult sensitivity;  ///< kDone only
  std::string sensitivity_csv;    ///< sensitivity.csv (kDone only)
  /// Dimensions reverted to the base point after the search, "label (reason)", and the exported
  /// point (the best point with those dimensions at the base point).
  std::vector<std::string> reverted;
  RevertResult revert;  ///< the joint revert (kDone only): every decision, the final evaluation
  std::vector<double> exported_u;
  /// The dimensions pinned at the base value in the exported set: the frozen and the reverted
  /// ones (ParameterSpace::WithPinned); the exported set is space().WithPinned(pinned_dims)
  /// decoding exported_u.
  std::vector<int> pinned_dims;
  // compare
  /// The exported point decoded against the base, quantised to the schema resolutions: exactly
  /// what is exported and compared.
  params::StabilityParams tuned;
  /// `scw params check` findings of the tuned set that the base set does not have ("key: text";
  /// by construction of the space there should be none).
  std::vector<std::string> new_findings;
  std::vector<std::string> changed;            ///< dotted keys where tuned ≠ base (sorted)
  std::vector<SetEvaluation> training;         ///< [0] base, [1] tuned, on the training scenarios
  std::vector<SetEvaluation> held_out;         ///< the same on the held-out ones (empty: none)
  SetChange training_change, held_out_change;  ///< verdicts (held_out_change: held-out only)
  /// The exported set's objectives at the vehicle's step (training), and both sets' clean laps on
  /// the held-out scenarios against the same budget.
  ObjectiveValue tuned_value, held_out_value;
  /// The base set's objectives on the held-out scenarios (its stability: a front's base point).
  ObjectiveValue held_out_base_value;
  /// Non-empty when the search found a gain the export does not keep: the statement that says so
  /// and why (the comparison then never calls the set unchanged).
  std::string unexported_gain;
  // neighbourhood
  bool neighbourhood_done = false;
  NeighbourhoodResult neighbourhood;
  /// options.robust: the knife edges before the robust continuation, and its rounds.
  NeighbourhoodResult neighbourhood_before_robust;
  ObjectiveValue tuned_value_before_robust;  ///< the exported set's objectives before it
  int robust_rounds = 0;
  int robust_evaluations = 0;
  TuneProvenance provenance;   ///< the tuned files' header
  std::string tuned_file;      ///< text of stability_tuned.yaml (checked)
  std::string overrides_file;  ///< text of stability_overrides.yaml (checked)
  std::string comparison_csv;  ///< comparison.csv
  /// comparison.md without the plots: heading, what the file changes and why (frozen, reverted,
  /// findings, convergence), tables and verdicts, then (kDone) the sensitivity.
  std::string comparison_markdown;
};

/// The convergence verdict of an optimisation over `dims` free dimensions (see
/// TuneReport::convergence). The rule: converged when NLopt met its tolerance, or when the best
/// cost has not improved by more than 0.5 % in the last 10 × dims evaluations (Subplex then has
/// had the budget for a full cycle through its subspaces without a gain); when that window does
/// not fit in the evaluations made, "budget too small to judge convergence".
std::string ConvergenceVerdict(const TuneResult& r, int max_evals, int dims);

/// Where a search's best set came from, for reports: "evaluation 14"; a front point's set found by
/// another point's search (index -1): "another point's search".
std::string EvaluationName(int index);

/// A resume whose log already holds the whole run (TuneStudyOptions::stop_if_complete): what()
/// says so and how to extend it.
class TuneAlreadyComplete : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// options.stop was set before the search began (during the preparation or the screen): nothing
/// was evaluated that a resume could continue; what() names the phase ("during the screen").
class TuneInterrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The screen file beside an evaluation log: "DIR/evaluations.csv" -> "DIR/evaluations.screen.yaml"
/// (the frozen dimensions with their reasons, read back by a resume instead of screening again).
std::string EvaluationLogScreenPath(const std::string& log);

/// The `scw params check` warnings (params::LintStability) of `tuned` whose kind the base does not
/// have, "key: text" (a kind is a warning's key and text without its numbers: the speed at which
/// a hysteresis inverts moves with the values, the kind of problem does not).
std::vector<std::string> NewCheckFindings(const params::StabilityParams& base,
                                          const params::StabilityParams& tuned);

/// The identity file beside an evaluation log: "DIR/evaluations.csv" ->
/// "DIR/evaluations.identity.yaml".
std::string EvaluationLogIdentityPath(const std::string& log);

/// Watches a study. Every method has an empty default. The job counts (OnJobs) may come from the
/// evaluator's worker threads, never two at once; everything else comes from the thread that
/// runs the study. An observer only watches: the report does not depend on it. OnEvaluation must
/// not throw (it is called inside the optimiser); an exception from any other method ends the
/// study with it.
class TuneObserver {
 public:
  virtual ~TuneObserver() = default;
  /// A phase begins; `total` counts its jobs: scenarios to prepare, the evaluation budget, runs
  /// and held-out preparations to compare, runs of the sensitivity.
  virtual void OnPhaseBegin(TunePhase /*phase*/, int /*total*/) {}
  /// Jobs done in the phase so far (kPrepare, kCompare, kSensitivity), 1 to total.
  virtual void OnJobs(TunePhase /*phase*/, int /*done*/, int /*total*/) {}
  /// After every evaluation of the optimisation (replayed ones included).
  virtual void OnEvaluation(const Progress& /*progress*/) {}
  /// A phase ended; `report` holds the results so far: after kPrepare the threads and ranks,
  /// after kScreen the frozen dimensions, after kOptimise the optimisation, after kSensitivity
  /// the sensitivity and the reverted dimensions, after kCompare the final report (the outputs
  /// are complete). Not called for a phase that threw or did not run.
  virtual void OnPhaseEnd(TunePhase /*phase*/, const TuneReport& /*report*/) {}
};

/// What only the writer of a run folder knows, for manifest.yaml.
struct TuneRunRecord {
  std::string command_line;
  /// SHA-256 of the input files named in the options (`sha256sum` form); not read for a built-in
  /// input, whose printed form the study hashes.
  std::string base_sha256, space_sha256, scenarios_sha256;
  double wall_time_s = 0.0;
  /// (file name, SHA-256) of the outputs as written, in the order to list them.
  std::vector<std::pair<std::string, std::string>> files_sha256;
};

/// What the phases of one run share: made by TuneStudy::Prepare (phases prepare and screen),
/// read by Search and Finish (and by a front's points, which share one preparation).
struct TunePrepared {
  std::shared_ptr<controller::planning::ReferenceCache> cache;  ///< every evaluator's
  /// Every evaluator's runs (evaluator.h RunMemo): a set run once is not run again by the study
  /// (or by a front's other points, which share the preparation).
  std::shared_ptr<RunMemo> memo;
  std::shared_ptr<const BatchEvaluator> training;  ///< training scenarios, each vehicle's step
  /// At the search step, when its check passed (null: the search runs on `training`).
  std::shared_ptr<const BatchEvaluator> coarse;
  SetEvaluation fine_base, coarse_base;  ///< the base set on each
  bool screen_read = false;  ///< the frozen dimensions came from the resume log's screen file
  const BatchEvaluator& search() const { return coarse ? *coarse : *training; }
  const SetEvaluation& search_base() const { return coarse ? coarse_base : fine_base; }
};

class TuneStudy {
 public:
  /// Fits `space` to `base` (options.base_outside) and checks the settings (see the header
  /// comment for what it throws). Runs nothing.
  TuneStudy(params::StabilityParams base, const ParameterSpace& space, ScenarioSet scenarios,
            TuneStudyOptions options);

  /// Every phase, in order; see above. Prepare, Search and Finish one after the other.
  TuneReport Run(TuneObserver& observer) const;
  TuneReport Run() const;

  /// Phases prepare and screen: the evaluators, the base set on them, the frozen dimensions
  /// (report: plant_step, threads, ranks, objective, base_value, screening, frozen).
  TunePrepared Prepare(TuneObserver& observer, TuneReport* report) const;
  /// The resume checks and phase optimise from the base point (report: optimisation,
  /// top_points, convergence, extended).
  void Search(const TunePrepared& prepared, TuneObserver& observer, TuneReport* report) const;
  /// The phases after the search (select, sensitivity, revert, compare, neighbourhood, robust,
  /// export) for report->optimisation and report->top_points; the outputs are complete after it.
  void Finish(const TunePrepared& prepared, TuneObserver& observer, TuneReport* report) const;
  /// This study's objective on an evaluator, against the base set's evaluation there.
  TuneObjective ObjectiveOn(const BatchEvaluator& ev, const SetEvaluation& base) const;
  /// The dimensions the search moves (all of them when every one is frozen: the base is then
  /// evaluated once), and whether every one is frozen.
  std::vector<int> FreeDimensions(const TuneReport& report, bool* all_frozen = nullptr) const;

  /// `scw tune --check-set`: the base set on every scenario as it is and with each subsystem off
  /// (set_check.h), then, if options.sensitivity, the parameter sensitivity around the base point
  /// on the training scenarios; returns the Markdown. `progress` counts every preparation and run
  /// as one job, starting with (0, total) from the calling thread. Deterministic for any thread
  /// count.
  std::string CheckSet(const BatchProgress& progress = {}) const;

  /// manifest.yaml of a run: the versions, the inputs and their hashes, the settings, the
  /// optimisation, the costs and verdicts, the sensitivity's state, the wall time and the hashes
  /// of the outputs.
  std::string ManifestYaml(const TuneReport& report, const TuneRunRecord& record) const;

  const params::StabilityParams& base() const { return base_; }
  /// The space the optimiser searches: the space as given, fitted to the base.
  const ParameterSpace& space() const { return space_; }
  /// The space as given (before fitting it to the base).
  const ParameterSpace& given_space() const { return given_; }
  /// One note per range grown to include the base (BaseOutsideSpace::kGrow).
  const std::vector<std::string>& grown() const { return grown_; }
  /// The base point: decodes to the base set bit for bit.
  const std::vector<double>& start_point() const { return u0_; }
  const ScenarioSet& scenarios() const { return scenarios_; }
  const TuneStudyOptions& options() const { return options_; }

 private:
  /// The identity file of this run's evaluation log: program, settings, hashes of the base, the
  /// fitted space and the scenarios (the set and each training scenario as loaded), the frozen
  /// dimensions. A resume must match it line for line.
  std::string LogIdentity(const TuneReport& report, const BatchEvaluator& training) const;

 public:
  /// The options of the search (TunerOptions) for the free dimensions: budget, seed, log header
  /// of `objective`, stop flag; no log path, no resume, no callbacks.
  TunerOptions SearchOptions(const TuneReport& report, const TrainingObjective& objective) const;

 private:
  params::StabilityParams base_;
  ParameterSpace given_;  ///< as loaded (the header names the ranges grown from it)
  ScenarioSet scenarios_;
  TuneStudyOptions options_;
  std::vector<std::string> grown_;
  ParameterSpace space_;
  std::vector<double> u0_;
};

/// `scw evaluate`'s table: each of `sets` (named by `labels`, one per set) on the training, then
/// the held-out scenarios of `scenarios` (a group without scenarios is left out).
struct SetsEvaluation {
  std::string markdown;  ///< one comparison table per group
  std::string csv;       ///< ComparisonCsv rows of both groups, one header
};
/// `progress` counts every preparation and run as one job, starting with (0, total) from the
/// calling thread. Deterministic for any thread count.
SetsEvaluation EvaluateSets(const ScenarioSet& scenarios,
                            const std::vector<params::StabilityParams>& sets,
                            const std::vector<std::string>& labels, int threads = 0,
                            const BatchProgress& progress = {});

}  // namespace scw::tuning
