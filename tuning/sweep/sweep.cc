#include "tuning/sweep/sweep.h"

namespace scw::tuning::sweep {

SweepResult RunSweep(const SweepDefinition& d, const SweepExecution& execution,
                     const SweepTraceOptions& traces) {
  return RunSweep(ExpandSweep(d), execution, traces);
}

SweepResult RunSweep(const SweepDefinition& d, int threads, const SweepTraceOptions& traces) {
  SweepExecution execution;
  execution.threads = threads;
  return RunSweep(d, execution, traces);
}

}  // namespace scw::tuning::sweep
