// One full StabilityController::Step (slip estimation, μ map, ESC, ABS/TC slip control,
// countersteer) on realistic inputs. Reported: time per step. Run:
//   build/controller/test/scw_benchmarks --benchmark_filter=StabilityController
// Also the path matching of the motion controllers (Path::Project with the local window of pure
// pursuit): --benchmark_filter=PathProject
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "controller/motion/path.h"
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

/// One Path::Project per iteration as pure pursuit calls it: a car 0.3 m beside a 3 km closed
/// line with a station every metre, 0.5 m further at each call (so it crosses the start line),
/// the last match as the hint and pure pursuit's 20 m window. The poses are made beforehand.
void BM_PathProject(benchmark::State& bench) {
  const int n = 3000;
  const double r = n / (2 * M_PI);
  std::vector<motion::PathPoint> pts(n);
  for (int i = 0; i < n; ++i) {
    const double th = i / r, rr = r * (1.0 + 0.1 * std::sin(4 * th));
    pts[i] = {double(i), rr * std::cos(th), rr * std::sin(th), th + M_PI / 2, 1 / r, 30.0, 0.0};
  }
  const motion::Path path(std::move(pts), double(n));
  struct Pose {
    double x, y, psi;
  };
  std::vector<Pose> poses(2 * n);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const motion::PathPoint on = path.Sample(0.5 * double(k));
    poses[k] = {on.x - 0.3 * std::sin(on.psi), on.y + 0.3 * std::cos(on.psi), on.psi + 0.02};
  }
  double hint = 0.0;
  std::size_t k = 0;
  for (auto _ : bench) {
    const Pose& q = poses[k];
    const motion::PathProjection m = path.Project(q.x, q.y, q.psi, hint, 20.0);
    hint = m.s;
    benchmark::DoNotOptimize(m);
    if (++k == poses.size()) k = 0;
  }
  bench.SetItemsProcessed(bench.iterations());
}
BENCHMARK(BM_PathProject);

}  // namespace
}  // namespace scw::controller
