// Run: a SweepPlan's runs through the closed loop — on threads, worker processes or MPI ranks —
// into per-index result slots, then the traces of the selected reported runs.
//
// Stopping at the first abort (definition.stop_at_first_abort): a series reports its runs only up
// to and including its first abort. The runs go in waves (the next ceil(workers / series still
// going) values of every series still going, in parallel), so little is computed past an abort;
// runs after the first abort may or may not be computed (depending on the worker count) and are
// never reported, so the reported results do not depend on the worker count.
//
// Resolutions (racing line and velocity profile) happen when a run first needs them, once per
// SweepPlan::resolutions entry (values after every series' first abort are never resolved); each
// run gets a copy of its group's resolved scenario with its own spec.
//
// Determinism: resolutions and runs are pure functions written into per-index slots, so the
// results are bit-identical for any thread count, process count and number of MPI ranks.
//
// Execution (tuning/exec/executor.h): the runs go through the execution layer, on threads of this
// process, on worker processes (SweepExecution::processes; `worker_command` + "--worker-fd=3", the
// same scw binary: `scw sweep --worker-fd=3` serves the task kind "sweep") or on MPI ranks (rank 0
// of a run with more than one rank, without processes). A remote worker gets the definition,
// builds the same plan, resolves the scenarios it is given (the racing line once per process) and
// sends each run's results back as exact text (hexadecimal floats) into the same per-index slots,
// so the table is bit-identical to the single-process one and the series stop at their first abort
// exactly as with threads; the waves count every worker. A worker process that dies or cannot be
// started ends the sweep with std::runtime_error naming the run it was computing; nothing is
// written then. Traces are re-run in this process (threads).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "params/schema/scenario_params.h"
#include "tuning/exec/executor.h"
#include "tuning/sim/metrics.h"
#include "tuning/sweep/sweep_plan.h"

namespace scw::tuning::sweep {

struct SweepRun {
  GridPoint point;
  params::ScenarioParams spec;
  RunMetrics metrics;
  double ideal_lap_time = 0.0;  ///< [s] of the run's reference
  bool computed = false;        ///< false: skipped after its series' first abort
  bool reported = true;
};

struct SweepResult {
  std::vector<SweepAxis> axes;
  std::vector<SweepConfig> configs;  ///< as run (never empty)
  std::vector<SweepRun> runs;        ///< every run of the grid, in run order
  int resolves = 0;                  ///< distinct scenario resolutions
};

/// Which runs a series reports when it stops at its first abort: `aborted[i]` for run i,
/// `series[i]` its series (runs of a series in order). Without stopping every run is reported.
std::vector<bool> ReportedRuns(const std::vector<int>& series, const std::vector<bool>& aborted,
                               bool stop_at_first_abort);

/// Trace request: the runs to trace and the folder (one CSV per run, TraceFileName in
/// sweep_write.h).
struct SweepTraceOptions {
  std::string dir;  ///< "" = no traces
  /// "key=value" conditions (ParseTraceConditions: key `config` or a varied key; numbers compare
  /// by value). Conditions on different keys must all hold, on the same key any one; none = every
  /// reported run.
  std::vector<std::string> at;
};

/// Progress of a sweep: phase "run" counts the computed runs (a run's scenario resolution is
/// part of it), phase "trace" the traced runs. With stop_at_first_abort the run total shrinks
/// when a series stops (its later runs are never computed).
struct SweepProgress {
  std::string phase;
  int done = 0;
  int total = 0;
};

/// Where the runs execute (threads, processes, worker_command: exec::Options; with processes
/// `threads` serves the traces only), and who watches.
struct SweepExecution : exec::Options {
  /// The observer: called at the start of each phase (done = 0), after every finished run and,
  /// when stopping at the first abort, after every wave (with the new total); from the worker
  /// threads but never two calls at once. It only observes: the results do not depend on it.
  std::function<void(const SweepProgress&)> on_progress;
};

/// Runs the plan and writes the traces of the selected reported runs (re-run with a trace
/// writer: runs are deterministic). Throws ConfigError for bad trace conditions (before anything
/// runs) and for runs that fail on their input, std::runtime_error for I/O failures and failed
/// worker processes.
SweepResult RunSweep(const SweepPlan& plan, const SweepExecution& execution,
                     const SweepTraceOptions& traces = {});

/// The remote side of a sweep (task kind "sweep": registered by scw's main for MPI ranks and by
/// `scw sweep --worker-fd` for worker processes).
std::unique_ptr<exec::WorkerTask> MakeSweepWorkerTask(std::string_view setup, int threads);

}  // namespace scw::tuning::sweep
