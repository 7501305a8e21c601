// Expand: a SweepDefinition → the runs of its grid, each with its scenario, in run order, and the
// distinct scenario resolutions they need. Runs nothing (the scenario file, if any, is read).
//
//   grid    configurations × Cartesian product of the axes
//   series  one configuration at fixed values of axes 2..n over the values of the FIRST axis in
//           the order given (e.g. increasing GG)
//
// Order of the runs (and of the CSV rows): configuration (in the order given), then the axes
// 2..n (the last one fastest), then the first axis — so each series is a contiguous block.
//
// Overrides apply in this order: the base overrides (`--set`), the configuration's, the axes'.
// The stability file (if given) replaces the scenario's `stability` key (as an absolute path).
//
// Resolution groups: runs whose scenarios differ only in keys the closed loop reads at run time
// (subsystems.*, abort.*, laps, name) share one resolution (racing line and velocity profile,
// ~1 s); PlannedRun::resolution names it.
//
// Deterministic: the same definition gives the same plan (worker processes and MPI ranks rebuild
// it from the definition and number the runs identically).
#pragma once

#include <string>
#include <vector>

#include "params/schema/scenario_params.h"
#include "tuning/sweep/sweep_spec.h"

namespace scw::tuning::sweep {

/// One run of the grid: indices into the configurations and into each axis's values.
struct GridPoint {
  int config = 0;
  std::vector<int> value;  ///< per axis
  int series = 0;          ///< runs with the same series index form one series
};

/// The grid in run order (see the header comment). `n_configs` ≥ 1; no axes = one run per
/// configuration (each its own series); an axis without values = no runs.
std::vector<GridPoint> ExpandGrid(const std::vector<SweepAxis>& axes, int n_configs);

/// One run's scenario: base spec + configuration + axis values (throws ConfigError).
params::ScenarioParams PointScenario(const SweepDefinition& d, const GridPoint& p);

/// Checks every configuration and axis value against the scenario schema before anything runs.
/// Throws one ConfigError listing every bad argument, each named as given on the command line
/// (e.g. "--vary gg_scale=1.0,abc: gg_scale: cannot read the value 'abc'"), and duplicate
/// configuration names, varied keys and values.
void ValidateSweep(const SweepDefinition& d);

struct PlannedRun {
  GridPoint point;
  params::ScenarioParams spec;
  int resolution = 0;  ///< index into SweepPlan::resolutions
};

struct SweepPlan {
  SweepDefinition definition;        ///< as given (workers rebuild the plan from it)
  std::vector<SweepConfig> configs;  ///< as run: definition.configs, or {"default"} if none
  std::vector<PlannedRun> runs;      ///< run order
  /// One scenario per distinct resolution, in the order of first use.
  std::vector<params::ScenarioParams> resolutions;
  std::string base_dir;  ///< the scenario file's folder (relative paths in it), "" if built-in
  std::string source;    ///< the scenario file, or "built-in" (messages)

  const std::vector<SweepAxis>& axes() const { return definition.axes; }
};

/// Validates `d` (ValidateSweep) and builds every run's scenario, serially so that errors come out
/// in run order. Throws ConfigError.
SweepPlan ExpandSweep(const SweepDefinition& d);

}  // namespace scw::tuning::sweep
