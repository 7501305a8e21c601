// `scw replay` speed (issue 10): a 10-minute log at 100 Hz (60 000 rows of the synthetic lap of
// test/tuning/replay/log_stories.h, every subsystem intervening) read, stepped through the
// stability controller and its outputs written (atomically, with fsync) — the whole command
// without the params loading. The log is written to a temporary file once. Reported: time per
// replay of the full log. Run:
//   build/<dir>/test/scw_benchmarks --benchmark_filter=Replay
#include <benchmark/benchmark.h>

#include "test/tuning/replay/log_stories.h"
#include "tuning/replay/replay.h"

namespace scw::tuning::replay {
namespace {

constexpr long kRows = 60000;  // 10 min at 100 Hz

class ReplayFixture {
 public:
  ReplayFixture() : dir_("scw_replay_bench") {
    ControllerLogWriter log(dir_.File("log.csv"));
    for (long k = 0; k < kRows; ++k) log.Write(testing::SyntheticRow(p_, k));
    log.Commit();
  }
  std::string Log() const { return dir_.File("log.csv"); }
  std::string Out() const { return dir_.File("out.csv"); }
  const params::StabilityParams& params() const { return p_; }

 private:
  params::StabilityParams p_;
  testing::TempDir dir_;
};

const ReplayFixture& Fixture() {
  static const ReplayFixture f;
  return f;
}

void BM_Replay10MinLogWithOutput(benchmark::State& bench) {
  const ReplayFixture& f = Fixture();
  const controller::StabilityController c(f.params());
  for (auto _ : bench) {
    const ReplaySummary s = ReplayLog(f.Log(), c, f.Out());
    benchmark::DoNotOptimize(s.rows);
  }
  bench.SetItemsProcessed(bench.iterations() * kRows);
}
BENCHMARK(BM_Replay10MinLogWithOutput)->Unit(benchmark::kMillisecond);

void BM_Replay10MinLogSummaryOnly(benchmark::State& bench) {
  const ReplayFixture& f = Fixture();
  const controller::StabilityController c(f.params());
  for (auto _ : bench) {
    const ReplaySummary s = ReplayLog(f.Log(), c);
    benchmark::DoNotOptimize(s.rows);
  }
  bench.SetItemsProcessed(bench.iterations() * kRows);
}
BENCHMARK(BM_Replay10MinLogSummaryOnly)->Unit(benchmark::kMillisecond);

void BM_Compare10MinLog(benchmark::State& bench) {
  const ReplayFixture& f = Fixture();
  params::StabilityParams halved = f.params();
  for (double& x : halved.ESC.beta_threshold_activate) x *= 0.5;
  const controller::StabilityController a(f.params());
  const controller::StabilityController b(halved);
  for (auto _ : bench) {
    const ComparisonSummary s = CompareOnLog(f.Log(), a, b);
    benchmark::DoNotOptimize(s.differing_rows);
  }
  bench.SetItemsProcessed(bench.iterations() * kRows);
}
BENCHMARK(BM_Compare10MinLog)->Unit(benchmark::kMillisecond);

/// Reading and parsing alone (no controller).
void BM_ReadControllerLog10Min(benchmark::State& bench) {
  const ReplayFixture& f = Fixture();
  for (auto _ : bench) {
    ControllerLogReader r(f.Log());
    controller::StabilityInput in;
    while (r.Next(&in)) benchmark::DoNotOptimize(in.t);
  }
  bench.SetItemsProcessed(bench.iterations() * kRows);
}
BENCHMARK(BM_ReadControllerLog10Min)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace scw::tuning::replay
