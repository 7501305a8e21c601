// scw tune — the main job: tune the stability parameters against the scenario set, compare the
// tuned set with the starting set on training and held-out scenarios, export the car's params
// files. scw evaluate — compare given parameter files side by side. The workflows are library
// calls (tuning/optim/tune_study.h); this file maps the options onto them, checks the run folder,
// catches Ctrl-C during the optimisation, shows the progress and writes the files.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include <unistd.h>

#include "params/io/atomic_file.h"
#include "params/io/load.h"
#include "params/io/sha256.h"
#include "params/io/test_fault.h"
#include "tuning/cli/command.h"
#include "tuning/cli/console.h"
#include "tuning/cli/options.h"
#include "tuning/cli/progress.h"
#include "tuning/cli/revision.h"  // generated: SCW_GIT_REVISION
#include "tuning/cli/tune_plots.h"
#include "tuning/exec/mpi_backend.h"
#include "tuning/optim/front.h"
#include "tuning/optim/space.h"
#include "tuning/optim/tune_study.h"
#include "tuning/optim/tuner.h"
#include "tuning/sim/scenario_set.h"

namespace scw::cli {
namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
// The first Ctrl-C asks the tune to stop (the search keeps its best and the outputs are written;
// before the search nothing is kept); the handler then steps aside, so a second one quits at once.
extern "C" void OnSigint(int) {
  g_stop = true;
  std::signal(SIGINT, SIG_DFL);
  static const char kMsg[] =
      "\nscw tune: stopping at the next evaluation or phase (Ctrl-C again to quit at once)\n";
  [[maybe_unused]] const auto n = write(2, kMsg, sizeof kMsg - 1);
}

struct TuneOptions {
  std::string space, scenarios, base, algorithm = "sbplx", out, resume, node;
  std::string base_outside = "grow";
  bool force = false;  // --out-dir may name an existing folder
  int max_evals = 240;
  double max_time = 0.0;  // opt-in: a wall-time limit makes the result depend on the machine
  double search_plant_step = -1.0;  // [s], 0: the vehicles' own; < 0: by the objective
  int threads = 0;
  int batch = 1;  // --batch: candidates per objective call (the batched algorithm lhs+B)
  unsigned long long seed = 1;
  std::string progress = "auto";
  bool print_set = false;
  bool check_set = false;       // --check-set: which subsystems the scenario set can see, then exit
  bool no_sensitivity = false;  // skip the parameter sensitivity (after the tune; --check-set)
  bool no_freeze = false;       // keep the dimensions the training cannot see free
  std::string objective = "constrained";
  double lap_budget = tuning::kDefaultLapBudget;   // [s per lap]
  bool free_clean_activations = false;             // drop the activations part of the budget
  double resolution = tuning::kDefaultResolution;  // [s]
  bool no_neighbourhood = false;                   // skip the knife-edge check
  bool robust = false;                             // robust in the small
  int front = 0;                                   // --front N: N points (0: one tune)
  bool max_evals_given = false;                    // --max-evals on the command line
  bool lap_budget_given = false;                   // --lap-budget on the command line
  std::vector<std::string> params_files;           // evaluate
  std::vector<std::string> labels;                 // evaluate
  std::string csv;                                 // evaluate
};

/// "9.6 s" / "0.42 s": wall times as a person reads them.
std::string Seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, s >= 10.0 ? "%.1f s" : "%.2f s", s);
  return buf;
}

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string Cost(double c) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", c);
  return buf;
}

/// A job count shown on the progress line as one phase (nothing when the line is off).
tuning::BatchProgress LineProgress(ProgressLine& line, const std::string& phase,
                                   const std::string& unit) {
  if (!line.enabled()) return {};
  return [&line, phase, unit](int done, int total) {
    line.Update({phase, static_cast<double>(done), static_cast<double>(total), unit, "", -1.0});
  };
}

/// SHA-256 of a file's bytes, as `sha256sum` prints it ("unreadable" if it cannot be read).
std::string FileSha256(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "unreadable";
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return io::Sha256Hex(bytes.str());
}

void CreateFolder(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create the output folder " + dir + ": " + ec.message());
}

/// Refuses, before anything is prepared or written, an --out-dir that would mix two runs: an
/// existing file, or an existing folder that is not empty, unless the run resumes (its log is
/// there) or --force says so.
void CheckRunFolder(const TuneOptions& o) {
  if (o.out.empty()) return;
  std::error_code ec;
  const auto st = fs::status(o.out, ec);
  if (!fs::exists(st)) return;
  if (!fs::is_directory(st))
    throw ConfigError("scw tune", "--out-dir", "'" + o.out + "' exists and is not a folder");
  if (o.resume.empty() && !o.force && !fs::is_empty(o.out, ec))
    throw ConfigError("scw tune", "--out-dir",
                      "the folder '" + o.out +
                          "' already holds files (an earlier run?): choose a new folder, "
                          "continue that run with --resume " +
                          (fs::path(o.out) / "evaluations.csv").string() +
                          ", or overwrite its files with --force");
}

/// --out-dir, or a fresh scw-runs/tune-<date>-<time> (not created yet).
std::string RunFolderName(const std::string& requested) {
  if (!requested.empty()) return requested;
  const std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", std::localtime(&now));
  std::string dir = std::string("scw-runs/tune-") + stamp;
  std::error_code ec;
  for (int k = 2; fs::exists(dir, ec); ++k)
    dir = std::string("scw-runs/tune-") + stamp + "-" + std::to_string(k);
  return dir;
}

params::StabilityParams LoadBase(const std::string& path, std::set<std::string>* present) {
  if (path.empty()) return params::StabilityParams{};
  params::LoadReport rep;
  auto p = params::LoadRosFile<params::StabilityParams>(path, params::kStabilityNodeKey, &rep);
  if (present) *present = rep.present;
  return p;
}

tuning::ScenarioSet LoadSet(const std::string& path) {
  return tuning::ScenarioSet::FromNameOrFile(path);
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

tuning::TuneStudyOptions StudyOptions(const TuneOptions& o, std::set<std::string> present) {
  tuning::TuneStudyOptions so;
  so.algorithm = o.algorithm;
  so.batch = o.batch;
  so.max_evals = o.max_evals;
  so.max_time_s = o.max_time;
  so.seed = o.seed;
  so.threads = o.threads;
  so.base_outside = o.base_outside == "refuse" ? tuning::BaseOutsideSpace::kRefuse
                                               : tuning::BaseOutsideSpace::kGrow;
  so.sensitivity = !o.no_sensitivity;
  so.freeze_unexercised = !o.no_freeze;
  so.search_plant_step = o.search_plant_step;
  so.objective = tuning::ObjectiveKindFromName(o.objective);
  so.budget.lap_s = o.lap_budget;
  so.budget.interventions = !o.free_clean_activations;
  so.resolution = o.resolution;
  so.neighbourhood = !o.no_neighbourhood;
  so.robust = o.robust;
  so.resume_log = o.resume;
  so.stop = &g_stop;
  so.base_file = o.base;
  so.space_file = o.space;
  so.scenarios_file = o.scenarios;
  so.base_keys = std::move(present);
  so.tool_version = SCW_VERSION;
  so.git_revision = SCW_GIT_REVISION;
  so.date_utc = UtcNow;
  return so;
}

/// `scw tune --check-set`: what the scenario set can see around the base point of the space the
/// tune would search (the base outside a range handled by the tune's own rule).
int RunCheckSet(const TuneOptions& o, const tuning::TuneStudy& study) {
  ProgressLine progress(o.progress);
  const std::string md = study.CheckSet(LineProgress(progress, "check", "jobs"));
  progress.Finish();
  std::cout << AlignMarkdownTables(md);
  return kExitOk;
}

/// What the progress line counts in a phase of a tune.
const char* JobUnit(tuning::TunePhase phase) {
  switch (phase) {
    case tuning::TunePhase::kPrepare:
      return "scenarios";
    case tuning::TunePhase::kScreen:
      return "runs";
    case tuning::TunePhase::kOptimise:
    case tuning::TunePhase::kRobust:
      return "evals";
    case tuning::TunePhase::kCompare:
      return "jobs";
    case tuning::TunePhase::kSelect:
    case tuning::TunePhase::kSensitivity:
    case tuning::TunePhase::kNeighbourhood:
      return "runs";
    case tuning::TunePhase::kRevert:
      return "trials";
    case tuning::TunePhase::kExport:
      return "";
  }
  return "";
}

/// Writes a finished tune's outputs into `dir` (the params files, comparison.csv and .md, the
/// plots, sensitivity.csv, the manifest, each atomically); returns the plots' Markdown ("" when
/// they could not be drawn, said on stderr).
std::string WriteRunOutputs(const TuneOptions& o, const tuning::TuneStudy& study,
                            const std::string& dir, const tuning::TuneReport& r,
                            double wall_time_s) {
  const auto path = [&dir](const char* file) { return (fs::path(dir) / file).string(); };
  io::WriteFileAtomic(path(tuning::kTunedParamsFile), r.tuned_file);
  io::WriteFileAtomic(path(tuning::kOverridesParamsFile), r.overrides_file);
  // The plots read comparison.csv and evaluations.csv; comparison.md embeds them.
  io::WriteFileAtomic(path("comparison.csv"), r.comparison_csv);
  std::string plots_md, plot_message;
  if (WriteTunePlots(dir, &plot_message))
    plots_md = TunePlotsMarkdown();
  else
    std::cerr << "  note: no plots (" << plot_message
              << "); the run's other outputs are complete\n";
  if (r.sensitivity_state == tuning::SensitivityState::kDone) {
    io::WriteFileAtomic(path("sensitivity.csv"), r.sensitivity_csv);
  } else {
    std::error_code ec;  // a --force or --resume folder may hold an earlier run's table
    fs::remove(path("sensitivity.csv"), ec);
  }
  io::WriteFileAtomic(path("comparison.md"), r.comparison_markdown + plots_md);
  tuning::TuneRunRecord record;
  for (const auto& a : CommandLine())
    record.command_line += (record.command_line.empty() ? "" : " ") + a;
  if (!o.base.empty()) record.base_sha256 = FileSha256(o.base);
  if (!o.space.empty()) record.space_sha256 = FileSha256(o.space);
  if (!o.scenarios.empty()) record.scenarios_sha256 = FileSha256(o.scenarios);
  record.wall_time_s = wall_time_s;
  for (const char* f : {"evaluations.csv", "evaluations.identity.yaml", tuning::kTunedParamsFile,
                        tuning::kOverridesParamsFile, "comparison.md", "comparison.csv",
                        "sensitivity.csv", kConvergencePlotFile, kComparisonPlotFile})
    if (fs::exists(path(f))) record.files_sha256.emplace_back(f, FileSha256(path(f)));
  io::WriteFileAtomic(path("manifest.yaml"), study.ManifestYaml(r, record));
  return plots_md;
}

/// scw tune's side of a study: the progress line and the messages on stderr, the SIGINT flag
/// during the optimisation, and the run folder's files, each written (atomically) as soon as the
/// study has it; the manifest before the sensitivity and again after it.
class TuneRun : public tuning::TuneObserver {
 public:
  TuneRun(const TuneOptions& o, const tuning::TuneStudy& study, std::string dir,
          std::chrono::steady_clock::time_point t_start)
      : o_(o), study_(study), dir_(std::move(dir)), t_start_(t_start) {
    g_stop = false;
    previous_ = std::signal(SIGINT, OnSigint);
    sigint_ = true;
  }
  ~TuneRun() override { RestoreSigint(); }

  /// TunePlotsMarkdown() when the figures were drawn, else "".
  const std::string& plots_markdown() const { return plots_md_; }
  bool plots() const { return !plots_md_.empty(); }

  void OnPhaseBegin(tuning::TunePhase phase, int total) override {
    switch (phase) {
      case tuning::TunePhase::kPrepare:
        prepare_.emplace(o_.progress);
        OnJobs(phase, 0, total);
        break;
      case tuning::TunePhase::kScreen:
        t_screen_ = std::chrono::steady_clock::now();
        progress_.emplace(o_.progress);
        OnJobs(phase, 0, total);
        break;
      case tuning::TunePhase::kOptimise:
        if (!progress_) progress_.emplace(o_.progress);
        break;
      case tuning::TunePhase::kSensitivity:
        t_sensitivity_ = std::chrono::steady_clock::now();
        OnJobs(phase, 0, total);
        break;
      case tuning::TunePhase::kSelect:
      case tuning::TunePhase::kRevert:
      case tuning::TunePhase::kCompare:
      case tuning::TunePhase::kNeighbourhood:
        t_phase_ = std::chrono::steady_clock::now();
        OnJobs(phase, 0, total);
        break;
      case tuning::TunePhase::kRobust:
        t_phase_ = std::chrono::steady_clock::now();
        break;
      case tuning::TunePhase::kExport:
        break;
    }
  }

  void OnJobs(tuning::TunePhase phase, int done, int total) override {
    // Tests interrupt here (tune_interrupt_test): Ctrl-C before the search.
    if (phase == tuning::TunePhase::kScreen) io::TestFaultPoint("tune-screen", done);
    const bool prepare = phase == tuning::TunePhase::kPrepare;
    (prepare ? *prepare_ : *progress_)
        .Update({tuning::TunePhaseName(phase), static_cast<double>(done),
                 static_cast<double>(total), JobUnit(phase), "", -1.0});
  }

  void OnEvaluation(const tuning::Progress& p) override {
    io::TestFaultPoint("tune-eval", p.evals);  // tests interrupt here (tune_interrupt_test)
    if (!progress_->enabled()) return;
    const double eta = p.evals > 0 ? p.elapsed_s / p.evals * (p.max_evals - p.evals) : -1.0;
    const bool limited = o_.max_time > 0.0 && eta > o_.max_time - p.elapsed_s;
    progress_->Update({p.phase, static_cast<double>(p.evals), static_cast<double>(p.max_evals),
                       "evals", "best cost " + Cost(p.best_cost) + (limited ? " (time limit)" : ""),
                       limited ? std::max(0.0, o_.max_time - p.elapsed_s) : eta});
  }

  void OnPhaseEnd(tuning::TunePhase phase, const tuning::TuneReport& r) override {
    switch (phase) {
      case tuning::TunePhase::kPrepare:
        prepare_.reset();
        std::cerr << "  scenarios prepared in " << Seconds(SecondsSince(t_start_)) << " ("
                  << (r.ranks > 1 ? std::to_string(r.ranks) + " MPI ranks x " : "") << r.threads
                  << " threads)\n";
        break;
      case tuning::TunePhase::kScreen:
        progress_->Finish();
        Screened(r);
        break;
      case tuning::TunePhase::kOptimise:
        Optimised(r);
        break;
      case tuning::TunePhase::kSelect:
        progress_->Finish();
        std::cerr << "  select: " << r.selection.size()
                  << " best points of the search run at the vehicle's step in "
                  << Seconds(SecondsSince(t_phase_)) << "; exporting evaluation " << r.chosen_eval
                  << "\n";
        break;
      case tuning::TunePhase::kSensitivity:
        progress_->Finish();
        SensitivityDone(r);
        break;
      case tuning::TunePhase::kRevert:
        progress_->Finish();
        std::cerr << "  revert: " << r.revert.evaluations << " whole-set evaluations in "
                  << Seconds(SecondsSince(t_phase_)) << "; "
                  << tuning::RevertedItems(r.revert).size() << " reverted, "
                  << r.revert.decisions.size() - tuning::RevertedItems(r.revert).size()
                  << " kept (reverting them changes a run)\n";
        break;
      case tuning::TunePhase::kCompare:
        progress_->Finish();
        break;
      case tuning::TunePhase::kNeighbourhood:
        progress_->Finish();
        std::cerr << "  knife edges: " << r.neighbourhood.neighbours.size() << " neighbours, "
                  << r.neighbourhood.runs << " runs in " << Seconds(SecondsSince(t_phase_)) << "; "
                  << r.neighbourhood.edges.size() << " knife edge(s)\n";
        break;
      case tuning::TunePhase::kRobust:
        progress_->Finish();
        std::cerr << "  robust round " << r.robust_rounds << ": " << r.robust_evaluations
                  << " evaluations so far in " << Seconds(SecondsSince(t_phase_)) << "\n";
        break;
      case tuning::TunePhase::kExport:
        Compared(r);
        break;
    }
  }

 private:
  std::string Path(const char* file) const { return (fs::path(dir_) / file).string(); }

  void RestoreSigint() {
    if (sigint_) std::signal(SIGINT, previous_);
    sigint_ = false;
  }

  void Screened(const tuning::TuneReport& r) const {
    if (r.screening.sets == 0)  // a resume: the frozen set comes from the log's screen file
      std::cerr << "  screen: read from the log's screen file; ";
    else
      std::cerr << "  screen: " << r.screening.sets << " sets x " << r.screening.scenarios.size()
                << " scenarios in " << Seconds(SecondsSince(t_screen_)) << "; ";
    if (r.frozen.empty()) {
      std::cerr << "every parameter changes some training run at an end of its range\n";
      return;
    }
    std::cerr << r.frozen.size() << " of " << study_.space().size()
              << " parameters frozen at the base value (no training run responds to them)\n";
  }

  void Optimised(const tuning::TuneReport& report) {
    const tuning::TuneResult& r = report.optimisation;
    progress_->Finish();
    std::cerr << "  optimisation: " << r.evals << " evaluations (" << r.replayed
              << " replayed), stop: " << r.stop_reason << ", best cost " << Cost(r.best_cost)
              << " at evaluation " << r.best_eval << "\n";
    if (r.stop_reason == "max_time")
      std::cerr << "  note: the --max-time limit of " << o_.max_time << " s stopped the run after "
                << r.evals << " of " << o_.max_evals
                << " evaluations; the result depends on this machine's speed\n";
  }

  /// The outputs: the folder is complete from here on.
  void Compared(const tuning::TuneReport& r) {
    plots_md_ = WriteRunOutputs(o_, study_, dir_, r, SecondsSince(t_start_));
  }

  void SensitivityDone(const tuning::TuneReport& r) const {
    const std::vector<std::string> not_exercised = r.sensitivity.NotExercised();
    std::cerr << "  sensitivity: " << r.sensitivity.sets << " sets x "
              << r.sensitivity.scenarios.size() << " scenarios in "
              << Seconds(SecondsSince(t_sensitivity_)) << "; " << not_exercised.size() << " of "
              << study_.space().size()
              << " parameters not exercised one at a time around the exported point\n";
  }

  const TuneOptions& o_;
  const tuning::TuneStudy& study_;
  const std::string dir_;
  const std::chrono::steady_clock::time_point t_start_;
  std::chrono::steady_clock::time_point t_sensitivity_, t_screen_, t_phase_;
  std::optional<ProgressLine> prepare_;   ///< the preparation's line
  std::optional<ProgressLine> progress_;  ///< from the optimisation on
  bool sigint_ = false;                   ///< OnSigint is installed
  void (*previous_)(int) = SIG_DFL;
  std::string plots_md_;
};

/// One line per scenario group: cost before -> after, the verdict and the aborts.
std::string GroupLine(const std::string& group, const std::vector<tuning::SetEvaluation>& sets,
                      const tuning::SetChange& change) {
  const auto aborts = [](const tuning::SetEvaluation& e) {
    int n = 0;
    for (const auto& m : e.runs) n += m.aborted();
    return n;
  };
  const std::size_t n = sets[0].runs.size();
  return "  " + group + " (" + std::to_string(n) + (n == 1 ? " scenario" : " scenarios") +
         "): cost " + Cost(sets[0].total) + " -> " + Cost(sets[1].total) + ", aborts " +
         std::to_string(aborts(sets[0])) + " -> " + std::to_string(aborts(sets[1])) +
         ", verdict: " + tuning::VerdictName(change.verdict) + " (" +
         std::to_string(change.better) + " better, " + std::to_string(change.worse) + " worse, " +
         std::to_string(change.new_aborts) + " new aborts)\n";
}

/// The clean laps of a group in one line: the largest change a lap and whether the budget holds.
std::string CleanLine(const std::string& group, const tuning::ObjectiveValue& v,
                      const tuning::CleanLapBudget& b) {
  if (v.clean.empty()) return "";
  std::string out = "  clean laps (" + group + "): largest change ";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%+.3f s a lap", v.lap_loss);
  out += std::isfinite(v.lap_loss) ? std::string(buf) : std::string("(a clean lap aborts)");
  out += ", " + std::to_string(v.extra_activations) + " extra activations; ";
  if (v.within_budget())
    return out + "within the budget (" + tuning::LapBudgetText(b.lap_s) + ")\n";
  out += "OVER the budget:";
  for (const auto& c : v.clean)
    if (!c.breach.empty()) out += " " + c.scenario + " " + c.breach + ";";
  out.back() = '\n';
  return out;
}

/// The console's account of a tune (the tables stay in the files): objective, verdicts, the clean
/// laps against the budget, search best against exported, what the file changes and keeps, and the
/// knife edges last (a warning an engineer must not miss).
std::string TuneSummary(const tuning::TuneReport& r, const tuning::TuneStudy& study) {
  const tuning::TuneStudyOptions& so = study.options();
  std::string out = "scw tune: baseline -> tuned (lower cost is better)\n";
  out += "  objective: " + r.objective + "\n";
  if (so.objective == tuning::ObjectiveKind::kConstrained)
    out += "  stability cost (critical training scenarios): " + Cost(r.base_value.stability) +
           " -> " + Cost(r.tuned_value.stability) + "\n";
  out += GroupLine("training", r.training, r.training_change);
  if (!r.held_out.empty()) out += GroupLine("held-out", r.held_out, r.held_out_change);
  out += CleanLine("training", r.tuned_value, so.budget);
  if (!r.held_out.empty()) out += CleanLine("held-out", r.held_out_value, so.budget);
  out += "  search best " + Cost(r.optimisation.best_cost) + " (" +
         tuning::EvaluationName(r.optimisation.best_eval) + "), exported " +
         Cost(r.tuned_value.merit) + " at the vehicle's step (base " + Cost(r.base_value.merit) +
         ")\n";
  if (!r.unexported_gain.empty()) out += "  NOTE: " + r.unexported_gain + "\n";
  out += "  convergence: " + r.convergence + "\n";
  out += "  changed keys: " + std::to_string(r.changed.size()) + " of the " +
         std::to_string(study.space().size()) + " parameters searched\n";
  const auto list = [&out](const std::string& what, const std::vector<std::string>& items) {
    out += "  " + what + ": " +
           (items.empty() ? std::string("none") : std::to_string(items.size())) + "\n";
    for (const auto& item : items) out += "    " + item + "\n";
  };
  if (r.screened) list("frozen at the base value before the search", r.frozen);
  if (r.sensitivity_state == tuning::SensitivityState::kDone) {
    list("reverted to the base value after the search (whole set re-evaluated)", r.reverted);
    std::vector<std::string> kept;
    for (const auto& k : tuning::KeptItems(r.revert))
      if (k.find("NOT reverted") == std::string::npos) kept.push_back(k);
    if (!kept.empty()) list("kept although unexercised one at a time (they act together)", kept);
  } else {
    out +=
        "  reverted after the search: NOT CHECKED (no sensitivity): the file may change "
        "parameters no training run responds to\n";
  }
  if (r.new_findings.empty())
    out += "  params check: no finding the base set does not have\n";
  else
    list("params check findings the base set does not have", r.new_findings);
  if (so.robust && r.neighbourhood_done)
    out += "  robust: " + std::to_string(r.neighbourhood_before_robust.edges.size()) +
           " knife edge(s) before, " + std::to_string(r.neighbourhood.edges.size()) + " after (" +
           std::to_string(r.robust_rounds) + " round(s), " + std::to_string(r.robust_evaluations) +
           " evaluations)\n";
  if (!r.neighbourhood_done)
    out += "  knife edges: not checked\n";
  else if (r.neighbourhood.edges.empty())
    out += "  knife edges: none (" + std::to_string(r.neighbourhood.neighbours.size()) +
           " neighbours on training and held-out)\n";
  return out;
}

/// scw tune --front N's side: the stages' progress, each point's folder as it is exported, then
/// front.csv, front.md and front.png.
class FrontRun : public tuning::FrontObserver {
 public:
  FrontRun(const TuneOptions& o, const tuning::TuneStudy& study, std::string dir,
           std::chrono::steady_clock::time_point t_start)
      : o_(o), study_(study), dir_(std::move(dir)), t_start_(t_start) {}

  void OnStage(int stage, int points, int max_evals) override {
    t_stage_ = std::chrono::steady_clock::now();
    line_.emplace(o_.progress);
    std::cerr << "  front stage " << stage << ": " << points
              << (stage == 1 ? " ends (no loss, no budget)" : " inner points (warm-started)")
              << " in lockstep, " << max_evals << " evaluations each\n";
  }
  void OnRound(int evaluations, int total) override {
    line_->Update(
        {"front", static_cast<double>(evaluations), static_cast<double>(total), "evals", "", -1.0});
  }
  void OnPointBegin(int k, int n) override {
    if (line_) line_->Finish();
    t_point_ = std::chrono::steady_clock::now();
    std::cerr << "  point " << k << " of " << n << ": exporting (sensitivity, revert, comparison, "
              << "knife edges)\n";
  }
  void OnPoint(const tuning::FrontPoint& p) override {
    const fs::path folder = fs::path(dir_) / p.folder;
    const tuning::TuneStudy point_study(
        study_.base(), study_.given_space(), study_.scenarios(),
        tuning::FrontPointOptions(study_.options(), p.budget, p.folder));
    (void)WriteRunOutputs(o_, point_study, folder.string(), p.report, SecondsSince(t_start_));
    const tuning::ObjectiveValue& v = p.report.tuned_value;
    char loss[32];
    std::snprintf(loss, sizeof loss, "%+.3f", v.lap_loss);
    std::cerr << "  point " << p.index << " (" << p.label << "): clean-lap loss "
              << (std::isfinite(v.lap_loss) ? loss : "abort") << " s/lap, stability "
              << Cost(v.stability) << ", " << p.report.changed.size() << " keys changed"
              << (p.adopted_from >= 0 ? " (point " + std::to_string(p.adopted_from) +
                                            "'s set: this point's own export ended worse)"
                                      : std::string())
              << ", in " << Seconds(SecondsSince(t_point_)) << " -> " << folder.string() << "\n";
  }

 private:
  const TuneOptions& o_;
  const tuning::TuneStudy& study_;
  const std::string dir_;
  const std::chrono::steady_clock::time_point t_start_;
  std::chrono::steady_clock::time_point t_stage_, t_point_;
  std::optional<ProgressLine> line_;
};

int RunFrontCli(const TuneOptions& o, const tuning::TuneStudy& study, const std::string& dir,
                std::chrono::steady_clock::time_point t_start) {
  TuneRun run(o, study, dir, t_start);
  FrontRun front(o, study, dir, t_start);
  const tuning::FrontResult r = tuning::RunFront(study, o.front, run, front);
  io::WriteFileAtomic((fs::path(dir) / "front.csv").string(), r.csv);
  std::string plot_message, figure;
  if (WriteFrontPlot(dir, &plot_message))
    figure = std::string(
                 "\n![The front: clean-lap loss against stability cost, training and "
                 "held-out](") +
             kFrontPlotFile + ")\n";
  else
    std::cerr << "  note: no front figure (" << plot_message << ")\n";
  io::WriteFileAtomic((fs::path(dir) / "front.md").string(), r.markdown + figure);
  std::cout << AlignMarkdownTables(r.markdown);
  std::cout << "outputs: " << dir << "/{front.csv, front.md"
            << (figure.empty() ? "" : ", front.png") << ", point_0 ... point_" << o.front - 1
            << "/} in " << Seconds(SecondsSince(t_start)) << "\n";
  std::cout << "runs: " << r.runs_made << " made, " << r.runs_reused
            << " identical ones taken from the run memo instead of run again\n";
  for (const auto& p : r.points)
    if (p.report.neighbourhood_done && tuning::OwnEdges(p.report.neighbourhood) > 0)
      std::cout << "WARNING: point " << p.index << " has "
                << tuning::OwnEdges(p.report.neighbourhood) << " knife edge(s) of its own: see "
                << p.folder << "/comparison.md\n";
  return kExitOk;
}

int RunTune(TuneOptions o) {
  const auto t_start = std::chrono::steady_clock::now();
  const tuning::ScenarioSet set = LoadSet(o.scenarios);
  if (o.print_set) {
    std::cout << set.ToYaml();
    return kExitOk;
  }
  // Every argument problem is found before a folder is created or a scenario prepared.
  if (o.check_set) {
    // --check-set runs no search and writes no folder: options that only a tune reads are an
    // error, not silently ignored.
    std::vector<std::string> unused;
    for (const auto& [given, name] :
         std::vector<std::pair<bool, std::string>>{{o.max_evals_given, "--max-evals"},
                                                   {!o.out.empty(), "--out-dir"},
                                                   {!o.resume.empty(), "--resume"},
                                                   {o.front != 0, "--front"},
                                                   {o.robust, "--robust"}})
      if (given) unused.push_back(name);
    if (!unused.empty()) {
      Problems pr;
      for (const auto& u : unused)
        pr.Add(u, "--check-set runs no search and writes no folder: drop " + u +
                      " (or drop --check-set to tune)");
      throw ConfigError("scw tune", pr.items());
    }
  }
  NoteThreads("scw tune", o.threads);
  if (o.front != 0 && !o.resume.empty())
    throw ConfigError("scw tune", "--front", "a front cannot be resumed: drop --resume");
  if (o.front != 0 && o.objective != "constrained")
    throw ConfigError("scw tune", "--front",
                      "a front is a row of constrained tunes: drop --objective " + o.objective);
  // A front sets each point's clean-lap budget itself: a budget given for it would be ignored.
  if (o.front != 0)
    for (const auto& [given, name] : std::vector<std::pair<bool, std::string>>{
             {o.lap_budget_given, "--lap-budget"},
             {o.free_clean_activations, "--free-clean-activations"}})
      if (given)
        throw ConfigError("scw tune", name,
                          "a front sets each point's clean-lap budget itself (no loss and no "
                          "extra activation at point 0, no budget at the last): drop " +
                              name);
  try {
    tuning::CheckTunerAlgorithm(o.algorithm);
  } catch (const std::invalid_argument& e) {
    throw ConfigError("scw tune", "--algorithm", e.what());
  }
  try {
    tuning::CheckTunerBatch(o.algorithm, o.batch);
  } catch (const std::invalid_argument& e) {
    throw ConfigError("scw tune", "--batch", e.what());
  }
  if (!o.resume.empty() && !std::ifstream(o.resume))
    throw ConfigError(o.resume, "", "cannot open the resume log for reading");
  CheckRunFolder(o);
  // A scenario of the set that cannot be loaded is found now, before a folder is made.
  for (const auto* group : {&set.training, &set.held_out})
    for (const auto& e : *group) (void)tuning::LoadEntry(e, set.base_dir);
  const tuning::ParameterSpace loaded = o.space.empty() ? tuning::ParameterSpace::Default()
                                                        : tuning::ParameterSpace::FromFile(o.space);
  std::set<std::string> present;
  const params::StabilityParams base = LoadBase(o.base, &present);
  tuning::TuneStudyOptions so = StudyOptions(o, std::move(present));
  if (o.check_set) return RunCheckSet(o, tuning::TuneStudy(base, loaded, set, so));
  // The study fits the space to the base (or refuses, exit 2) before the folder is made. A resume
  // writes into the log's folder unless told otherwise.
  const std::string dir = RunFolderName(
      o.out.empty() && !o.resume.empty() ? fs::path(o.resume).parent_path().string() : o.out);
  std::error_code ec;
  const bool folder_existed = fs::exists(dir, ec);
  // Resuming into a folder whose run is complete (its manifest is there) rewrites nothing when
  // the log already holds the whole search.
  so.stop_if_complete = !o.resume.empty() && fs::exists(fs::path(dir) / "manifest.yaml", ec);
  so.run_folder = dir;
  so.evaluation_log = (fs::path(dir) / "evaluations.csv").string();
  const tuning::TuneStudy study(base, loaded, set, std::move(so));
  CreateFolder(dir);
  std::cerr << "scw tune: " << study.space().size() << " parameters, " << set.training.size()
            << " training and " << set.held_out.size() << " held-out scenarios; output in " << dir
            << "\n";
  if (tuning::exec::mpi::Ranks() > 1) {
    const std::string log = (fs::path(dir) / "evaluations.csv").string();
    tuning::exec::mpi::SetTerminationNote("scw tune: " + log +
                                          " holds every finished evaluation; continue the run with "
                                          "the same options and --resume " +
                                          log + " (with or without mpirun)\n");
  }
  for (const auto& g : study.grown()) std::cerr << "  note: " << g << "\n";
  if (o.front != 0) return RunFrontCli(o, study, dir, t_start);

  TuneRun run(o, study, dir, t_start);
  tuning::TuneReport r;
  try {
    r = study.Run(run);
  } catch (const tuning::TuneAlreadyComplete& e) {
    std::cerr << "scw tune: " << e.what() << "\n";
    return kExitOk;
  } catch (const tuning::TuneInterrupted& e) {
    // Nothing was evaluated that a resume could use: a folder this run made and left empty goes.
    std::error_code rm;
    const bool empty = fs::is_empty(dir, rm);
    if (!folder_existed && empty) fs::remove(dir, rm);
    std::cerr << "scw tune: interrupted " << e.what() << ": nothing was written"
              << (!folder_existed && empty ? " (the empty folder " + dir + " was removed)" : "")
              << "\n";
    return kExitInterrupted;
  }
  const bool sensitivity = r.sensitivity_state == tuning::SensitivityState::kDone;
  std::cout << TuneSummary(r, study);
  std::cout << "outputs: " << dir << "/{evaluations.csv, evaluations.identity.yaml, "
            << "stability_tuned.yaml, stability_overrides.yaml, comparison.md, comparison.csv, "
            << (sensitivity ? "sensitivity.csv, " : "")
            << (run.plots() ? "convergence.png, comparison.png, " : "") << "manifest.yaml}\n"
            << "the tables, per-scenario verdicts and the sensitivity are in " << dir
            << "/comparison.md: read its held-out rows before a car run\n";
  if (r.neighbourhood_done) std::cout << tuning::NeighbourhoodWarning(r.neighbourhood);
  const std::string& stop = r.optimisation.stop_reason;
  // Ctrl-C: the outputs of the best set so far are written; exit as an interrupted program does.
  return stop == "interrupted" ? kExitInterrupted : kExitOk;
}

/// The column names of `scw evaluate`: --labels, else the file names (the paths as given where
/// two files share a name). Throws ConfigError for labels that cannot name the sets.
std::vector<std::string> EvaluateLabels(const TuneOptions& o) {
  const std::size_t n = std::max<std::size_t>(1, o.params_files.size());
  std::vector<std::string> labels = o.labels;
  if (labels.empty()) {
    if (o.params_files.empty()) return {"built-in"};
    for (const auto& f : o.params_files) labels.push_back(fs::path(f).filename().string());
    const auto distinct = [](const std::vector<std::string>& v) {
      for (std::size_t i = 0; i < v.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
          if (v[i] == v[j]) return false;
      return true;
    };
    if (distinct(labels)) return labels;
    if (distinct(o.params_files)) return o.params_files;
    throw ConfigError("scw evaluate", "PARAMS",
                      "a file is given twice: name the sets with --labels A,B,...");
  }
  Problems problems;
  if (labels.size() != n)
    problems.Add("--labels", std::to_string(labels.size()) + " label(s) for " + std::to_string(n) +
                                 " parameter set(s): give one label per PARAMS file, in order" +
                                 (o.params_files.empty() ? " (none: the built-in set)" : ""));
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i].empty() || labels[i].find_first_of("|\n\r") != std::string::npos)
      problems.Add("--labels", "'" + labels[i] +
                                   "' is not a usable label (empty, or with | or a "
                                   "line break)");
    for (std::size_t j = 0; j < i; ++j)
      if (labels[i] == labels[j]) problems.Add("--labels", "'" + labels[i] + "' is given twice");
  }
  if (!problems.empty()) throw ConfigError("scw evaluate", problems.items());
  return labels;
}

int RunEvaluate(const TuneOptions& o) {
  const std::vector<std::string> labels = EvaluateLabels(o);
  NoteThreads("scw evaluate", o.threads);
  const tuning::ScenarioSet set = LoadSet(o.scenarios);
  std::vector<params::StabilityParams> sets;
  for (const auto& f : o.params_files) sets.push_back(LoadBase(f, nullptr));
  if (sets.empty()) sets.push_back(params::StabilityParams{});
  // One progress phase: each scenario's preparation and every run are a job.
  ProgressLine progress(o.progress);
  const tuning::SetsEvaluation table = tuning::EvaluateSets(
      set, sets, labels, o.threads, LineProgress(progress, "evaluate", "jobs"));
  progress.Finish();
  std::cout << AlignMarkdownTables(table.markdown);
  if (!o.csv.empty()) io::WriteFileAtomic(o.csv, table.csv);
  return kExitOk;
}

constexpr const char* kThreadsHelp =
    "Worker threads per process (0: all cores; under mpirun with more than one rank: 1 per "
    "rank)";

void AddTune(CLI::App& app) {
  auto o = std::make_shared<TuneOptions>();
  auto* cmd = app.add_subcommand(
      "tune",
      "Tune the stability parameters on the scenario set (no arguments: the built-in "
      "space and scenarios, about three minutes on 2 cores) and export the car's params files");
  cmd->add_option("--space", o->space, "Search space file (params/spaces/*.yaml)");
  cmd->add_option("--scenarios", o->scenarios,
                  "Scenario set: a built-in name (default; robust: Monte-Carlo draws of the "
                  "situations and of the plant values we do not know) or a file "
                  "(params/scenarios/*.yaml)");
  cmd->add_option("--base", o->base, "Starting stability params file (car's ROS 2 layout)");
  cmd->add_option("--base-outside", o->base_outside,
                  "A base value outside a space range: grow the range to include it (default), "
                  "or refuse (exit 2, naming the key)")
      ->check(CLI::IsMember({"grow", "refuse"}));
  cmd->add_option("--algorithm", o->algorithm,
                  "Search algorithm: NLopt's sbplx (Subplex from the base set: the default, "
                  "chosen by experiments/tuning_benchmark.py, docs/tuning-benchmark.md), crs2, "
                  "isres, esch, direct_l, mlsl, neldermead, bobyqa, cobyla; auglag (NLopt's "
                  "augmented Lagrangian around Subplex: the clean-lap budget as a constraint "
                  "instead of the exact penalty, docs/tuned-files.md); lhs (a "
                  "Latin-hypercube design, batched: see --batch); or A+B (global A on 60 % of "
                  "the budget, then local B from its best point). --seed matters only to the "
                  "stochastic ones (crs2, isres, esch, lhs)")
      ->capture_default_str();
  WholeNumberIn(cmd->add_option("--batch", o->batch,
                                "Candidates evaluated at once, with --algorithm lhs+sbplx (the "
                                "design in batches, then that many Subplex searches in lockstep); "
                                "helps when there are more workers than training scenarios, e.g. "
                                "under mpirun. The NLopt algorithms take 1 candidate at a time"),
                1, 1024)
      ->capture_default_str();
  WholeNumberIn(cmd->add_option("--max-evals", o->max_evals,
                                "Evaluation budget (the default run stops here)"),
                1, 1000000)
      ->capture_default_str();
  NumberIn(cmd->add_option("--max-time", o->max_time,
                           "Wall-time limit [s], opt-in (0: none; with a limit the result depends "
                           "on the machine's speed and the final message says when it stopped "
                           "the run)"),
           0.0, 1e7)
      ->capture_default_str();
  NumberIn(cmd->add_option("--search-plant-step", o->search_plant_step,
                           "Plant step [s] the optimiser evaluates candidates with, used only if "
                           "the base set gives the same outcomes there as at each vehicle's own "
                           "step on every training scenario (0: the vehicles' own step; default: "
                           "0 for the constrained objective, 0.002 for sum). The comparison, "
                           "sensitivity and exported files always use the vehicle's step; with "
                           "a coarser search step the best points are re-run there and the best "
                           "within the budget is exported (docs/plant-step.md)"),
           0.0, 0.005);
  WholeNumberIn(cmd->add_option("--threads", o->threads, kThreadsHelp), 0, 1024)
      ->capture_default_str();
  SeedOption(cmd->add_option("--seed", o->seed, "Optimizer seed (a whole number >= 0)"))
      ->capture_default_str();
  cmd->add_option("--out-dir", o->out, "Output folder (default: a fresh scw-runs/tune-<time>)");
  AddHiddenAlias(cmd, "--out", o->out);
  cmd->add_flag("--force", o->force,
                "Write into an --out-dir that already holds files (default: refuse, exit 2)");
  cmd->add_option("--resume", o->resume,
                  "Continue a run from its evaluations.csv (same options; a larger --max-evals "
                  "extends a finished sbplx run exactly; --out-dir defaults to the log's folder)");
  AddProgressOption(cmd, &o->progress);
  cmd->add_flag("--print-scenarios", o->print_set, "Print the scenario set as YAML and exit");
  cmd->add_flag("--check-set", o->check_set,
                "Before tuning: run the base set on every scenario as it is and with each "
                "subsystem off, print which subsystem acts in and decides which scenario, warn "
                "about subsystems the training set cannot see, show the parameter sensitivity "
                "around the base set (unless --no-sensitivity), and exit");
  cmd->add_flag("--no-sensitivity", o->no_sensitivity,
                "Skip the parameter sensitivity that by default follows the optimisation (and "
                "--check-set): each parameter of the space moved by +/- one resolution step and "
                "+/- 10 %, one batch on the training scenarios, around the best point; every "
                "parameter it finds not exercised is reverted to the base value before the "
                "export. Without it nothing is checked, and the files say so");
  cmd->add_option("--objective", o->objective,
                  "What the search minimises: constrained (default: the stability cost of the "
                  "critical scenarios, subject to the clean-lap budget) or sum (the weighted sum "
                  "of every scenario's cost, the earlier tunes' objective)")
      ->check(CLI::IsMember({"constrained", "sum"}))
      ->capture_default_str();
  NumberIn(cmd->add_option("--lap-budget", o->lap_budget,
                           "Clean-lap budget [s per lap]: no clean training lap may be slower "
                           "than with the base set by more than this (constrained objective)"),
           0.0, 1e6)
      ->capture_default_str();
  cmd->add_flag("--free-clean-activations", o->free_clean_activations,
                "Drop the other half of the budget: by default no subsystem may act more often "
                "on a clean lap than with the base set");
  NumberIn(cmd->add_option("--resolution", o->resolution,
                           "Smallest change of a scenario's cost [s, per lap for the lap time] "
                           "the comparison calls a change; an abort is always a change"),
           1e-6, 1e6)
      ->capture_default_str();
  cmd->add_flag("--no-neighbourhood", o->no_neighbourhood,
                "Skip the knife-edge check of the exported set (each changed key +/- 10 % of its "
                "range and the plant's unknowns at their bounds, on training and held-out)");
  cmd->add_flag("--robust", o->robust,
                "Robust in the small: the training knife edges the check finds join the cost and "
                "the search continues from the exported set (up to 2 rounds of max-evals/2 "
                "evaluations at the vehicle's step), then the check runs again");
  WholeNumberIn(cmd->add_option("--front", o->front,
                                "The trade-off as N tuned sets, from the base set's lap time (no "
                                "loss) to no clean-lap budget (whatever it takes to survive), each "
                                "a constrained tune (the ends --max-evals evaluations from the "
                                "base set, the inner points twice that from the best set so far), "
                                "in lockstep; "
                                "writes front.csv, front.md, front.png and point_<k>/ with each "
                                "point's params files (docs/tuned-files.md#front)"),
                2, 20);
  cmd->add_flag("--no-freeze", o->no_freeze,
                "Do not screen and freeze before the search: by default each parameter is moved "
                "alone to both ends of its range on the training scenarios (one batch at the "
                "search step), and one that changes no run is kept at the base value");
  cmd->footer(
      "Under MPI (mpirun -np N scw tune ...): rank 0 runs the tune and writes every file, all\n"
      "ranks compute runs; the outputs equal a plain run's for any N (docs/scaling.md).");
  cmd->callback([o, cmd] {
    o->max_evals_given = cmd->count("--max-evals") > 0;
    o->lap_budget_given = cmd->count("--lap-budget") > 0;
    SetExitCode(RunTune(*o));
  });

  auto e = std::make_shared<TuneOptions>();
  auto* ev = app.add_subcommand(
      "evaluate",
      "Evaluate stability params files side by side on the training and held-out "
      "scenarios");
  ev->add_option("PARAMS", e->params_files,
                 "Stability params files (car's ROS 2 layout; none: the built-in set)");
  ev->add_option("--labels", e->labels,
                 "Names of the sets in the table, one per PARAMS file in order (comma-separated; "
                 "default: the file names)")
      ->delimiter(',');
  ev->add_option("--scenarios", e->scenarios,
                 "Scenario set: a built-in name (default, robust) or a file (default: the "
                 "built-in default set)");
  WholeNumberIn(ev->add_option("--threads", e->threads, kThreadsHelp), 0, 1024);
  ev->add_option("-o,--output", e->csv, "Also write the table as CSV");
  AddHiddenAlias(ev, "--csv", e->csv);
  AddProgressOption(ev, &e->progress);
  ev->callback([e] { SetExitCode(RunEvaluate(*e)); });
}

const CommandRegistrar kRegistrar(25, &AddTune);

}  // namespace
}  // namespace scw::cli
