// Parameter sweeps: one scenario run over a grid of scenario overrides and named configurations,
// as one deterministic batch (the paper's simulation studies, §IV–V: "lateral and longitudinal
// acceleration references ... incrementally increased in each run by a linear acceleration
// scaling value until an abort condition occurs ... The results for each configuration are
// reported up to the first scaling that results in an abort").
//
// Four steps, each its own header:
//   parse   sweep_spec.h   the arguments as text → SweepDefinition (axes, configurations) and
//                          trace conditions; pure
//   expand  sweep_plan.h   SweepDefinition → SweepPlan: the runs in their deterministic order,
//                          each with its scenario, and the distinct resolutions they need
//   run     sweep_run.h    SweepPlan → SweepResult on threads, worker processes or MPI ranks
//                          (results in per-index slots: the same for any of them), series stopping
//                          at their first abort, traces of the selected runs
//   write   sweep_write.h  SweepResult → the results CSV, the console table, trace file names
//
// `scw sweep` (tuning/cli/cmd_sweep.cc) maps its options onto ParseSweepArguments, ExpandSweep
// and RunSweep, shows the progress and writes what they return.
#pragma once

#include "tuning/sweep/sweep_plan.h"
#include "tuning/sweep/sweep_run.h"
#include "tuning/sweep/sweep_spec.h"
#include "tuning/sweep/sweep_write.h"

namespace scw::tuning::sweep {

/// Expands and runs `d` in one call: RunSweep(ExpandSweep(d), execution, traces).
SweepResult RunSweep(const SweepDefinition& d, const SweepExecution& execution,
                     const SweepTraceOptions& traces = {});
/// The same on `threads` threads (0 = all cores).
SweepResult RunSweep(const SweepDefinition& d, int threads, const SweepTraceOptions& traces = {});

}  // namespace scw::tuning::sweep
