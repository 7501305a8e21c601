// Parameter sweeps: one scenario run over a grid of scenario overrides and named configurations,
// as one deterministic batch (the paper's simulation studies, §IV–V: "lateral and longitudinal
// acceleration references ... incrementally increased in each run by a linear acceleration
// scaling value until an abort condition occurs ... The results for each configuration are
// reported up to the first scaling that results in an abort").
//
// Vocabulary
//   axis           one varied scenario key with its values, from `--vary key=v1,v2,...` or
//                  `--vary key=start:step:stop` (values kept as text: they are `--set` values)
//   configuration  a named set of overrides, from `--config name:key=v,key=v` (e.g. the four
//                  ESC/CS combinations); no configuration = one configuration "default"
//   grid           configurations × Cartesian product of the axes
//   series         one configuration at fixed values of axes 2..n over the values of the FIRST
//                  axis in the order given (e.g. increasing GG)
//
// Order of the runs (and of the CSV rows): configuration (in the order given), then the axes
// 2..n (the last one fastest), then the first axis — so each series is a contiguous block.
//
// Overrides apply in this order: the base overrides (`--set`), the configuration's, the axes'.
// The stability file (if given) replaces the scenario's `stability` key.
//
// Stopping at the first abort (stop_at_first_abort): a series reports its runs only up to and
// including its first abort. The runs go in waves (the next ceil(threads / series still going)
// values of every series still going, in parallel), so little is computed past an abort; runs
// after the first abort may or may not be computed (depending on the thread count) and are never
// reported, so the reported results do not depend on the thread count.
//
// Resolution (racing line and velocity profile, ~1 s) is shared: runs whose scenarios differ only
// in keys the closed loop reads at run time (subsystems.*, abort.*, laps, name) share one
// Resolve; each run gets a copy of the resolved scenario with its own spec. Resolutions happen
// when a run first needs them (values after every series' first abort are never resolved).
//
// Determinism: resolutions and runs are pure functions written into per-index slots, so the
// results are bit-identical for any thread count.
//
// Worker processes (SweepExecution::processes): the MPC motion controllers' Ipopt calls are
// serialised within a process (controller/motion/nlp_solver.h), so threads do not speed up MPC
// sweeps. With `processes` = N the runs go to N worker processes instead: each is
// `worker_command` + SweepWorkerArguments(d) (the same scw binary, `scw sweep ... --worker-fd=3`,
// RunSweepWorker), builds the same grid, resolves the scenarios it is given (the racing line
// once per process) and computes one run at a time, handed out by the parent as workers become
// free, in the same waves as with threads. Results travel as exact text (hexadecimal floats)
// into the same per-index slots, so the table is bit-identical to the single-process one and the
// series stop at their first abort exactly as with threads. A worker that dies or cannot be
// started ends the sweep with std::runtime_error naming the run it was computing; nothing is
// written then. Traces are re-run in the parent (threads).
//
// MPI (tuning/sim/parallel/mpi_backend.h; without --processes): on rank 0 of a run with more than
// one rank, every rank builds the same grid and takes runs one at a time, `threads` per rank;
// results travel as the same exact text into the same slots, the waves count every rank's threads,
// and the reported table is the one of a single process.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "params/schema/scenario_params.h"
#include "tuning/sim/metrics.h"

namespace scw::tuning {

namespace mpi {
class WorkerTask;
}  // namespace mpi

struct SweepAxis {
  std::string key;                  ///< dotted scenario key, e.g. gg_scale
  std::vector<std::string> values;  ///< `--set` values, e.g. "1.05"
};

struct SweepConfig {
  std::string name;                    ///< [A-Za-z0-9_.+-]+ (file names, CSV)
  std::vector<std::string> overrides;  ///< "key=value"
};

/// Parses `key=v1,v2,...` (commas inside [...] do not split: list values) or
/// `key=start:step:stop` (inclusive stop, within 1e-9 of a step; values printed with the decimals
/// of the arguments, e.g. 1.0:0.05:1.2 → 1, 1.05, 1.1, 1.15, 1.2). The key is not checked here
/// (see ValidateSweep). Throws ConfigError with source "--vary <arg>" saying what is wrong.
SweepAxis ParseVary(const std::string& arg);

/// Parses `name:key=v,key=v` (or just `name` for no overrides). Throws ConfigError with source
/// "--config <arg>".
SweepConfig ParseConfig(const std::string& arg);

/// One run of the grid: indices into the configurations and into each axis's values.
struct GridPoint {
  int config = 0;
  std::vector<int> value;  ///< per axis
  int series = 0;          ///< runs with the same series index form one series
};

/// The grid in run order (see the header comment). `n_configs` ≥ 1; no axes = one run per
/// configuration (each its own series).
std::vector<GridPoint> ExpandGrid(const std::vector<SweepAxis>& axes, int n_configs);

/// Which runs a series reports when it stops at its first abort: `aborted[i]` for run i,
/// `series[i]` its series (runs of a series in order). Without stopping every run is reported.
std::vector<bool> ReportedRuns(const std::vector<int>& series, const std::vector<bool>& aborted,
                               bool stop_at_first_abort);

struct SweepDefinition {
  std::string scenario_file;                ///< "" = the built-in default scenario
  std::vector<std::string> base_overrides;  ///< `--set`
  std::string stability_file;               ///< "" = the scenario's
  std::vector<SweepAxis> axes;
  std::vector<SweepConfig> configs;  ///< empty = one configuration "default"
  bool stop_at_first_abort = false;
};

/// One run's scenario: base spec + configuration + axis values (throws ConfigError).
params::ScenarioParams PointScenario(const SweepDefinition& d, const GridPoint& p);

/// Checks every configuration and axis value against the scenario schema before anything runs.
/// Throws one ConfigError listing every bad argument, each named as given on the command line
/// (e.g. "--vary gg_scale=1.0,abc: gg_scale: cannot read the value 'abc'").
void ValidateSweep(const SweepDefinition& d);

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

/// Trace request: the runs to trace and the folder (one CSV per run, TraceFileName).
struct SweepTraceOptions {
  std::string dir;  ///< "" = no traces
  /// "key=value" conditions (key: `config` or a varied key; numbers compare by value). Conditions
  /// on different keys must all hold, on the same key any one; none = every reported run.
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

/// Where the runs execute (see the header comment).
struct SweepExecution {
  int threads = 0;    ///< threads of this process (0 = all cores); with processes: traces only
  int processes = 0;  ///< ≥ 1: worker processes for the runs; 0: threads
  /// Executable and leading arguments of a worker, e.g. {"/proc/self/exe", "sweep"}.
  std::vector<std::string> worker_command;
  /// Called at the start of each phase (done = 0) and after every finished run, from the worker
  /// threads but never two calls at once. It only observes: the results do not depend on it.
  std::function<void(const SweepProgress&)> on_progress;
};

/// Runs the grid and writes the traces of the selected reported runs (re-run with a trace
/// writer: runs are deterministic). Throws ConfigError for bad input, std::runtime_error for I/O
/// failures and failed worker processes.
SweepResult RunSweep(const SweepDefinition& d, const SweepExecution& exec,
                     const SweepTraceOptions& traces = {});
/// The same on `threads` threads (0 = all cores).
SweepResult RunSweep(const SweepDefinition& d, int threads, const SweepTraceOptions& traces = {});

/// The `scw sweep` arguments that rebuild `d` in a worker (--scenario=, --set=, --stability=,
/// --vary= with the expanded values, --config=).
std::vector<std::string> SweepWorkerArguments(const SweepDefinition& d);

/// The worker side: reads "run <i>" lines from `in_fd` until end of input and answers each on
/// `out_fd` with the run's results (or its error). Returns the process exit code (0: input ended).
int RunSweepWorker(const SweepDefinition& d, int in_fd, int out_fd);

/// The other ranks' side of a sweep under MPI (main registers it as task kind "sweep").
std::unique_ptr<mpi::WorkerTask> MakeSweepWorkerTask(std::string_view setup, int threads);

/// Whether a run matches the trace conditions (throws ConfigError for a malformed condition or a
/// key that is neither `config` nor varied).
bool MatchesTraceConditions(const SweepResult& r, const SweepRun& run,
                            const std::vector<std::string>& at);

/// "<config>__<key>-<value>[__...].csv", characters outside [A-Za-z0-9_.+-] replaced by '_'.
std::string TraceFileName(const SweepResult& r, const SweepRun& run);

/// Writes the reported runs as CSV (atomic; shortest round-trip numbers; NaN as "nan"):
/// config, the varied keys, status, progress, laps_completed, lap_1_s..lap_N_s, mean_lap_time_s,
/// max_abs_sideslip_deg, max_slip_front_pct, max_slip_rear_pct, max_abs_lateral_error_m,
/// max_abs_heading_error_deg, max_speed_mps, {esc,cs,abs,tc}_count, {esc,cs,abs,tc}_time_s,
/// esc_brake_energy_J, end_lap, end_s_m, ideal_lap_time_s.
void WriteSweepCsv(const std::string& path, const SweepResult& r);

}  // namespace scw::tuning
