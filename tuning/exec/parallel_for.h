// The threads back end of the execution layer (executor.h), also usable alone: a deterministic
// parallel map. Job i is a pure function of its inputs and writes only slot i, so the results are
// bit-identical for any thread count (ecosystem spec §6). Workers claim positions from an atomic
// counter; exceptions are captured per job index and rethrown (the first by index) after every
// worker has joined, never from a worker thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <stdexcept>
#include <thread>
#include <vector>

#include "tuning/exec/mpi_backend.h"

namespace scw::tuning::exec {

/// Number of worker threads for `requested` (0 = all hardware threads; under MPI with more than
/// one rank: 1 per rank, the ranks being the parallelism), at least 1.
inline int ResolveThreads(int requested) {
  if (requested > 0) return requested;
  if (mpi::Ranks() > 1) return 1;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

/// Calls fn(i) for i in [0, n) on up to `threads` threads (0 = all cores, this thread included),
/// handing the jobs out in `order` (empty, or a permutation of [0, n): e.g. longest first; it
/// changes when a job runs, never its result).
template <class Fn>
void ParallelFor(int n, int threads, const std::vector<int>& order, Fn&& fn) {
  if (n <= 0) return;
  if (!order.empty() && order.size() != static_cast<std::size_t>(n))
    throw std::logic_error("job order of the wrong length");
  const int workers = std::min(ResolveThreads(threads), n);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
  std::atomic<int> next{0};
  auto work = [&] {
    for (int p = next.fetch_add(1); p < n; p = next.fetch_add(1)) {
      const int i = order.empty() ? p : order[static_cast<std::size_t>(p)];
      try {
        fn(i);
      } catch (...) {
        errors[static_cast<std::size_t>(i)] = std::current_exception();
      }
    }
  };
  if (workers == 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(workers - 1));
    for (int w = 1; w < workers; ++w) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
  }
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

/// Calls fn(i) for i in [0, n), in index order, on up to `threads` threads (0 = all cores).
template <class Fn>
void ParallelFor(int n, int threads, Fn&& fn) {
  ParallelFor(n, threads, std::vector<int>{}, std::forward<Fn>(fn));
}

}  // namespace scw::tuning::exec
