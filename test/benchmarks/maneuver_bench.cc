// Google Benchmark: each standard maneuver of `scw maneuver` on the built-in car with the car's
// set (tuning/maneuver/maneuver.h), the car resolved once. The suite's budget (docs/maneuvers.md):
// each maneuver under a second of wall time, all of them under a minute.
#include <benchmark/benchmark.h>

#include <string>

#include "tuning/maneuver/maneuver.h"

namespace {

void BM_Maneuver(benchmark::State& state, const std::string& name, const std::string& extra) {
  std::vector<std::string> sets = {"kind=maneuver", "maneuver.name=" + name};
  if (!extra.empty()) sets.push_back(extra);
  const scw::tuning::ResolvedScenario sc = scw::tuning::Resolve(scw::tuning::DefaultScenario(sets));
  double simulated = 0.0;
  for (auto _ : state) {
    const scw::tuning::ManeuverResult r = scw::tuning::RunManeuver(sc, sc.stability);
    simulated = 0.0;
    for (const auto& run : r.runs) simulated += run.signals.t.size() * sc.stability.tS;
    benchmark::DoNotOptimize(r.runs.size());
  }
  state.counters["simulated_s"] = simulated;
}

BENCHMARK_CAPTURE(BM_Maneuver, sine_with_dwell_80kmh, std::string("sine_with_dwell"), "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, sine_with_dwell_40mps, std::string("sine_with_dwell"),
                  "maneuver.speed=40")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, step_steer, std::string("step_steer"), "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, steady_state_circular, std::string("steady_state_circular"), "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, braking_in_turn, std::string("braking_in_turn"), "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, power_off_in_turn, std::string("power_off_in_turn"), "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, power_on_in_turn, std::string("power_on_in_turn"), "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, split_mu_braking, std::string("split_mu_braking"), "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, split_mu_acceleration, std::string("split_mu_acceleration"), "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Maneuver, mu_jump_acceleration, std::string("mu_jump_acceleration"), "")
    ->Unit(benchmark::kMillisecond);

}  // namespace
