// Google Benchmark: one plant step (EAV24 set) and the tyre model alone.
#include <benchmark/benchmark.h>

#include <cmath>

#include "params/schema/vehicle_params.h"
#include "plant/tire/magic_formula.h"
#include "plant/vehicle/maneuver.h"
#include "plant/vehicle/vehicle.h"

namespace {

// Steps the reference manoeuvre; the state is reset every 60 s simulated so all its phases recur.
void BM_PlantStep(benchmark::State& state) {
  const scw::params::VehicleParams p;
  const scw::plant::Vehicle v(p);
  scw::plant::State s = v.MakeState();
  const scw::plant::State start = s;
  const double radius = p.wheels.radius_rear;
  for (auto _ : state) {
    const scw::plant::Measurement m = v.Measure(s);
    v.Step(scw::plant::ReferenceManeuverInput(s.time, m, radius), &s);
    if (s.time > 60.0) {
      state.PauseTiming();
      s = start;
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(s.x);
  }
  state.counters["real_time_factor"] = benchmark::Counter(
      v.time_step() * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PlantStep);

void BM_TireForces(benchmark::State& state) {
  const scw::params::Mf52Params t;
  double k = 0.0;
  for (auto _ : state) {
    k = k > 0.2 ? -0.2 : k + 1e-4;
    benchmark::DoNotOptimize(scw::plant::TireForces({3000.0, k, 0.5 * k, 1.0, 1.0}, t));
  }
}
BENCHMARK(BM_TireForces);

}  // namespace
