// The remote side of a job: what an MPI rank or a worker process runs for the caller of
// exec::Executor (executor.h). Both remote back ends serve the same tasks, so a library describes
// its remote work once.
//
// A task is one kind of work prepared once on every worker from setup bytes (e.g. an evaluator:
// its scenario entries, resolved by each worker itself) and then run in batches: StartBatch gets
// the batch's payload (e.g. the candidate sets), Run(i) computes job i of the batch and returns
// its result as bytes, which the caller decodes into slot i.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>

namespace scw::tuning::exec {

/// One prepared task on a worker (an MPI rank ≥ 1 or a worker process).
class WorkerTask {
 public:
  virtual ~WorkerTask() = default;
  /// A new batch: its payload, before any of its jobs runs.
  virtual void StartBatch(std::string_view payload) = 0;
  /// Job `index` of the current batch, from up to `threads` threads at once; the result's bytes.
  /// An exception becomes an error of that job on the caller's side (std::runtime_error with its
  /// message).
  virtual std::string Run(int index) const = 0;
};

/// Builds a task from the setup bytes the caller sent, with `threads` job threads (may take long:
/// it runs while the caller prepares its own copy).
using TaskFactory = std::function<std::unique_ptr<WorkerTask>(std::string_view setup, int threads)>;

/// The task kinds a worker can serve, by name (e.g. "evaluate", "sweep").
using TaskKinds = std::map<std::string, TaskFactory>;

}  // namespace scw::tuning::exec
