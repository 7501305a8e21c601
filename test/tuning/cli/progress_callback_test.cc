// The batch runners' progress callbacks (issue 15) only observe: every call reports one more
// finished job (never two calls at once, `done` counting up to the total), and the results with
// a callback on two threads are bit-identical to those without one on one thread.
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "tuning/optim/evaluator.h"
#include "tuning/sweep/sweep.h"

namespace scw::tuning {
namespace {

std::vector<ScenarioEntry> TwoShortScenarios() {
  return {{"nominal", 1.0, "", {"laps=1", "gg_scale=1.1"}},
          {"slower", 1.0, "", {"laps=1", "gg_scale=1.0"}}};
}

/// Records the calls and fails on overlapping ones.
struct Recorder {
  std::vector<std::pair<int, int>> calls;
  std::atomic<int> inside{0};
  bool overlapped = false;
  void operator()(int done, int total) {
    if (inside.fetch_add(1) != 0) overlapped = true;
    calls.emplace_back(done, total);
    inside.fetch_sub(1);
  }
};

void ExpectCountsUp(const Recorder& r, int total) {
  EXPECT_FALSE(r.overlapped);
  ASSERT_EQ(r.calls.size(), static_cast<std::size_t>(total));
  for (int k = 0; k < total; ++k) {
    EXPECT_EQ(r.calls[static_cast<std::size_t>(k)].first, k + 1);
    EXPECT_EQ(r.calls[static_cast<std::size_t>(k)].second, total);
  }
}

TEST(ProgressCallbackTest, EvaluatorReportsEveryJobAndResultsDoNotChange) {
  const params::CostWeights w;
  Recorder prepared, ran;
  const auto observed = BatchEvaluator::FromEntries(TwoShortScenarios(), "", w, 2,
                                                    [&](int d, int t) { prepared(d, t); });
  ExpectCountsUp(prepared, 2);
  params::StabilityParams a, b;
  b.ESC.kp_psi_dot = 4.0;
  const std::vector<params::StabilityParams> sets = {a, b};
  const auto with = observed.Evaluate(sets, [&](int d, int t) { ran(d, t); });
  ExpectCountsUp(ran, 4);

  const auto plain = BatchEvaluator::FromEntries(TwoShortScenarios(), "", w, 1);
  const auto without = plain.Evaluate(sets);
  ASSERT_EQ(with.size(), without.size());
  for (std::size_t s = 0; s < with.size(); ++s) {
    EXPECT_EQ(with[s].total, without[s].total);
    for (std::size_t k = 0; k < with[s].runs.size(); ++k) {
      EXPECT_EQ(with[s].runs[k].lap_times, without[s].runs[k].lap_times);
      EXPECT_EQ(with[s].runs[k].max_abs_sideslip, without[s].runs[k].max_abs_sideslip);
      EXPECT_EQ(with[s].runs[k].esc_brake_energy, without[s].runs[k].esc_brake_energy);
    }
  }
}

TEST(ProgressCallbackTest, SweepReportsItsRunsAndResultsDoNotChange) {
  sweep::SweepDefinition d;
  d.base_overrides = {"laps=1"};
  d.axes = {sweep::ParseVary("gg_scale=1.0,1.1")};
  sweep::SweepExecution exec;
  exec.threads = 2;
  std::vector<sweep::SweepProgress> calls;
  std::atomic<int> inside{0};
  bool overlapped = false;
  exec.on_progress = [&](const sweep::SweepProgress& p) {
    if (inside.fetch_add(1) != 0) overlapped = true;
    calls.push_back(p);
    inside.fetch_sub(1);
  };
  const sweep::SweepResult with = sweep::RunSweep(d, exec);
  const sweep::SweepResult without = sweep::RunSweep(d, 1);

  EXPECT_FALSE(overlapped);
  ASSERT_EQ(calls.size(), 3u);  // the start, then one call per run
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(calls[static_cast<std::size_t>(k)].phase, "run");
    EXPECT_EQ(calls[static_cast<std::size_t>(k)].done, k);
    EXPECT_EQ(calls[static_cast<std::size_t>(k)].total, 2);
  }
  ASSERT_EQ(with.runs.size(), without.runs.size());
  for (std::size_t i = 0; i < with.runs.size(); ++i) {
    EXPECT_EQ(with.runs[i].metrics.lap_times, without.runs[i].metrics.lap_times);
    EXPECT_EQ(with.runs[i].metrics.max_abs_sideslip, without.runs[i].metrics.max_abs_sideslip);
    EXPECT_EQ(with.runs[i].ideal_lap_time, without.runs[i].ideal_lap_time);
  }
}

}  // namespace
}  // namespace scw::tuning
