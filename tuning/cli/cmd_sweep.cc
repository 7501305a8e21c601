// scw sweep — a scenario over a grid of overrides and named configurations
// (tuning/sweep/sweep.h).
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "params/io/write.h"
#include "tuning/cli/command.h"
#include "tuning/cli/options.h"
#include "tuning/cli/progress.h"
#include "tuning/sim/motion_factory.h"
#include "tuning/sweep/sweep.h"

namespace scw::cli {
namespace {

struct SweepOptions {
  std::string scenario, stability, out, trace_dir;
  std::vector<std::string> overrides, vary, configs, trace_at;
  bool stop_at_first_abort = false, list_controllers = false;
  int threads = 0, processes = 0, worker_fd = 0;
  std::string progress = "auto";
};

int RunSweepCommand(const SweepOptions& o) {
  if (o.list_controllers) {
    for (const auto& name : tuning::MotionControllerNames()) std::cout << name << '\n';
    return kExitOk;
  }
  // A worker process of --processes: the definition comes with the task (tuning/exec/processes.h).
  if (o.worker_fd > 0)
    return tuning::exec::ServeWorkerProcess({{"sweep", &tuning::sweep::MakeSweepWorkerTask}}, 0,
                                            o.worker_fd);
  RefuseRepeatedKeys("scw sweep", "--set", o.overrides);
  tuning::sweep::SweepArguments a;
  a.scenario = o.scenario;
  a.overrides = o.overrides;
  a.stability = o.stability;
  a.vary = o.vary;
  a.configs = o.configs;
  a.stop_at_first_abort = o.stop_at_first_abort;
  const tuning::sweep::SweepDefinition d = tuning::sweep::ParseSweepArguments(a);
  tuning::sweep::SweepTraceOptions to;
  to.dir = o.trace_dir;
  to.at = o.trace_at;
  if (to.dir.empty() && !to.at.empty())
    throw ConfigError("scw sweep", "--trace-at", "needs --trace-dir DIR (where to write)");

  NoteThreads("scw sweep", o.threads);
  const auto t0 = std::chrono::steady_clock::now();
  tuning::sweep::SweepExecution exec;
  exec.threads = o.threads;
  exec.processes = o.processes;
  exec.worker_command = {"/proc/self/exe", "sweep"};
  ProgressLine progress(o.progress);
  if (progress.enabled())
    exec.on_progress = [&progress](const tuning::sweep::SweepProgress& p) {
      progress.Update({p.phase == "run" ? "sweep" : p.phase, static_cast<double>(p.done),
                       static_cast<double>(p.total), "runs", "", -1.0});
    };
  const tuning::sweep::SweepResult r =
      tuning::sweep::RunSweep(tuning::sweep::ExpandSweep(d), exec, to);
  progress.Finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!o.out.empty()) tuning::sweep::WriteSweepCsv(o.out, r);

  std::cout << tuning::sweep::SweepTable(r) << std::flush;
  const auto reported =
      std::count_if(r.runs.begin(), r.runs.end(), [](const auto& run) { return run.reported; });
  std::ostringstream wall_s;
  wall_s << std::fixed << std::setprecision(1) << wall;
  std::cerr << "sweep: " << r.runs.size() << " runs (" << reported << " reported), " << r.resolves
            << " scenario resolutions, " << wall_s.str() << " s wall";
  if (!o.out.empty()) std::cerr << "; table: " << o.out;
  if (!o.trace_dir.empty()) std::cerr << "; traces: " << o.trace_dir;
  std::cerr << '\n';
  return kExitOk;
}

void AddSweep(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  auto* cmd = app.add_subcommand(
      "sweep",
      "Run a scenario over a grid of overrides and named configurations as one parallel, "
      "deterministic batch (the paper's studies: GG raised until the first abort)");
  cmd->footer(
      "Runs are ordered by configuration, then the other varied keys, then the first varied key;\n"
      "a series is one configuration over the values of the first --vary key.\n"
      "Example (the lateral study):\n"
      "  scw sweep --set grip.rear_mu_y=0.8 abort.lock_slip_pct=100 \\\n"
      "    --vary gg_scale=1.0:0.05:1.6 --stop-at-first-abort \\\n"
      "    --config none:subsystems.esc=false,subsystems.cs=false \\\n"
      "    --config esc:subsystems.cs=false --config cs:subsystems.esc=false --config esc+cs \\\n"
      "    -o lateral.csv --trace-dir traces --trace-at gg_scale=1.4\n"
      "MPC controllers (pmpc, nmpc): use --processes 2 (their Ipopt calls do not run in\n"
      "parallel threads); the table is the same for any --threads/--processes.\n"
      "Exit codes: 0 every run evaluated and the outputs written (aborted runs are results),\n"
      "1 a run or a write failed, 2 bad arguments or files.");
  cmd->add_option("--scenario", o->scenario,
                  "Scenario file (params/scenarios/*.yaml); default: the built-in scenario");
  cmd->add_option("--set", o->overrides, "Override a scenario key for every run, e.g. laps=3")
      ->take_all();
  cmd->add_option("--vary", o->vary,
                  "Varied key: key=v1,v2,... or key=start:step:stop (inclusive); repeat for a "
                  "grid (Cartesian product)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--config", o->configs,
                  "Named configuration name:key=v,key=v (repeatable), e.g. "
                  "esc:subsystems.cs=false")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_flag("--stop-at-first-abort", o->stop_at_first_abort,
                "Report each series only up to and including its first abort (the paper)");
  cmd->add_option("--stability", o->stability,
                  "Stability params file (car's ROS 2 layout); overrides the scenario's");
  cmd->add_option("-o,--output", o->out, "Write the results table (CSV, one row per reported run)");
  AddHiddenAlias(cmd, "--out", o->out);
  cmd->add_option("--trace-dir", o->trace_dir, "Write the traces of the selected runs here");
  cmd->add_option("--trace-at", o->trace_at,
                  "Select runs to trace: key=value with key config or a varied key (repeatable; "
                  "different keys: all must match; default: every reported run)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  auto* threads = WholeNumberIn(cmd->add_option("--threads", o->threads,
                                                "Worker threads per process (0: all cores; under "
                                                "mpirun with more than one rank: 1 per rank)"),
                                0, 1024);
  WholeNumberIn(cmd->add_option("--processes", o->processes,
                                "Run the jobs in N worker processes (copies of this scw) instead "
                                "of threads: use for pmpc/nmpc, whose Ipopt calls are serialised "
                                "within a process; same table as with threads (0: threads; "
                                "under mpirun: the ranks, unless this is given); an alternative "
                                "to --threads, not a multiplier"),
                0, 256)
      ->excludes(threads);
  WholeNumberIn(
      cmd->add_option("--worker-fd", o->worker_fd, "(internal) run as a worker of --processes"), 3,
      1024)
      ->group("");
  AddProgressOption(cmd, &o->progress);
  cmd->add_flag("--list-controllers", o->list_controllers,
                "Print the motion controllers (motion.controller values) and exit");
  cmd->callback([o] { SetExitCode(RunSweepCommand(*o)); });
}

const CommandRegistrar kRegistrar(22, &AddSweep);

}  // namespace
}  // namespace scw::cli
