// Batch evaluation of (parameter set × scenario) jobs on a thread pool.
//
// Every job is a pure function of its inputs (the resolved scenario, the parameter set and the
// scenario's seed); results land in per-index slots and are aggregated serially in index order,
// so the results are bit-identical for any thread count. A failed run (abort, NaN, invalid set)
// is a result with a status, never an exception.
//
// Thread safety: an evaluator is immutable after construction; Evaluate may be called from one
// thread at a time (it owns the worker threads of its call).
//
// Execution (tuning/exec/executor.h): the jobs run through the execution layer. On rank 0 of an
// MPI run with more than one rank, FromEntries also sends the entries to every other rank (task
// kind "evaluate"), which resolves the same scenarios; Evaluate then sends the sets and hands the
// jobs out to all ranks (rank 0 included, `threads` each). Results travel bit for bit into the
// same slots, so they equal those of one process. Otherwise the jobs run on threads.
//
// Order of the jobs: longest first (a batch ends when its last job ends, so a long job started
// last leaves the other workers idle). The length of a scenario's job is its wall time in the
// previous call (the longest over the sets), or its planned distance before the first call. The
// order decides only when a job runs, never its result.
//
// Progress: FromEntries and Evaluate optionally report (jobs done, jobs in the call) after every
// finished job, from the worker threads but never two calls at once, with `done` increasing by 1
// from 1 to the total. The callback only observes: the results do not depend on it (or on its
// timing), so they stay bit-identical for any thread count.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "params/schema/cost_params.h"
#include "params/schema/stability_params.h"
#include "tuning/optim/cost.h"
#include "tuning/sim/metrics.h"
#include "tuning/sim/scenario.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {

namespace exec {
class Executor;
class WorkerTask;
}  // namespace exec

struct SetEvaluation {
  std::vector<RunMetrics> runs;      ///< per scenario
  std::vector<CostBreakdown> costs;  ///< per scenario
  double total = 0.0;                ///< Σ weight · J
  std::string invalid;               ///< non-empty: the set was rejected (first problem)
};

/// Progress of one batch: (jobs finished, jobs in the batch). See the header comment.
using BatchProgress = std::function<void(int done, int total)>;

/// Runs already made, for the evaluators of one study to reuse (FromEntries' `memo`): a run is a
/// pure function of its scenario entry (name, file, overrides, folder, cost settings) and the
/// parameter set, so the run of a set an evaluator has made before, on any evaluator of the same
/// memo, is returned as it was, bit for bit, without running it again. A front's points whose
/// searches end on the same set, the exported set's evaluations across the export phases and the
/// base set beside every plant neighbour then run once. Keys are exact (the set's and the entry's
/// bytes). Bounded: beyond `max_sets` sets the memo forgets the set it learnt first (the export
/// phases ask again for the sets of the latest ones), which costs runs, never results.
/// Thread-safe.
class RunMemo {
 public:
  /// 2048 sets of ~30 runs: ~25 MB at most.
  static constexpr std::size_t kDefaultMaxSets = 2048;
  explicit RunMemo(std::size_t max_sets = kDefaultMaxSets)
      : max_sets_(max_sets > 0 ? max_sets : 1) {}
  /// The runs of set `set` on the scenarios `scenarios` (keys), if every one is known (false:
  /// `runs` and `invalid` hold nothing of use).
  bool Find(const std::string& set, const std::vector<std::string>& scenarios,
            std::vector<RunMetrics>* runs, std::vector<std::string>* invalid) const;
  /// Remembers runs[i] / invalid[i] of `set` on scenarios[i].
  void Store(const std::string& set, const std::vector<std::string>& scenarios,
             const RunMetrics* runs, const std::string* invalid);
  /// Runs returned from the memo so far, and runs stored (made) so far.
  long reused_runs() const;
  long made_runs() const;

 private:
  struct Run {
    RunMetrics metrics;
    std::string invalid;
  };
  mutable std::mutex mutex_;
  std::size_t max_sets_;
  std::unordered_map<std::string, std::unordered_map<std::string, Run>> runs_;  ///< set -> entry
  std::deque<const std::string*> order_;  ///< the keys of runs_, first learnt first
  mutable long reused_ = 0;
  long made_ = 0;
};

class BatchEvaluator {
 public:
  BatchEvaluator(std::vector<ResolvedScenario> scenarios, std::vector<double> weights,
                 params::CostWeights cost, int threads = 0);

  /// Resolves the entries of a set (training or held-out) in parallel; `progress` counts the
  /// resolved scenarios. `cache` (the caller's, shared by its evaluators) holds the prepared
  /// references; null: one of this call's own over the disk store. `memo` (null: none): the runs
  /// this evaluator makes are remembered there, and a set whose runs are all there is not run.
  static BatchEvaluator FromEntries(const std::vector<ScenarioEntry>& entries,
                                    const std::string& base_dir, const params::CostWeights& cost,
                                    int threads = 0, const BatchProgress& progress = {},
                                    controller::planning::ReferenceCache* cache = nullptr,
                                    std::shared_ptr<RunMemo> memo = nullptr);

  /// Every set on every scenario (sets.size() × scenarios jobs); `progress` counts the runs.
  std::vector<SetEvaluation> Evaluate(const std::vector<params::StabilityParams>& sets,
                                      const BatchProgress& progress = {}) const;
  SetEvaluation Evaluate(const params::StabilityParams& set) const;

  const std::vector<ResolvedScenario>& scenarios() const { return scenarios_; }
  const std::vector<double>& weights() const { return weights_; }
  const params::CostWeights& cost() const { return cost_; }
  int threads() const { return threads_; }

 private:
  /// Runs every set on every scenario into slots / invalid (set-major), calling job_done after
  /// each job.
  void Run(const std::vector<params::StabilityParams>& sets, std::vector<RunMetrics>* slots,
           std::vector<std::string>* invalid, const std::function<void()>& job_done) const;

  std::vector<ResolvedScenario> scenarios_;
  std::vector<double> weights_;
  params::CostWeights cost_;
  int threads_;
  std::shared_ptr<const exec::Executor> exec_;  ///< runs the jobs (threads, or MPI ranks)
  struct JobLengths;
  std::shared_ptr<JobLengths> lengths_;  ///< per scenario, for the job order (see above)
  std::shared_ptr<RunMemo> memo_;
  std::vector<std::string> memo_keys_;  ///< per scenario: its entry's key in memo_
};

/// Longest first: the job indices [0, lengths.size()) sorted by decreasing length, ties by index.
std::vector<int> LongestFirst(const std::vector<double>& lengths);

/// The remote side of an evaluator (task kind "evaluate"; scw's main registers it for MPI ranks).
std::unique_ptr<exec::WorkerTask> MakeEvaluatorWorkerTask(std::string_view setup, int threads);

}  // namespace scw::tuning
