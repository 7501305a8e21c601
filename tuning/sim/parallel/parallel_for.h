// Deterministic parallel map: job i is a pure function of its inputs and writes only slot i, so
// the results are bit-identical for any thread count (ecosystem spec §6). Workers claim indices
// from an atomic counter; exceptions are captured per index and rethrown (the first by index)
// after every worker has joined, never from a worker thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

#include "tuning/sim/parallel/mpi_backend.h"

namespace scw::tuning {

/// Number of worker threads for `requested` (0 = all hardware threads; under MPI with more than
/// one rank: 1 per rank, the ranks being the parallelism), at least 1.
inline int ResolveThreads(int requested) {
  if (requested > 0) return requested;
  if (mpi::Ranks() > 1) return 1;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

/// Calls fn(i) for i in [0, n) on up to `threads` threads (0 = all cores).
template <class Fn>
void ParallelFor(int n, int threads, Fn&& fn) {
  if (n <= 0) return;
  const int workers = std::min(ResolveThreads(threads), n);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
  std::atomic<int> next{0};
  auto work = [&] {
    for (int i = next.fetch_add(1); i < n; i = next.fetch_add(1)) {
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

}  // namespace scw::tuning
