// The worker-process back end of the execution layer (executor.h): N child processes (normally
// the same scw binary) each serve the caller's task (worker_task.h), one job at a time.
//
// Why processes besides threads: the MPC motion controllers' Ipopt calls are serialised within a
// process (controller/motion/nlp_solver.h), so threads do not speed up MPC runs.
//
// Protocol: each worker is `argv` + "--worker-fd=3" (e.g. `scw sweep --worker-fd=3`, which calls
// ServeWorkerProcess); it reads lines on its stdin and answers on fd 3, one line per job. Binary
// data travels as hexadecimal text, so every message is one line:
//   to the worker     "setup <kind> <setup>" once, then per batch "batch <payload>", then
//                     "job <i>" whenever it is free; end of input: exit 0
//   from the worker   "ok <i> <result bytes>" or "error <i> <message>"
// The worker's stdout goes to stderr, so stray output cannot corrupt the protocol; one job per
// worker at a time, so no pipe can fill. Jobs are handed out in the caller's order as workers
// become free; results land by index, so which worker ran which job changes nothing.
#pragma once

#include <signal.h>
#include <sys/types.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "tuning/exec/worker_task.h"

namespace scw::tuning::exec {

/// A worker process died, could not be started or sent something unreadable.
class WorkerError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ProcessPool {
 public:
  /// Starts `n` workers and sends each the task (`kind`, `setup`). Throws WorkerError when a pipe
  /// or process cannot be made.
  ProcessPool(std::vector<std::string> argv, int n, const std::string& kind,
              const std::string& setup);
  /// Ends the workers still running (SIGTERM) and waits for them.
  ~ProcessPool();
  ProcessPool(const ProcessPool&) = delete;
  ProcessPool& operator=(const ProcessPool&) = delete;

  /// Runs jobs [0, jobs) of a batch with `payload`, handed out in `order` (empty: index order);
  /// on_result(i, bytes) for every answer "ok", from the calling thread. Errors (an "error" answer
  /// as std::runtime_error, or an exception of on_result) are rethrown after the batch, the first
  /// by index; a worker that dies throws WorkerError at once, naming label(i) of its job.
  void Run(const std::string& payload, int jobs, const std::vector<int>& order,
           const std::function<void(int, std::string_view)>& on_result,
           const std::function<std::string(int)>& label);

  /// Ends the workers (end of their input) and checks that each exited with 0 (else WorkerError).
  void Finish();

  int size() const { return static_cast<int>(workers_.size()); }

 private:
  struct Worker {
    pid_t pid;
    int to, from;
    std::string buf;
    int job;
  };
  [[noreturn]] void Died(Worker& w, const std::string& doing);

  std::vector<Worker> workers_;
  struct sigaction old_sigpipe_ {};
};

/// The worker side: reads the protocol on `in_fd` and answers on `out_fd`, building the task
/// from `kinds`, until end of input. Returns the process exit code (0: input ended).
int ServeWorkerProcess(const TaskKinds& kinds, int in_fd, int out_fd);

}  // namespace scw::tuning::exec
