// One full StabilityController::Step (slip estimation, μ map, ESC, ABS/TC slip control,
// countersteer) on realistic inputs. Reported: time per step. Run:
//   build/controller/test/scw_benchmarks --benchmark_filter=StabilityController
#include <benchmark/benchmark.h>

#include <vector>

#include "controller/stability/stability_controller.h"
#include "test/controller/stability/scenario_inputs.h"

namespace scw::controller {
namespace {

/// A 4 s loop of cruise, oversteer slide (ESC + countersteer active), braking lock-up (ABS) and
/// rear-wheel spin (TC), replayed cyclically so every branch of the step is timed.
std::vector<StabilityInput> MixedEpisode(const params::StabilityParams& p) {
  std::vector<StabilityInput> v;
  int t = 0;
  for (int k = 0; k < 50; ++k, ++t) v.push_back(testing::Cruise(p, 0.01 * t));
  for (int k = 0; k < 100; ++k, ++t) v.push_back(testing::Oversteer(p, 0.01 * t));
  for (int k = 0; k < 50; ++k, ++t) v.push_back(testing::Cruise(p, 0.01 * t, 40.0));
  for (int k = 0; k < 100; ++k, ++t) v.push_back(testing::Lockup(p, 0.01 * t, k));
  for (int k = 0; k < 100; ++k, ++t) v.push_back(testing::RearSpin(p, 0.01 * t));
  return v;
}

void BM_StabilityControllerStep(benchmark::State& bench) {
  const params::StabilityParams p;
  const StabilityController controller(p);
  const auto inputs = MixedEpisode(p);
  StabilityController::State s;
  std::size_t i = 0;
  double time_offset = 0.0;
  for (auto _ : bench) {
    StabilityInput in = inputs[i];
    in.t += time_offset;  // keep simulation time increasing across laps of the episode
    auto out = controller.Step(in, &s);
    benchmark::DoNotOptimize(out);
    if (++i == inputs.size()) {
      i = 0;
      time_offset += 0.01 * static_cast<double>(inputs.size());
    }
  }
  bench.SetItemsProcessed(bench.iterations());
}
BENCHMARK(BM_StabilityControllerStep);

void BM_StabilityControllerStepCruise(benchmark::State& bench) {
  const params::StabilityParams p;
  const StabilityController controller(p);
  StabilityController::State s;
  StabilityInput in = testing::Cruise(p, 0.0);
  for (auto _ : bench) {
    in.t += 0.01;
    auto out = controller.Step(in, &s);
    benchmark::DoNotOptimize(out);
  }
  bench.SetItemsProcessed(bench.iterations());
}
BENCHMARK(BM_StabilityControllerStepCruise);

}  // namespace
}  // namespace scw::controller
