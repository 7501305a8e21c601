#include "tuning/sim/sweep/sweep.h"

namespace scw::tuning {

SweepResult RunSweep(const SweepDefinition& d, const SweepExecution& exec,
                     const SweepTraceOptions& traces) {
  return RunSweep(ExpandSweep(d), exec, traces);
}

SweepResult RunSweep(const SweepDefinition& d, int threads, const SweepTraceOptions& traces) {
  SweepExecution exec;
  exec.threads = threads;
  return RunSweep(d, exec, traces);
}

}  // namespace scw::tuning
