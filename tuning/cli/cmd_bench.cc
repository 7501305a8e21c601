// scw bench --plant [...] — wall-clock speed of the simulation parts on one core.
// Each mode flag runs one workload; more modes (e.g. --closed-loop) are added as flags here.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "params/io/load.h"
#include "params/schema/vehicle_params.h"
#include "plant/vehicle/maneuver.h"
#include "plant/vehicle/vehicle.h"
#include "tuning/cli/command.h"

namespace scw::cli {
namespace {

struct BenchOptions {
  bool plant = false;
  std::string vehicle;
  double duration = 600.0;
  int repeat = 3;
};

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

// The plant alone, single thread: the reference manoeuvre (plant/vehicle/maneuver.h) from rest,
// best of `repeat` runs (the machine is shared; the best run is the least disturbed one).
int BenchPlant(const BenchOptions& o) {
  const params::VehicleParams p = o.vehicle.empty()
                                      ? params::VehicleParams{}
                                      : params::LoadPlainFile<params::VehicleParams>(o.vehicle);
  const plant::Vehicle v(p);
  double best = 1e300;
  plant::ManeuverSummary sum;
  for (int r = 0; r < o.repeat; ++r) {
    plant::State s = v.MakeState();
    const auto t0 = std::chrono::steady_clock::now();
    sum = plant::RunReferenceManeuver(v, o.duration, &s);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    best = std::min(best, wall);
  }
  if (sum.status != plant::kStatusOk) {
    std::cerr << "error: the plant run ended with status " << sum.status << '\n';
    return kExitFailed;
  }
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "plant '%s', reference manoeuvre, %.0f s simulated, %ld steps of %.3g ms, "
                "1 thread, best of %d\n"
                "cpu: %s\n"
                "wall time: %.4f s, %.3f us/step (distance %.0f m, max |a_y| %.1f m/s^2)\n",
                p.name.c_str(), sum.sim_time, sum.steps, 1e3 * v.time_step(), o.repeat,
                CpuModel().c_str(), best, 1e6 * best / static_cast<double>(sum.steps), sum.distance,
                sum.max_abs_ay);
  std::cout << buf << "real-time factor: " << static_cast<long>(sum.sim_time / best) << '\n';
  return kExitOk;
}

void AddBench(CLI::App& app) {
  auto* cmd = app.add_subcommand("bench", "Measure simulation speed (wall clock, one core)");
  auto o = std::make_shared<BenchOptions>();
  cmd->add_flag("--plant", o->plant,
                "The plant alone driving its reference manoeuvre; prints 'real-time factor: N'");
  cmd->add_option("--vehicle", o->vehicle, "Vehicle file (default: built-in EAV24 set)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--duration", o->duration, "Simulated time per run [s]")
      ->check(CLI::Range(1.0, 1e6));
  cmd->add_option("--repeat", o->repeat, "Runs; the fastest is reported")
      ->check(CLI::Range(1, 100));
  cmd->callback([o] {
    if (!o->plant) {
      std::cerr << "error: choose what to measure, e.g. scw bench --plant\n";
      SetExitCode(kExitBadInput);
      return;
    }
    SetExitCode(BenchPlant(*o));
  });
}

const CommandRegistrar kRegistrar(90, &AddBench);

}  // namespace
}  // namespace scw::cli
