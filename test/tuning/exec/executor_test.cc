// The execution layer's one interface (tuning/exec/executor.h): the same batch on threads and on
// worker processes (test_worker.cc serves the task) gives the same slots, in index order, for any
// worker count and hand-out order; errors come back the first by index after the batch; a worker
// that dies ends the batch naming its job. The MPI back end runs end to end in mpi_test.sh.
#include "tuning/exec/executor.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace scw::tuning::exec {
namespace {

constexpr double kFactor = 0.1;  // not exact in binary: the text must carry every bit

double Affine(int i, double offset) { return kFactor * i + offset; }

Options Threads(int n) {
  Options o;
  o.threads = n;
  return o;
}

Options Processes(int n) {
  Options o;
  o.processes = n;
  o.worker_command = {SCW_TEST_WORKER};
  return o;
}

std::unique_ptr<Executor> Make(const Options& o) {
  return std::make_unique<Executor>(o, "affine", [] { return std::string("0.1"); });
}

// Runs `jobs` jobs with `offset`; job `throw_at` throws, the worker dies at `die_at` (-1: none).
std::vector<double> RunBatch(const Executor& ex, int jobs, double offset,
                             const std::vector<int>& order = {}, int throw_at = -1,
                             int die_at = -1) {
  std::vector<double> slots(static_cast<std::size_t>(jobs), -1.0);
  Batch b;
  b.jobs = jobs;
  b.order = order;
  b.local = [&](int i) {
    if (i == throw_at) throw std::runtime_error("job " + std::to_string(i) + " failed");
    slots[static_cast<std::size_t>(i)] = Affine(i, offset);
  };
  char payload[64];
  std::snprintf(payload, sizeof payload, "%a %d %d", offset, throw_at, die_at);
  b.payload = payload;
  b.remote = [&](int i, std::string_view bytes) {
    slots[static_cast<std::size_t>(i)] = std::strtod(std::string(bytes).c_str(), nullptr);
  };
  b.label = [](int i) { return "affine job " + std::to_string(i); };
  ex.Run(b);
  return slots;
}

TEST(ExecutorTest, EveryBackEndFillsTheSameSlotsInIndexOrder) {
  const int n = 23;
  std::vector<int> reversed(n);
  std::iota(reversed.rbegin(), reversed.rend(), 0);
  const auto threads = Make(Threads(1));
  ASSERT_EQ(threads->backend(), Backend::kThreads);
  const std::vector<double> expected = RunBatch(*threads, n, 1.0 / 3.0);
  for (int i = 0; i < n; ++i)
    EXPECT_EQ(expected[static_cast<std::size_t>(i)], Affine(i, 1.0 / 3.0));
  EXPECT_EQ(RunBatch(*Make(Threads(3)), n, 1.0 / 3.0, reversed), expected);
  for (const int p : {1, 2, 3}) {
    const auto ex = Make(Processes(p));
    ASSERT_EQ(ex->backend(), Backend::kProcesses);
    EXPECT_EQ(ex->workers(), p);
    EXPECT_EQ(RunBatch(*ex, n, 1.0 / 3.0), expected) << p << " processes";
    EXPECT_EQ(RunBatch(*ex, n, 1.0 / 3.0, reversed), expected) << p << " processes, reversed";
    // A second batch with another payload on the same workers.
    EXPECT_EQ(RunBatch(*ex, 5, 2.0), RunBatch(*threads, 5, 2.0)) << p << " processes";
    EXPECT_NO_THROW(ex->Finish());
  }
}

TEST(ExecutorTest, AFailedJobIsRethrownAfterTheBatchWithTheOthersDone) {
  for (const Options& o : {Threads(2), Processes(2)}) {
    const auto ex = Make(o);
    std::vector<double> slots;
    try {
      (void)RunBatch(*ex, 10, 0.0, {}, 3);
      ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "job 3 failed");
    }
    // The executor serves the next batch.
    EXPECT_EQ(RunBatch(*ex, 4, 0.5), RunBatch(*Make(Threads(1)), 4, 0.5));
  }
}

TEST(ExecutorTest, AWorkerThatDiesEndsTheBatchNamingItsJob) {
  const auto ex = Make(Processes(2));
  try {
    (void)RunBatch(*ex, 10, 0.0, {}, -1, 4);
    ADD_FAILURE() << "no error";
  } catch (const WorkerError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("exited with code 3 while computing affine job 4"), std::string::npos)
        << what;
  }
}

TEST(ExecutorTest, WorkerProcessesNeedACommandThatServesTheKind) {
  Options none;
  none.processes = 1;
  EXPECT_THROW(Make(none), std::invalid_argument);
  const auto ex =
      std::make_unique<Executor>(Processes(1), "no_such_kind", [] { return std::string(); });
  try {
    (void)RunBatch(*ex, 2, 0.0);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no task kind 'no_such_kind'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace scw::tuning::exec
