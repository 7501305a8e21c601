// The execution layer: one interface that runs N indexed jobs on threads, worker processes or MPI
// ranks and leaves their results in index order. The batch evaluator (tuning/optim/evaluator.h)
// and the sweep (tuning/sweep/sweep_run.h) use it; neither knows which back end runs its jobs.
//
// A caller describes a job twice, once per side:
//   here     Batch::local(i) computes job i in this process and writes slot i;
//   remote   a WorkerTask (worker_task.h), registered by kind on the workers (scw's main for MPI
//            ranks, the command behind Options::worker_command for processes), computes job i
//            from the task's setup bytes and the batch's payload and returns its result as bytes;
//            Batch::remote(i, bytes) decodes them into slot i, on the calling thread.
// Results land in their slots by index, so they are bit-identical for any back end, thread count,
// process count and number of ranks; the hand-out order (Batch::order) changes when a job runs,
// never its result. Errors are collected per job and the first by index is rethrown after the
// batch (a worker process that dies ends the batch at once with WorkerError, processes.h).
//
// Back ends, chosen at construction:
//   processes   Options::processes ≥ 1: that many worker processes (processes.h), one job each
//               at a time; this process only hands out jobs and decodes results
//   MPI         rank 0 of an MPI run with more than one rank (mpi_backend.h): every rank,
//               this one included, runs `threads` jobs at once
//   threads     otherwise: ParallelFor (parallel_for.h) on Options::threads threads
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "tuning/exec/mpi_backend.h"
#include "tuning/exec/processes.h"
#include "tuning/exec/worker_task.h"

namespace scw::tuning::exec {

/// Where jobs run.
struct Options {
  /// Job threads of this process (0 = all cores; under MPI with several ranks: 1 per rank).
  /// With processes: the threads of what the caller does here besides the jobs.
  int threads = 0;
  /// ≥ 1: worker processes run the jobs; 0: threads (or MPI ranks).
  int processes = 0;
  /// With processes: a worker's executable and leading arguments, e.g. {"/proc/self/exe",
  /// "sweep"}; the worker gets "--worker-fd=3" and serves with ServeWorkerProcess.
  std::vector<std::string> worker_command;
};

enum class Backend { kThreads, kProcesses, kMpi };

/// One batch: jobs [0, jobs).
struct Batch {
  int jobs = 0;
  /// Computes job i in this process and writes its slot (threads, and this rank under MPI).
  std::function<void(int)> local;
  /// Remote back ends: what every worker gets before the batch's jobs (WorkerTask::StartBatch).
  std::string payload;
  /// Remote back ends: writes job i's slot from the bytes WorkerTask::Run returned.
  std::function<void(int, std::string_view)> remote;
  /// Hand-out order: empty, or a permutation of [0, jobs) (e.g. longest first).
  std::vector<int> order;
  /// Names job i in a message about a worker process (default "job <i+1>").
  std::function<std::string(int)> label;
};

class Executor {
 public:
  /// Picks the back end (see the header comment). `kind` names the task registered on the
  /// workers; `setup()` gives its setup bytes, called only for a remote back end (under MPI the
  /// ranks build their copies while the caller goes on). Throws WorkerError when worker
  /// processes cannot be started.
  Executor(const Options& options, const std::string& kind,
           const std::function<std::string()>& setup);
  /// Threads only (no remote task): the same as Options{threads}.
  explicit Executor(int threads);
  ~Executor();
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  /// Runs the batch's jobs; returns when every job is done (or a worker process died).
  void Run(const Batch& batch) const;
  /// Worker processes: ends them and checks their exit codes (WorkerError). Otherwise nothing.
  void Finish();

  Backend backend() const { return backend_; }
  /// Jobs running at once over every process: threads, processes, or ranks × threads.
  int workers() const { return workers_; }
  /// Job threads of this process (the threads back end; 1 per rank under MPI unless given).
  int threads() const { return threads_; }

 private:
  Backend backend_ = Backend::kThreads;
  int threads_ = 1;
  int workers_ = 1;
  std::shared_ptr<const mpi::RemoteTask> remote_;
  std::unique_ptr<ProcessPool> pool_;
};

}  // namespace scw::tuning::exec
