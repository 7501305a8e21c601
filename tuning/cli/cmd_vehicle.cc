// scw vehicle gg|init|validate — vehicle parameter sets of the plant (params/vehicles/*.yaml).
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/vehicle_params.h"
#include "plant/vehicle/ggv.h"
#include "tuning/cli/command.h"

namespace scw::cli {
namespace {

struct VehicleOptions {
  std::string vehicle;
  std::vector<double> speeds = {10, 20, 30, 40, 50, 60, 70, 80};
  bool csv = false;
  std::string out;
};

params::VehicleParams LoadVehicle(const std::string& path) {
  return path.empty() ? params::VehicleParams{}
                      : params::LoadPlainFile<params::VehicleParams>(path);
}

int Gg(const VehicleOptions& o) {
  const params::VehicleParams p = LoadVehicle(o.vehicle);
  for (double v : o.speeds)
    if (!(v > 0.5 && v < 200.0)) {
      std::cerr << "error: --speeds: " << v << " m/s is outside (0.5, 200)\n";
      return kExitBadInput;
    }
  const auto table = plant::ComputeGgv(p, o.speeds);
  if (o.csv) {
    std::cout
        << "speed_mps,lateral_max_mps2,braking_max_mps2,traction_max_mps2,lateral_lock_limited\n";
    for (const auto& g : table)
      std::cout << params::FormatDouble(g.speed) << ',' << params::FormatDouble(g.lateral_max)
                << ',' << params::FormatDouble(g.braking_max) << ','
                << params::FormatDouble(g.traction_max) << ',' << (g.lateral_lock_limited ? 1 : 0)
                << '\n';
    return kExitOk;
  }
  std::cout << "steady-state g-g-v limits of the plant '" << p.name << "'"
            << (o.vehicle.empty() ? " (built-in defaults)" : " (" + o.vehicle + ")") << "\n"
            << "accelerations are body-frame specific forces; braking includes drag, traction is\n"
            << "net of drag (0 = speed not reachable); lateral at constant speed (a_x = 0)\n\n"
            << "  speed [m/s]   lateral [m/s^2]   braking [m/s^2]   traction [m/s^2]\n";
  bool lock = false;
  for (const auto& g : table) {
    char line[128];
    std::snprintf(line, sizeof line, "  %10.1f   %14.2f%s   %15.2f   %16.2f\n", g.speed,
                  g.lateral_max, g.lateral_lock_limited ? "*" : " ", g.braking_max, g.traction_max);
    std::cout << line;
    lock |= g.lateral_lock_limited;
  }
  if (lock) std::cout << "\n  * bounded by the steering lock, not by the tyres\n";
  return kExitOk;
}

void AddVehicle(CLI::App& app) {
  auto* cmd = app.add_subcommand("vehicle", "Vehicle parameter sets of the plant");
  cmd->require_subcommand(1, 1);
  auto o = std::make_shared<VehicleOptions>();

  auto* gg = cmd->add_subcommand(
      "gg",
      "Print the steady-state g-g-v limits the plant reaches (max lateral, braking and traction "
      "acceleration per speed), found by simulating the plant");
  gg->add_option("--vehicle", o->vehicle,
                 "Vehicle file (params/vehicles/*.yaml); default: the built-in EAV24 set")
      ->check(CLI::ExistingFile);
  gg->add_option("--speeds", o->speeds, "Speeds [m/s] (default 10 20 ... 80)")
      ->delimiter(',')
      ->expected(1, -1);
  gg->add_flag("--csv", o->csv, "CSV output (speed_mps, lateral/braking/traction in m/s^2)");
  gg->callback([o] { SetExitCode(Gg(*o)); });

  auto* init =
      cmd->add_subcommand("init", "Write the built-in vehicle set (EAV24/25 class) as plain YAML");
  init->add_option("-o,--output", o->out, "Output file (e.g. params/vehicles/eav24.yaml)")
      ->required();
  init->callback([o] {
    params::WriteFileAtomic(
        o->out,
        params::ToPlainYaml(
            params::VehicleParams{},
            "EAV24/25-class car (A2RL, Dallara SF23 based): the plant's built-in default set.\n"
            "Public estimates, no validated set exists; every field's source or assumption is in\n"
            "params/schema/vehicle_params.h. Tyre friction scalings calibrated so the plant "
            "reaches\n"
            "29.5 m/s^2 lateral and 29.2 m/s^2 braking at 70 m/s (the paper's real-car maxima).\n"
            "Regenerate: scw vehicle init -o params/vehicles/eav24.yaml"));
    std::cerr << "wrote " << o->out << '\n';
    SetExitCode(kExitOk);
  });

  auto* val = cmd->add_subcommand("validate", "Strictly load a vehicle file (exit 2 on problems)");
  val->add_option("FILE", o->vehicle, "Vehicle file")->required()->check(CLI::ExistingFile);
  val->callback([o] {
    const auto p = LoadVehicle(o->vehicle);
    std::cout << o->vehicle << ": ok (" << p.name << ")\n";
    SetExitCode(kExitOk);
  });
}

const CommandRegistrar kRegistrar(20, &AddVehicle);

}  // namespace
}  // namespace scw::cli
