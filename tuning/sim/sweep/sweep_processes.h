// The worker-process back end of RunSweep (sweep_run.h, SweepExecution::processes); internal to
// the sweep.
//
// Protocol: each worker is `argv` + "--worker-fd=3"; it reads "run <i>" lines on its stdin and
// answers "ok <i> <results>" or "error <i> <C|R> <message>" on fd 3 (C: a ConfigError, R: another
// error; the message on one line, see OneLine). Its stdout goes to stderr so stray output cannot
// corrupt the protocol. One job per worker at a time, so no pipe can fill.
#pragma once

#include <signal.h>
#include <sys/types.h>

#include <functional>
#include <string>
#include <vector>

namespace scw::tuning::detail {

/// A message with its line breaks replaced by '\x1f' (undone by the pool), for an "error" line.
std::string OneLine(std::string s);

class SweepProcessPool {
 public:
  /// Starts `n` workers. `label(i)` names run i in messages ("run 3 (config all, gg_scale=1.1)").
  /// Throws std::runtime_error when a pipe or process cannot be made.
  SweepProcessPool(std::vector<std::string> argv, int n, std::function<std::string(int)> label);
  /// Ends the workers still running (SIGTERM) and waits for them.
  ~SweepProcessPool();
  SweepProcessPool(const SweepProcessPool&) = delete;
  SweepProcessPool& operator=(const SweepProcessPool&) = delete;

  /// Runs `jobs` on the workers; on_result(i, payload) for every answer "ok" (payload: the text
  /// after "ok <i>"), from the calling thread. Errors of runs are rethrown after the batch (the
  /// first by index; ConfigError for "C"); a worker that dies throws std::runtime_error at once.
  void Run(const std::vector<int>& jobs, const std::function<void(int, const char*)>& on_result);

  /// Ends the workers (EOF on their input) and checks that each exited with 0.
  void Finish();

 private:
  struct Worker {
    pid_t pid;
    int to, from;
    std::string buf;
    int job;
  };
  [[noreturn]] void Died(Worker& w);

  std::function<std::string(int)> label_;
  std::vector<Worker> workers_;
  struct sigaction old_sigpipe_ {};
};

}  // namespace scw::tuning::detail
