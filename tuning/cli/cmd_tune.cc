// scw tune — the main job: tune the stability parameters against the scenario set, compare the
// tuned set with the starting set on training and held-out scenarios, export the car's params
// files. scw evaluate — compare given parameter files side by side.
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
#include <sstream>

#include <nlopt.hpp>

#include "params/io/atomic_file.h"
#include "params/io/load.h"
#include "params/io/ros2_check.h"
#include "params/io/sha256.h"
#include "params/io/write.h"
#include "tuning/cli/command.h"
#include "tuning/cli/console.h"
#include "tuning/cli/options.h"
#include "tuning/cli/progress.h"
#include "tuning/optim/comparison.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/plots/tune_plots.h"
#include "tuning/optim/sensitivity.h"
#include "tuning/optim/set_check.h"
#include "tuning/optim/space.h"
#include "tuning/optim/tuner.h"
#include "tuning/sim/parallel/mpi_backend.h"
#include "tuning/sim/scenario_set.h"

namespace scw::cli {
namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void OnSigint(int) { g_stop = true; }

struct TuneOptions {
  std::string space, scenarios, base, algorithm = "crs2+sbplx", out, resume, node;
  std::string base_outside = "grow";
  bool force = false;  // --out-dir may name an existing folder
  int max_evals = 180;
  double max_time = 0.0;  // opt-in: a wall-time limit makes the result depend on the machine
  int threads = 0;
  int batch = 1;  // --batch: candidates per objective call (the batched algorithm lhs+B)
  unsigned long long seed = 1;
  std::string progress = "auto";
  bool print_set = false;
  bool check_set = false;       // --check-set: which subsystems the scenario set can see, then exit
  bool no_sensitivity = false;  // skip the parameter sensitivity (after the tune; --check-set)
  std::vector<std::string> params_files;  // evaluate
  std::vector<std::string> labels;        // evaluate
  std::string csv;                        // evaluate
};

/// "9.6 s" / "0.42 s": wall times as a person reads them.
std::string Seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, s >= 10.0 ? "%.1f s" : "%.2f s", s);
  return buf;
}

/// ", batch 4" after the algorithm when candidates were evaluated in batches ("" for 1).
std::string BatchNote(int batch) { return batch > 1 ? ", batch " + std::to_string(batch) : ""; }

std::string Cost(double c) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", c);
  return buf;
}

/// Reports the runs of the final comparison (or of `scw evaluate`) as one phase over several
/// batches: `offset` runs of earlier batches are done.
tuning::BatchProgress PhaseProgress(ProgressLine& line, const std::string& phase, int offset,
                                    int total, const std::string& unit) {
  if (!line.enabled()) return {};
  return [&line, phase, offset, total, unit](int done, int) {
    line.Update(
        {phase, static_cast<double>(offset + done), static_cast<double>(total), unit, "", -1.0});
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

std::string FreshRunFolder(const std::string& requested) {
  if (!requested.empty()) {
    CreateFolder(requested);
    return requested;
  }
  const std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", std::localtime(&now));
  std::string dir = std::string("scw-runs/tune-") + stamp;
  std::error_code ec;
  for (int k = 2; fs::exists(dir, ec); ++k)
    dir = std::string("scw-runs/tune-") + stamp + "-" + std::to_string(k);
  CreateFolder(dir);
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
  return path.empty() ? tuning::ScenarioSet::Default() : tuning::ScenarioSet::FromFile(path);
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
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

/// `scw tune --check-set`: the base set on every scenario, as it is and with each subsystem off;
/// then (unless --no-sensitivity) the parameter sensitivity around the base point on the training
/// scenarios.
int RunCheckSet(const TuneOptions& o, const tuning::ScenarioSet& set,
                const params::StabilityParams& base, const tuning::ParameterSpace& loaded) {
  ProgressLine progress(o.progress);
  const int n_scenarios = static_cast<int>(set.training.size() + set.held_out.size());
  // The base point of the space the tune would search, with the tune's own rule for a base
  // outside a range (grown by default, so that the centre is the base set bit for bit, or refused
  // with --base-outside refuse, exit 2 naming the key, as scw tune does).
  const tuning::ParameterSpace space =
      loaded.WithBase(base, o.base_outside == "refuse" ? tuning::BaseOutsideSpace::kRefuse
                                                       : tuning::BaseOutsideSpace::kGrow);
  const std::vector<double> u0 = space.Encode(base);
  tuning::SensitivityPlan plan;
  if (!o.no_sensitivity) plan = tuning::PlanSensitivity(space, u0, base);
  const int total = n_scenarios * 6 +  // preparation + 5 runs each
                    static_cast<int>(plan.sets.size() * set.training.size());
  progress.Update({"check", 0, static_cast<double>(total), "jobs", "", -1.0});
  int done = 0;
  std::string sensitivity;
  std::string md =
      "# scw tune --check-set\n\nbase = " +
      (o.base.empty() ? std::string("the car's shipped parameters (built-in)") : o.base) +
      "; activations ESC/CS/ABS/TC with the base set; a subsystem decides a scenario when "
      "switching it off turns a completed run into an abort (or the reverse) or changes the "
      "scenario's cost by 5 % or more\n\n";
  for (const auto* group : {&set.training, &set.held_out}) {
    if (group->empty()) continue;
    const int n = static_cast<int>(group->size());
    const auto ev =
        tuning::BatchEvaluator::FromEntries(*group, set.base_dir, set.cost, o.threads,
                                            PhaseProgress(progress, "check", done, total, "jobs"));
    done += n;
    const auto check =
        tuning::CheckSet(ev, base, 0.05, PhaseProgress(progress, "check", done, total, "jobs"));
    done += 5 * n;
    const bool training = group == &set.training;
    md += tuning::SetCheckMarkdown(training ? "Training scenarios" : "Held-out scenarios", check,
                                   training);
    md += "\n";
    if (training && !o.no_sensitivity) {
      sensitivity = tuning::SensitivityMarkdown(
          tuning::EvaluateSensitivity(ev, space, plan,
                                      PhaseProgress(progress, "check", done, total, "jobs")),
          "the base set");
      done += static_cast<int>(plan.sets.size()) * n;
    }
  }
  md += sensitivity;
  progress.Finish();
  std::cout << AlignMarkdownTables(md);
  return kExitOk;
}

int RunTune(const TuneOptions& o) {
  const auto t_start = std::chrono::steady_clock::now();
  const tuning::ScenarioSet set = LoadSet(o.scenarios);
  if (o.print_set) {
    std::cout << set.ToYaml();
    return kExitOk;
  }
  // Every argument problem is found before a folder is created or a scenario prepared.
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
  const tuning::ParameterSpace loaded = o.space.empty() ? tuning::ParameterSpace::Default()
                                                        : tuning::ParameterSpace::FromFile(o.space);
  std::set<std::string> present;
  const params::StabilityParams base = LoadBase(o.base, &present);
  if (o.check_set) return RunCheckSet(o, set, base, loaded);
  // The base must be exactly representable (evaluation 0 = the base set, keys the tuner leaves
  // alone stay the base values): grow ranges that do not contain it, or refuse.
  std::vector<std::string> grown;
  const tuning::ParameterSpace space =
      loaded.WithBase(base,
                      o.base_outside == "refuse" ? tuning::BaseOutsideSpace::kRefuse
                                                 : tuning::BaseOutsideSpace::kGrow,
                      &grown);
  const auto u0 = space.Encode(base);
  if (!params::DifferingKeys(space.Decode(u0, base, nullptr), base).empty())
    throw std::runtime_error("internal error: the start point does not decode to the base set");
  const std::string dir = FreshRunFolder(o.out);
  std::cerr << "scw tune: " << space.size() << " parameters, " << set.training.size()
            << " training and " << set.held_out.size() << " held-out scenarios; output in " << dir
            << "\n";
  if (tuning::mpi::Ranks() > 1) {
    const std::string log = (fs::path(dir) / "evaluations.csv").string();
    tuning::mpi::SetTerminationNote("scw tune: " + log +
                                    " holds every finished evaluation; continue the run with "
                                    "the same options and --resume " +
                                    log + " (with or without mpirun)\n");
  }
  for (const auto& g : grown) std::cerr << "  note: " << g << "\n";

  const auto training = [&] {
    ProgressLine prepare(o.progress);
    const int n = static_cast<int>(set.training.size());
    prepare.Update({"prepare", 0, static_cast<double>(n), "scenarios", "", -1.0});
    return tuning::BatchEvaluator::FromEntries(
        set.training, set.base_dir, set.cost, o.threads,
        PhaseProgress(prepare, "prepare", 0, n, "scenarios"));
  }();
  std::cerr
      << "  scenarios prepared in "
      << Seconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count())
      << " ("
      << (tuning::mpi::Ranks() > 1 ? std::to_string(tuning::mpi::Ranks()) + " MPI ranks x " : "")
      << training.threads() << " threads)\n";

  // Objective: decode, reject invalid sets with a graded penalty, evaluate the training set.
  std::vector<std::string> extra;
  for (const auto& e : space.entries()) extra.push_back("x:" + e.Label());
  for (const auto& sc : training.scenarios()) {
    extra.push_back("cost:" + sc.spec.name);
    extra.push_back("status:" + sc.spec.name);
    extra.push_back("lap:" + sc.spec.name);
  }
  const double invalid_cost =
      (set.cost.abort_base + set.cost.abort_progress_weight + set.cost.lap_time_cap) *
      static_cast<double>(std::max<std::size_t>(1, set.training.size()));
  // Several points at once (--batch): the valid sets run as one batch of (set x scenario) jobs.
  auto batch_objective =
      [&](const std::vector<std::vector<double>>& points) -> std::vector<tuning::Evaluation> {
    std::vector<tuning::Evaluation> evs(points.size());
    std::vector<params::StabilityParams> valid_sets;
    std::vector<std::size_t> valid_at;
    for (std::size_t i = 0; i < points.size(); ++i) {
      for (double x : space.Arguments(points[i])) evs[i].columns.push_back(params::FormatDouble(x));
      Problems pr;
      params::StabilityParams p = space.Decode(points[i], base, &pr);
      if (!pr.empty()) {
        evs[i].cost = invalid_cost;
        evs[i].status = "infeasible: " + pr.items()[0].path;
        continue;
      }
      valid_sets.push_back(std::move(p));
      valid_at.push_back(i);
    }
    if (valid_sets.empty()) return evs;
    const std::vector<tuning::SetEvaluation> results = training.Evaluate(valid_sets);
    for (std::size_t v = 0; v < valid_at.size(); ++v) {
      const tuning::SetEvaluation& r = results[v];
      tuning::Evaluation& ev = evs[valid_at[v]];
      ev.cost = r.total;
      int aborts = 0;
      for (std::size_t k = 0; k < r.runs.size(); ++k) {
        aborts += r.runs[k].aborted();
        ev.columns.push_back(params::FormatDouble(r.costs[k].total));
        ev.columns.push_back(tuning::RunStatusName(r.runs[k].status));
        const double lap = r.runs[k].MeanLapTime();
        ev.columns.push_back(std::isnan(lap) ? "nan" : params::FormatDouble(lap));
      }
      ev.status = aborts ? std::to_string(aborts) + " abort(s)" : "ok";
    }
    return evs;
  };
  // One point: a batch of one (the evaluator runs one set exactly as it runs a batch).
  auto objective = [&](const std::vector<double>& u) { return batch_objective({u}).front(); };

  tuning::TunerOptions to;
  to.algorithm = o.algorithm;
  to.max_evals = o.max_evals;
  to.max_time_s = o.max_time;
  to.seed = o.seed;
  to.batch = o.batch;
  to.log_path = (fs::path(dir) / "evaluations.csv").string();
  to.resume_path = o.resume;
  to.log_extra_header = extra;
  for (const auto& e : space.entries()) to.dimension_names.push_back("u:" + e.Label());
  to.stop = &g_stop;
  to.failure_cost = invalid_cost;
  ProgressLine progress(o.progress);
  if (progress.enabled())
    to.on_progress = [&](const tuning::Progress& p) {
      const double eta = p.evals > 0 ? p.elapsed_s / p.evals * (p.max_evals - p.evals) : -1.0;
      const bool limited = o.max_time > 0.0 && eta > o.max_time - p.elapsed_s;
      progress.Update({p.phase, static_cast<double>(p.evals), static_cast<double>(p.max_evals),
                       "evals", "best cost " + Cost(p.best_cost) + (limited ? " (time limit)" : ""),
                       limited ? std::max(0.0, o.max_time - p.elapsed_s) : eta});
    };
  g_stop = false;
  auto previous = std::signal(SIGINT, OnSigint);
  tuning::TuneResult r;
  try {
    r = tuning::Tune(u0, objective, batch_objective, to);
  } catch (...) {
    std::signal(SIGINT, previous);
    throw;
  }
  std::signal(SIGINT, previous);
  progress.Finish();
  std::cerr << "  optimisation: " << r.evals << " evaluations (" << r.replayed
            << " replayed), stop: " << r.stop_reason << ", best cost " << Cost(r.best_cost)
            << " at evaluation " << r.best_eval << "\n";
  if (r.stop_reason == "max_time")
    std::cerr << "  note: the --max-time limit of " << o.max_time << " s stopped the run after "
              << r.evals << " of " << o.max_evals
              << " evaluations; the result depends on this machine's speed\n";

  // Result: baseline (the starting set itself) vs tuned, on training and held-out scenarios.
  // The decoded set is already quantised to the schema resolutions: it is exactly what is exported.
  Problems pr;
  const params::StabilityParams tuned = space.Decode(r.best_u, base, &pr);
  if (!pr.empty())
    throw std::runtime_error("internal error: the best point decodes to an invalid set");
  const std::set<std::string> changed = params::DifferingKeys(tuned, base);
  const std::vector<std::string> labels = {"baseline", "tuned"};
  const std::vector<params::StabilityParams> both = {base, tuned};
  const int n_compare =
      static_cast<int>(both.size() * set.training.size() + (both.size() + 1) * set.held_out.size());
  progress.Update({"compare", 0, static_cast<double>(n_compare), "jobs", "", -1.0});
  const auto train_res =
      training.Evaluate(both, PhaseProgress(progress, "compare", 0, n_compare, "jobs"));
  std::string md =
      "# scw tune: comparison\n\nbaseline = " +
      (o.base.empty() ? std::string("the car's shipped parameters (built-in)") : o.base) +
      "; tuned = best of " + std::to_string(r.evals) + " evaluations (" + o.algorithm +
      BatchNote(o.batch) + ", seed " + std::to_string(o.seed) + "), " +
      std::to_string(changed.size()) + " key(s) changed\n\n";
  md += tuning::ComparisonMarkdown("Training scenarios", training, labels, train_res);
  std::string csv = tuning::ComparisonCsv("training", training, labels, train_res, true);
  std::vector<tuning::SetEvaluation> held_res;
  const tuning::SetChange train_change = tuning::CompareSets(training, train_res[0], train_res[1]);
  md += "\n" + tuning::SetChangeMarkdown("Training", train_change);
  tuning::SetChange held_change;
  if (!set.held_out.empty()) {
    const int n_train = static_cast<int>(both.size() * set.training.size());
    const auto held = tuning::BatchEvaluator::FromEntries(
        set.held_out, set.base_dir, set.cost, o.threads,
        PhaseProgress(progress, "compare", n_train, n_compare, "jobs"));
    held_res = held.Evaluate(
        both, PhaseProgress(progress, "compare", n_train + static_cast<int>(set.held_out.size()),
                            n_compare, "jobs"));
    md += tuning::ComparisonMarkdown("Held-out scenarios (not used for tuning)", held, labels,
                                     held_res);
    csv += tuning::ComparisonCsv("held_out", held, labels, held_res, false);
    held_change = tuning::CompareSets(held, held_res[0], held_res[1]);
    md += "\n" + tuning::SetChangeMarkdown("Held-out", held_change);
  }
  progress.Finish();
  // Outputs (each atomically), with a provenance header.
  const std::string full = (fs::path(dir) / "stability_tuned.yaml").string();
  const std::string over = (fs::path(dir) / "stability_overrides.yaml").string();
  tuning::TuneProvenance prov;
  prov.tool_version = SCW_VERSION;
  prov.git_revision = SCW_GIT_REVISION;
  prov.run_folder = dir;
  prov.date_utc = UtcNow();
  prov.base = o.base.empty() ? std::string("built-in (the car's shipped parameters)") : o.base;
  prov.algorithm = o.algorithm + BatchNote(o.batch);
  prov.seed = o.seed;
  prov.evaluations = r.evals;
  prov.stop_reason = r.stop_reason;
  prov.space = o.space.empty() ? std::string("built-in default") : o.space;
  prov.dimensions = space.size();
  for (const auto& m : loaded.BaseMismatches(base))
    prov.grown.push_back(m.label + ": [" + params::FormatNumber(m.lo) + ", " +
                         params::FormatNumber(m.hi) + "] -> [" + params::FormatNumber(m.grown_lo) +
                         ", " + params::FormatNumber(m.grown_hi) + "]");
  prov.training_scenarios = static_cast<int>(set.training.size());
  prov.training_before = train_res[0].total;
  prov.training_after = train_res[1].total;
  if (!held_res.empty()) {
    prov.held_out_scenarios = static_cast<int>(set.held_out.size());
    prov.held_out_before = held_res[0].total;
    prov.held_out_after = held_res[1].total;
  }
  prov.changed.assign(changed.begin(), changed.end());
  const std::string full_text = params::ToRosYaml(tuned, params::kStabilityNodeKey, present,
                                                  tuning::TunedFileHeader(prov, false));
  const std::string over_text = params::ToRosOverrides(tuned, base, params::kStabilityNodeKey,
                                                       tuning::TunedFileHeader(prov, true));
  CheckExport(full_text, true, full);
  CheckExport(over_text, false, over);
  io::WriteFileAtomic(full, full_text);
  io::WriteFileAtomic(over, over_text);
  // The plots read comparison.csv and evaluations.csv; comparison.md embeds them.
  io::WriteFileAtomic((fs::path(dir) / "comparison.csv").string(), csv);
  std::string plot_message;
  const bool plots = tuning::WriteTunePlots(dir, &plot_message);
  if (!plots)
    std::cerr << "  note: no plots (" << plot_message
              << "); the run's other outputs are complete\n";
  const std::string plots_md = plots ? tuning::TunePlotsMarkdown() : std::string();
  const std::string md_path = (fs::path(dir) / "comparison.md").string();
  io::WriteFileAtomic(md_path, md + plots_md);

  // The parameter sensitivity around the tuned point comes last: the manifest is written before
  // it (the folder is then complete; a run stopped during the phase keeps it so) and again after
  // it, with the section in comparison.md.
  std::string sensitivity = "pending";
  if (o.no_sensitivity)
    sensitivity = "skipped (--no-sensitivity)";
  else if (r.stop_reason == "interrupted" || r.stop_reason == "resume_mismatch")
    sensitivity = "skipped (" + r.stop_reason + ")";
  int sensitivity_sets = 0;
  std::vector<std::string> not_exercised;
  {
    std::error_code ec;  // a --force or --resume folder may hold an earlier run's table
    fs::remove(fs::path(dir) / "sensitivity.csv", ec);
  }
  std::string cmdline;
  for (const auto& a : CommandLine()) cmdline += (cmdline.empty() ? "" : " ") + a;
  const auto write_manifest = [&] {
    std::ostringstream man;
    man << "scw_version: " << SCW_VERSION << "\n"
        << "git_revision: " << SCW_GIT_REVISION << "\n"
        << "date_utc: " << prov.date_utc << "\n"
        << "nlopt_version: " << nlopt::version_major() << "." << nlopt::version_minor() << "."
        << nlopt::version_bugfix() << "\n"
        << "command_line: " << params::QuoteString(cmdline) << "\n"
        << "base: " << params::QuoteString(o.base.empty() ? "built-in" : o.base) << "\n"
        << "base_hash: "
        << (o.base.empty() ? io::Sha256Hex(params::ToRosYaml(base, params::kStabilityNodeKey))
                           : FileSha256(o.base))
        << "\n"
        << "space: " << params::QuoteString(o.space.empty() ? "built-in default" : o.space) << "\n"
        << "space_hash: " << (o.space.empty() ? io::Sha256Hex(space.ToYaml()) : FileSha256(o.space))
        << "\n"
        << "base_outside_space: " << o.base_outside << "\n"
        << "grown_ranges: " << grown.size() << "\n"
        << "scenarios: "
        << params::QuoteString(o.scenarios.empty() ? "built-in default" : o.scenarios) << "\n"
        << "scenarios_hash: "
        << (o.scenarios.empty() ? io::Sha256Hex(set.ToYaml()) : FileSha256(o.scenarios)) << "\n"
        << "algorithm: " << o.algorithm << "\n"
        << "batch: " << o.batch << "\n"
        << "seed: " << o.seed << "\n"
        << "max_evals: " << o.max_evals << "\n"
        << "max_time_s: " << params::FormatDouble(o.max_time) << "\n"
        << "threads: " << training.threads() << "\n"
        << "ranks: " << tuning::mpi::Ranks() << "\n"
        << "threads_per_rank: " << training.threads() << "\n"
        << "evaluations: " << r.evals << "\n"
        << "replayed_evaluations: " << r.replayed << "\n"
        << "stop_reason: " << r.stop_reason << "\n"
        << "start_cost: " << params::FormatDouble(r.start_cost) << "\n"
        << "best_cost: " << params::FormatDouble(r.best_cost) << "\n"
        << "best_evaluation: " << r.best_eval << "\n"
        << "baseline_cost: " << params::FormatDouble(train_res[0].total) << "\n"
        << "tuned_cost: " << params::FormatDouble(train_res[1].total) << "\n";
    man << "training_verdict: " << tuning::VerdictName(train_change.verdict) << "\n";
    if (!held_res.empty())
      man << "held_out_baseline_cost: " << params::FormatDouble(held_res[0].total) << "\n"
          << "held_out_tuned_cost: " << params::FormatDouble(held_res[1].total) << "\n"
          << "held_out_verdict: " << tuning::VerdictName(held_change.verdict) << "\n";
    man << "sensitivity: " << params::QuoteString(sensitivity) << "\n";
    if (sensitivity == "done") {
      man << "sensitivity_sets: " << sensitivity_sets << "\n"
          << "not_exercised:" << (not_exercised.empty() ? " []" : "") << "\n";
      for (const auto& label : not_exercised) man << "  - " << params::QuoteString(label) << "\n";
    }
    man << "hash_algorithm: sha256\n";
    man << "changed_keys: " << changed.size() << "\n"
        << "wall_time_s: "
        << params::FormatDouble(
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count())
        << "\n";
    // SHA-256 of the files as written (`sha256sum FILE` prints the same); the inputs above are
    // hashed as files when given, as their printed form when built in.
    man << "files_sha256:\n";
    for (const char* f :
         {"evaluations.csv", "stability_tuned.yaml", "stability_overrides.yaml", "comparison.md",
          "comparison.csv", "sensitivity.csv", "convergence.png", "comparison.png"})
      if (fs::exists(fs::path(dir) / f))
        man << "  " << f << ": " << FileSha256((fs::path(dir) / f).string()) << "\n";
    io::WriteFileAtomic((fs::path(dir) / "manifest.yaml").string(), man.str());
  };
  write_manifest();
  if (sensitivity == "pending") {
    const auto t0 = std::chrono::steady_clock::now();
    const tuning::SensitivityPlan plan = tuning::PlanSensitivity(space, r.best_u, base);
    const int n_runs = static_cast<int>(plan.sets.size() * training.scenarios().size());
    progress.Update({"sensitivity", 0, static_cast<double>(n_runs), "runs", "", -1.0});
    const tuning::SensitivityResult sens = tuning::EvaluateSensitivity(
        training, space, plan, PhaseProgress(progress, "sensitivity", 0, n_runs, "runs"));
    progress.Finish();
    md += "\n" + tuning::SensitivityMarkdown(sens, "the tuned set");
    io::WriteFileAtomic((fs::path(dir) / "sensitivity.csv").string(), tuning::SensitivityCsv(sens));
    io::WriteFileAtomic(md_path, md + plots_md);
    sensitivity = "done";
    sensitivity_sets = sens.sets;
    not_exercised = sens.NotExercised();
    write_manifest();
    std::cerr << "  sensitivity: " << sens.sets << " sets x " << training.scenarios().size()
              << " scenarios in "
              << Seconds(
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count())
              << "; ";
    if (not_exercised.empty()) {
      std::cerr << "every parameter is exercised by the training scenarios\n";
    } else {
      std::cerr << not_exercised.size() << " of " << space.size()
                << " parameters not exercised by the training scenarios:";
      for (const auto& label : not_exercised) std::cerr << " " << label;
      std::cerr << "\n";
    }
  }
  md += plots_md;
  std::cout << AlignMarkdownTables(md);
  std::cout << "outputs: " << dir << "/{evaluations.csv, stability_tuned.yaml, "
            << "stability_overrides.yaml, comparison.md, comparison.csv, "
            << (sensitivity == "done" ? "sensitivity.csv, " : "")
            << (plots ? "convergence.png, comparison.png, " : "") << "manifest.yaml}\n";
  if (r.stop_reason == "resume_mismatch") return kExitBadInput;
  // Ctrl-C: the outputs of the best set so far are written; exit as an interrupted program does.
  return r.stop_reason == "interrupted" ? kExitInterrupted : kExitOk;
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
  const tuning::ScenarioSet set = LoadSet(o.scenarios);
  std::vector<params::StabilityParams> sets;
  for (const auto& f : o.params_files) sets.push_back(LoadBase(f, nullptr));
  if (sets.empty()) sets.push_back(params::StabilityParams{});
  // One progress phase: each scenario's preparation and every run are a job.
  ProgressLine progress(o.progress);
  const int n_scenarios = static_cast<int>(set.training.size() + set.held_out.size());
  const int total = n_scenarios * static_cast<int>(sets.size() + 1);
  progress.Update({"evaluate", 0, static_cast<double>(total), "jobs", "", -1.0});
  int done = 0;
  std::string md, csv;
  bool header = true;
  for (const auto* group : {&set.training, &set.held_out}) {
    if (group->empty()) continue;
    const int n = static_cast<int>(group->size());
    const auto ev = tuning::BatchEvaluator::FromEntries(
        *group, set.base_dir, set.cost, o.threads,
        PhaseProgress(progress, "evaluate", done, total, "jobs"));
    done += n;
    const auto res = ev.Evaluate(sets, PhaseProgress(progress, "evaluate", done, total, "jobs"));
    done += n * static_cast<int>(sets.size());
    const std::string name = group == &set.training ? "training" : "held_out";
    md += tuning::ComparisonMarkdown(name, ev, labels, res);
    csv += tuning::ComparisonCsv(name, ev, labels, res, header);
    header = false;
  }
  progress.Finish();
  std::cout << AlignMarkdownTables(md);
  if (!o.csv.empty()) io::WriteFileAtomic(o.csv, csv);
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
      "space and scenarios, about two minutes on 2 cores) and export the car's params files");
  cmd->add_option("--space", o->space, "Search space file (params/spaces/*.yaml)");
  cmd->add_option("--scenarios", o->scenarios, "Scenario set file (params/scenarios/*.yaml)");
  cmd->add_option("--base", o->base, "Starting stability params file (car's ROS 2 layout)");
  cmd->add_option("--base-outside", o->base_outside,
                  "A base value outside a space range: grow the range to include it (default), "
                  "or refuse (exit 2, naming the key)")
      ->check(CLI::IsMember({"grow", "refuse"}));
  cmd->add_option("--algorithm", o->algorithm,
                  "Search algorithm: NLopt's crs2, isres, esch, direct_l, sbplx, neldermead, "
                  "bobyqa, cobyla; lhs (a Latin-hypercube design, batched: see --batch); or A+B "
                  "(global A, then local B)")
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
  WholeNumberIn(cmd->add_option("--threads", o->threads, kThreadsHelp), 0, 1024)
      ->capture_default_str();
  SeedOption(cmd->add_option("--seed", o->seed, "Optimizer seed (a whole number >= 0)"))
      ->capture_default_str();
  cmd->add_option("--out-dir", o->out, "Output folder (default: a fresh scw-runs/tune-<time>)");
  AddHiddenAlias(cmd, "--out", o->out);
  cmd->add_flag("--force", o->force,
                "Write into an --out-dir that already holds files (default: refuse, exit 2)");
  cmd->add_option("--resume", o->resume,
                  "Continue an interrupted run from its evaluations.csv (same options)");
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
                "+/- 10 %, one batch on the training scenarios, the parameters the scenarios "
                "cannot see flagged in comparison.md");
  cmd->footer(
      "Under MPI (mpirun -np N scw tune ...): rank 0 runs the tune and writes every file, all\n"
      "ranks compute runs; the outputs equal a plain run's for any N (docs/scaling.md).");
  cmd->callback([o] { SetExitCode(RunTune(*o)); });

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
  ev->add_option("--scenarios", e->scenarios, "Scenario set file (default: built-in)");
  WholeNumberIn(ev->add_option("--threads", e->threads, kThreadsHelp), 0, 1024);
  ev->add_option("-o,--output", e->csv, "Also write the table as CSV");
  AddHiddenAlias(ev, "--csv", e->csv);
  AddProgressOption(ev, &e->progress);
  ev->callback([e] { SetExitCode(RunEvaluate(*e)); });
}

const CommandRegistrar kRegistrar(25, &AddTune);

}  // namespace
}  // namespace scw::cli
