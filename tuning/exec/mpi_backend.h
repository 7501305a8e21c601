// The MPI back end of the execution layer (executor.h; the only file that includes <mpi.h> is
// mpi_backend.cc): `mpirun -np N scw tune|evaluate|sweep ...` spreads the runs over N processes
// (docs/scaling.md, "Running under MPI").
//
// Roles
//   rank 0     runs the command as in a plain run (optimiser, files, messages); when a batch of
//              jobs is due it hands the jobs out and also computes jobs itself on its own threads
//   ranks ≥ 1  never run the command: they serve tasks (RunWorker) until rank 0 says stop
//
// A task (worker_task.h) is one kind of work prepared once on every worker and then run in
// batches. A batch sends its payload
// (e.g. the candidate sets) to every worker; the workers then ask for jobs, rank 0 answers with
// the next job index or "none", and the result of job i comes back as bytes that rank 0 decodes
// into slot i. Jobs have very unequal lengths (aborted runs end early), hence the dynamic
// hand-out: a job thread gets its next job when it is free, except that while more jobs remain
// than all ranks have threads, each worker thread keeps one job queued behind the running one, so
// it does not wait for rank 0's answer between jobs. Because every result lands in its slot by
// index, the outcome does not depend on N, on the thread counts or on which process ran which job.
//
// Threads: MPI is initialised with MPI_THREAD_FUNNELED; only the thread that called Init (the
// main thread) talks to MPI. The jobs run on extra threads in every process (`threads` per rank),
// so rank 0's main thread only serves requests and sleeps in between (it polls every 20 µs to
// 1 ms, because a blocking MPI receive spins and would take a core from the jobs). Jobs are handed
// out in the order the caller gives (the evaluator: longest first).
//
// Without a launcher (no mpirun/srun environment) MPI is never touched: Ranks() = 1 and every
// command runs as in a build without MPI. A build without MPI (SCW_WITH_MPI=OFF) has the same
// interface; there Init only refuses a launch with several processes (StartupError).
//
// A rank that dies: Open MPI ends the whole job (mpirun sends SIGTERM to the other ranks). Rank 0
// then prints what happened and the note set with SetTerminationNote (scw tune: how to resume)
// before it dies by that signal.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "tuning/exec/worker_task.h"

namespace scw::tuning::exec::mpi {

/// Whether this program was built with the MPI backend.
bool BuiltIn();
/// The MPI library's name and version, e.g. "Open MPI v4.1.4" ("" without MPI).
std::string LibraryVersion();

/// Starts MPI if the process was started by an MPI launcher (its environment says so), else does
/// nothing. Call once, at the start of main, before any thread is created.
void Init(int* argc, char*** argv);
/// Rank 0: tells the workers to stop. Every rank: ends MPI. Safe to call more than once.
void Finalize();
/// Non-empty when this process must not run a command: a build without MPI started by a launcher
/// with more than one process (each copy would run the whole command and write the same files).
const std::string& StartupError();

/// MPI is running (started by a launcher, also with a single rank).
bool Launched();
/// Number of processes of the run (1 without MPI).
int Ranks();
/// This process's rank (0 without MPI).
int Rank();

/// Rank 0, more than one rank: text printed on stderr if the process is stopped by SIGTERM (what
/// mpirun sends when another rank dies). Empty: only the general message.
void SetTerminationNote(const std::string& note);

/// Ranks ≥ 1: serves tasks of the given kinds until rank 0 says stop; returns the exit code.
int RunWorker(const TaskKinds& kinds);

/// Rank 0's handle of a task prepared on every worker; destroying it frees the workers' copies.
class RemoteTask {
 public:
  /// Sends the task to every worker (returns at once; the workers build it in the background).
  /// Only when Ranks() > 1 on rank 0. `threads` = job threads of every rank for this task.
  RemoteTask(const std::string& kind, const std::string& setup, int threads);
  ~RemoteTask();
  RemoteTask(const RemoteTask&) = delete;
  RemoteTask& operator=(const RemoteTask&) = delete;

  /// Runs jobs [0, jobs) on every rank: local(i) on this process's job threads, remote(i, bytes)
  /// on the calling thread for a job a worker ran. Exceptions (of local, remote, or a worker's
  /// job) are rethrown after the batch, the first by index. Called from another thread than
  /// Init's, every job runs locally. `order` (empty, or a permutation of [0, jobs)) is the order
  /// in which jobs are handed out, e.g. longest first; it changes when a job runs, never its
  /// result.
  void Run(const std::string& payload, int jobs, const std::function<void(int)>& local,
           const std::function<void(int, std::string_view)>& remote,
           const std::vector<int>& order = {}) const;

  int threads() const { return threads_; }

 private:
  int id_;
  int threads_;
};

/// A RemoteTask when this is rank 0 of a run with more than one rank, else null.
std::shared_ptr<const RemoteTask> MaybeRemote(const std::string& kind,
                                              const std::function<std::string()>& setup,
                                              int threads);

}  // namespace scw::tuning::exec::mpi
