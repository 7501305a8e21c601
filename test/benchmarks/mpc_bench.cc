// Solve time of the MPC motion controllers (controller/motion/pmpc.h, nmpc.h): one solver call
// per iteration, warm-started from the previous plan, driving along the reference of the default
// scenario (Yas Marina North, GG 1.0) with a small lateral and heading disturbance. Reported: time
// per solve (mean over the run) and, as counters, the median and max of the controller's own
// solve-time statistics and the mean Ipopt iterations. Run:
//   build/<preset>/test/scw_benchmarks --benchmark_filter=Mpc
#include <benchmark/benchmark.h>

#include <cmath>

#include "controller/motion/nmpc.h"
#include "controller/motion/pmpc.h"
#include "tuning/sim/motion_factory.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning {
namespace {

namespace cm = controller::motion;

const ResolvedScenario& Scenario(const std::string& name) {
  static const ResolvedScenario pmpc = Resolve(DefaultScenario({"motion.controller=pmpc"}));
  static const ResolvedScenario nmpc = Resolve(DefaultScenario({"motion.controller=nmpc"}));
  return name == "pmpc" ? pmpc : nmpc;
}

template <class Mpc>
void Run(benchmark::State& bench, const std::string& name, double solve_period) {
  const ResolvedScenario& sc = Scenario(name);
  const auto ctl = MakeMotionController(sc);
  auto base = ctl->MakeState();
  auto* st = static_cast<typename Mpc::State*>(base.get());
  double s = 100.0, t = 0.0;
  int i = 0;
  for (auto _ : bench) {
    const cm::PathPoint p = sc.path->Sample(s);
    const double n = 0.2 * std::sin(0.1 * i), dpsi = 0.01 * std::cos(0.13 * i);
    cm::MotionInput in;
    in.t = t;
    in.x = p.x - n * std::sin(p.psi);
    in.y = p.y + n * std::cos(p.psi);
    in.psi = p.psi + dpsi;
    in.v_x = p.v;
    in.yaw_rate = p.kappa * p.v;
    auto out = ctl->Step(in, base.get());
    benchmark::DoNotOptimize(out);
    s += p.v * solve_period;
    t += solve_period;
    ++i;
  }
  const auto& d = st->diagnostics;
  bench.counters["median_ms"] = 1e3 * d.solve_time.Median();
  bench.counters["max_ms"] = 1e3 * d.solve_time.max();
  bench.counters["iterations"] = double(d.iterations) / std::max<double>(1.0, d.solves);
  bench.counters["failures"] = static_cast<double>(d.failures);
}

void BM_MpcPointMassSolve(benchmark::State& bench) {
  // Step calls the QP only every solve_period: call it at that period so every call solves.
  Run<cm::PointMassMpc>(bench, "pmpc", cm::PmpcOptions{}.solve_period);
}
BENCHMARK(BM_MpcPointMassSolve)->Unit(benchmark::kMillisecond)->Iterations(600);

void BM_MpcSingleTrackSolve(benchmark::State& bench) {
  Run<cm::SingleTrackMpc>(bench, "nmpc", cm::NmpcOptions{}.sample_time);
}
BENCHMARK(BM_MpcSingleTrackSolve)->Unit(benchmark::kMillisecond)->Iterations(600);

}  // namespace
}  // namespace scw::tuning
