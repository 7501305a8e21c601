#include "tuning/exec/executor.h"

#include <stdexcept>

#include "tuning/exec/parallel_for.h"

namespace scw::tuning::exec {

Executor::Executor(const Options& options, const std::string& kind,
                   const std::function<std::string()>& setup)
    : threads_(ResolveThreads(options.threads)), workers_(threads_) {
  if (options.processes > 0) {
    if (options.worker_command.empty())
      throw std::invalid_argument("exec::Executor: worker processes need a worker command");
    backend_ = Backend::kProcesses;
    pool_ = std::make_unique<ProcessPool>(options.worker_command, options.processes, kind, setup());
    workers_ = pool_->size();
  } else if ((remote_ = mpi::MaybeRemote(kind, setup, threads_))) {
    backend_ = Backend::kMpi;
    workers_ = mpi::Ranks() * remote_->threads();
  }
}

Executor::Executor(int threads) : threads_(ResolveThreads(threads)), workers_(threads_) {}

Executor::~Executor() = default;

void Executor::Run(const Batch& b) const {
  switch (backend_) {
    case Backend::kProcesses:
      pool_->Run(b.payload, b.jobs, b.order, b.remote,
                 [&b](int i) { return b.label ? b.label(i) : "job " + std::to_string(i + 1); });
      return;
    case Backend::kMpi:
      remote_->Run(b.payload, b.jobs, b.local, b.remote, b.order);
      return;
    case Backend::kThreads:
      ParallelFor(b.jobs, threads_, b.order, b.local);
      return;
  }
}

void Executor::Finish() {
  if (pool_) pool_->Finish();
}

}  // namespace scw::tuning::exec
