// scw vehicle gg|init|validate — vehicle parameter sets of the plant (params/vehicles/*.yaml).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "controller/planning/envelope.h"
#include "params/io/atomic_file.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/vehicle_params.h"
#include "plant/actuator/actuators.h"
#include "plant/tire/magic_formula.h"
#include "plant/vehicle/ggv.h"
#include "plant/vehicle/quasi_steady.h"
#include "tuning/cli/command.h"
#include "tuning/cli/options.h"
#include "tuning/sim/plant_choice.h"
#include "tuning/sim/plant_variation.h"
#include "tuning/sim/scenario.h"

namespace scw::cli {
namespace {

struct VehicleOptions {
  std::string vehicle;
  std::string track;
  double brake_bias_front = 0.58;
  std::vector<double> speeds = {10, 20, 30, 40, 50, 60, 70, 80};
  bool csv = false;
  std::string csv_file;  ///< gg, balance, envelope: -o FILE (the CSV table into a file)
  std::string out;
  double brake_dead_time = -1.0;  ///< balance: also show this split (< 0: not asked)
};

params::VehicleParams LoadVehicle(const std::string& path) {
  return path.empty() ? params::VehicleParams{}
                      : params::LoadPlainFile<params::VehicleParams>(path);
}

void CheckSpeeds(const std::vector<double>& speeds, const std::string& cmd) {
  for (double v : speeds)
    if (!(v > 0.5 && v < 200.0))
      throw ConfigError(cmd, "--speeds",
                        params::FormatNumber(v) + " m/s is outside (0.5, 200) m/s");
}

int Gg(const VehicleOptions& o, const std::string& cmd) {
  const params::VehicleParams p = LoadVehicle(o.vehicle);
  CheckSpeeds(o.speeds, cmd);
  std::vector<plant::GgvPoint> table;
  for (double v : o.speeds) table.push_back(plant::ComputeGgvPoint(p, v));
  if (o.csv || !o.csv_file.empty()) {
    std::ostringstream buffer;
    std::ostream& csv = o.csv_file.empty() ? std::cout : buffer;
    csv << "speed_mps,lateral_max_mps2,braking_max_mps2,traction_max_mps2,lateral_lock_limited\n";
    for (const auto& g : table)
      csv << params::FormatDouble(g.speed) << ',' << params::FormatDouble(g.lateral_max) << ','
          << params::FormatDouble(g.braking_max) << ',' << params::FormatDouble(g.traction_max)
          << ',' << (g.lateral_lock_limited ? 1 : 0) << '\n';
    if (!o.csv_file.empty()) io::WriteFileAtomic(o.csv_file, buffer.str());
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

int Balance(const VehicleOptions& o, const std::string& cmd) {
  const params::VehicleParams p = LoadVehicle(o.vehicle);
  CheckSpeeds(o.speeds, cmd);
  // The same total brake response with another dead time (the scenario key
  // plant.brake_dead_time), checked before anything is printed.
  params::BrakeParams split = p.brakes;
  if (o.brake_dead_time >= 0.0) {
    try {
      split = tuning::BrakesWithDeadTime(p.brakes, p.simulation.time_step, o.brake_dead_time);
    } catch (const ConfigError& e) {
      std::vector<Problem> problems;
      for (const Problem& pr : e.problems()) problems.push_back({"--brake-dead-time", pr.message});
      throw ConfigError(cmd, std::move(problems));
    }
  }
  const plant::QuasiSteadyModel qs(p);
  const auto& tf = p.tires.front;
  const auto& tr = p.tires.rear;
  const auto mf = plant::PeakFriction(tf.fnomin, 1.0, 1.0, tf);
  const auto mr = plant::PeakFriction(tr.fnomin, 1.0, 1.0, tr);
  if (o.csv || !o.csv_file.empty()) {
    std::ostringstream buffer;
    std::ostream& csv = o.csv_file.empty() ? std::cout : buffer;
    csv << "speed_mps,understeer_gradient_mrad_per_mps2,lateral_max_mps2,drive_max_mps2,"
           "brake_max_mps2\n";
    for (double v : o.speeds)
      csv << params::FormatDouble(v) << ',' << params::FormatDouble(1e3 * qs.UndersteerGradient(v))
          << ',' << params::FormatDouble(qs.MaxLateral(v)) << ','
          << params::FormatDouble(qs.MaxDrive(v, 0.0)) << ','
          << params::FormatDouble(qs.MaxBrake(v, 0.0)) << '\n';
    if (!o.csv_file.empty()) io::WriteFileAtomic(o.csv_file, buffer.str());
    return kExitOk;
  }
  char line[200];
  std::cout << "quasi-steady balance and limits of the plant '" << p.name << "'"
            << (o.vehicle.empty() ? " (built-in defaults)" : " (" + o.vehicle + ")") << "\n";
  std::snprintf(line, sizeof line,
                "tyre friction at nominal load: front mu_x %.3f mu_y %.3f (ratio %.3f), rear "
                "mu_x %.3f mu_y %.3f (ratio %.3f)\n\n",
                mf.mu_x, mf.mu_y, mf.mu_x / mf.mu_y, mr.mu_x, mr.mu_y, mr.mu_x / mr.mu_y);
  std::cout << line;
  std::snprintf(line, sizeof line,
                "brake actuator: 63 %% of an 80 bar step after %.0f ms (dead time %.0f ms, lag "
                "%.0f ms, rate limit %.0f bar/s)\n",
                1e3 * plant::BrakeStepResponseTime(p.brakes, p.simulation.time_step),
                1e3 * p.brakes.delay, 1e3 * p.brakes.time_constant, p.brakes.rate_limit);
  std::cout << line;
  if (o.brake_dead_time >= 0.0) {
    std::snprintf(line, sizeof line,
                  "  with dead time %.1f ms: lag %.1f ms keeps 63 %% at %.0f ms (feasible dead "
                  "times 0-%.0f ms)\n",
                  1e3 * split.delay, 1e3 * split.time_constant,
                  1e3 * plant::BrakeStepResponseTime(split, p.simulation.time_step),
                  1e3 * tuning::FeasibleBrakeDeadTimes(p.brakes, p.simulation.time_step).max);
    std::cout << line;
  }
  std::cout << "\n"
            << "  speed [m/s]   understeer gradient [mrad/(m/s^2)]   lateral   drive   brake "
               "[m/s^2]\n";
  bool beyond_top_speed = false;
  for (double v : o.speeds) {
    const double k = qs.UndersteerGradient(v);
    char gradient[40];
    if (std::isnan(k)) {
      beyond_top_speed = true;
      std::snprintf(gradient, sizeof gradient, "%33s", "n/a (*)");
    } else {
      std::snprintf(gradient, sizeof gradient, "%33.2f", 1e3 * k);
    }
    std::snprintf(line, sizeof line, "  %10.1f   %s   %7.2f   %5.2f   %5.2f\n", v, gradient,
                  qs.MaxLateral(v), qs.MaxDrive(v, 0.0), qs.MaxBrake(v, 0.0));
    std::cout << line;
  }
  std::cout << "\n  understeer gradient: d(steer)/d(a_y) - l/v^2 at small a_y (> 0 understeers);\n"
               "  limits: quasi-steady double track with the car's brake bias and differential\n"
               "  (plant/vehicle/quasi_steady.h). scw vehicle gg simulates the plant itself "
               "(ideal\n"
               "  actuators, no drag or rolling resistance, a slow steering ramp: "
               "plant/vehicle/ggv.h),\n"
               "  so the two lateral limits differ, most at high speed.\n";
  if (beyond_top_speed)
    std::cout << "  (*) the drive cannot hold this speed against the drag (above the top speed): "
                 "no steady\n"
                 "      state to take the gradient from (nan in --csv).\n";
  return kExitOk;
}

int Envelope(const VehicleOptions& o) {
  const params::VehicleParams p = LoadVehicle(o.vehicle);
  const auto rows = controller::planning::SampleEnvelope(p, o.brake_bias_front, o.speeds);
  const auto fit = controller::planning::FitEnvelope(rows);
  if (o.csv || !o.csv_file.empty()) {
    std::ostringstream buffer;
    std::ostream& csv = o.csv_file.empty() ? std::cout : buffer;
    csv << "speed_mps,ay_max_mps2,level,drive_mps2,brake_mps2,drive_fit_mps2,brake_fit_mps2\n";
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (std::size_t j = 0; j < controller::planning::kEnvelopeLevels.size(); ++j) {
        const double ay = controller::planning::kEnvelopeLevels[j] * rows[i].ay_max;
        const double v = rows[i].speed;
        csv << params::FormatDouble(v) << ',' << params::FormatDouble(rows[i].ay_max) << ','
            << params::FormatDouble(controller::planning::kEnvelopeLevels[j]) << ','
            << params::FormatDouble(rows[i].drive[j]) << ','
            << params::FormatDouble(rows[i].brake[j]) << ','
            << params::FormatDouble(fit.AxDriveMax(v) * fit.DriveFactor(ay, fit.AyMax(v), v)) << ','
            << params::FormatDouble(fit.AxBrakeMax(v) * fit.BrakeFactor(ay, fit.AyMax(v), v))
            << '\n';
      }
    if (!o.csv_file.empty()) io::WriteFileAtomic(o.csv_file, buffer.str());
    return kExitOk;
  }
  std::cout << "combined g-g-v envelope of the plant '" << p.name << "'"
            << (o.vehicle.empty() ? " (built-in defaults)" : " (" + o.vehicle + ")")
            << ", brake bias front " << o.brake_bias_front << "\n"
            << "quasi-steady double track; drive is net of drag, braking includes it [m/s^2];\n"
            << "columns: the largest drive / brake acceleration at a_y = level x ay_max, and the\n"
            << "planner's fitted law (peak, exponent p), which lies inside the samples\n\n";
  char line[256];
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double v = rows[i].speed;
    std::snprintf(line, sizeof line,
                  "v %5.1f m/s  ay_max %5.2f   drive fit %5.2f p %.2f   brake fit %5.2f p %.2f\n",
                  v, rows[i].ay_max, fit.AxDriveMax(v), fit.DriveExponent(v), fit.AxBrakeMax(v),
                  fit.BrakeExponent(v));
    std::cout << line << "   level  ";
    for (double l : controller::planning::kEnvelopeLevels) {
      std::snprintf(line, sizeof line, "%6.2f", l);
      std::cout << line;
    }
    std::cout << "\n   drive  ";
    for (double d : rows[i].drive) {
      std::snprintf(line, sizeof line, "%6.2f", d);
      std::cout << line;
    }
    std::cout << "\n   brake  ";
    for (double d : rows[i].brake) {
      std::snprintf(line, sizeof line, "%6.2f", d);
      std::cout << line;
    }
    std::cout << "\n";
  }
  return kExitOk;
}

int Lap(const VehicleOptions& o) {
  std::vector<std::string> sets;
  if (!o.vehicle.empty()) sets.push_back("vehicle=" + o.vehicle);
  if (!o.track.empty()) sets.push_back("track=" + o.track);
  const params::ScenarioParams spec = tuning::DefaultScenario(sets);
  const tuning::ResolvedScenario sc = tuning::Resolve(spec);
  char line[512];
  std::snprintf(line, sizeof line,
                "minimum-time lap at the plant's full combined limits: %.2f s\n"
                "(%s, optimal line with %.1f m margin, the plant's own g-g-v envelope; "
                "scenarios plan at GG x limit_fraction %.2f of it)\n",
                sc.limit_lap_time, sc.track->name().c_str(), spec.motion.raceline_margin,
                spec.limit_fraction);
  std::cout << line;
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
                 "Vehicle file (params/vehicles/*.yaml); default: the built-in EAV24 set");
  gg->add_option("--speeds", o->speeds, "Speeds [m/s] (default 10 20 ... 80)")
      ->check(FiniteNumber())
      ->delimiter(',')
      ->expected(1, -1);
  gg->add_option("-o,--output", o->csv_file,
                 "Write the CSV table to this file (atomically) instead of printing it");
  gg->add_flag("--csv", o->csv, "CSV output (speed_mps, lateral/braking/traction in m/s^2)");
  gg->callback([o] { SetExitCode(Gg(*o, "scw vehicle gg")); });

  auto* bal = cmd->add_subcommand(
      "balance",
      "Print the quasi-steady balance (understeer gradient) and the combined-slip limits of the "
      "plant per speed, and the tyres' friction at nominal load");
  bal->add_option("--vehicle", o->vehicle,
                  "Vehicle file (params/vehicles/*.yaml); default: the built-in EAV24 set");
  bal->add_option("--speeds", o->speeds, "Speeds [m/s] (default 10 20 ... 80)")
      ->check(FiniteNumber())
      ->delimiter(',')
      ->expected(1, -1);
  bal->add_option("-o,--output", o->csv_file,
                  "Write the CSV table to this file (atomically) instead of printing it");
  bal->add_flag("--csv", o->csv, "CSV output");
  NumberIn(bal->add_option("--brake-dead-time", o->brake_dead_time,
                           "Also print the brake lag that keeps the total response with this "
                           "dead time [s] (the scenario key plant.brake_dead_time)"),
           0.0, 1.0);
  bal->callback([o] { SetExitCode(Balance(*o, "scw vehicle balance")); });

  auto* env = cmd->add_subcommand(
      "envelope",
      "Print the plant's combined g-g-v envelope (drive and brake at each lateral level, from "
      "quasi-steady evaluations of the plant) and the planner's law fitted inside it");
  env->add_option("--vehicle", o->vehicle,
                  "Vehicle file (params/vehicles/*.yaml); default: the built-in EAV24 set");
  env->add_option("--speeds", o->speeds, "Speeds [m/s] (default 10 20 ... 80)")
      ->check(FiniteNumber())
      ->delimiter(',')
      ->expected(1, -1);
  NumberIn(env->add_option("--brake-bias", o->brake_bias_front, "Front share of the braking force"),
           0.0, 1.0)
      ->capture_default_str();
  env->add_option("-o,--output", o->csv_file,
                  "Write the CSV table to this file (atomically) instead of printing it");
  env->add_flag("--csv", o->csv, "CSV output");
  env->callback([o] { SetExitCode(Envelope(*o)); });

  auto* lap = cmd->add_subcommand(
      "lap", "Print the minimum-time lap at the plant's full combined limits (default track)");
  lap->add_option("--vehicle", o->vehicle,
                  "Vehicle file (params/vehicles/*.yaml); default: the built-in EAV24 set");
  lap->add_option("--track", o->track,
                  "Track: a built-in name (yas_north, monza) or a file (.yaml or .csv); default: "
                  "Yas Marina North");
  lap->callback([o] { SetExitCode(Lap(*o)); });

  auto* ocd = cmd->add_subcommand(
      "ocd",
      "Print how the vehicle file maps onto Open-Car-Dynamics' parameters (plant.model=ocd): a "
      "Markdown table of every OCD parameter with its value and its scw source, or for OCD-only "
      "quantities the public source and why; then what OCD cannot represent or replaces");
  ocd->add_option("--vehicle", o->vehicle,
                  "Vehicle file (params/vehicles/*.yaml); default: the built-in EAV24 set");
  ocd->callback([o] {
    const params::VehicleParams p =
        o->vehicle.empty() ? params::VehicleParams{} : LoadVehicle(o->vehicle);
#if SCW_WITH_OCD
    std::cout << plant::ocd::MappingTableMarkdown(p);
    for (const Problem& q : plant::ocd::CheckRepresentable(p))
      std::cout << "\ncannot represent: " << q.path << ": " << q.message;
    for (const std::string& n : plant::ocd::Replaced(p)) std::cout << "\nreplaced: " << n;
    std::cout << '\n';
    SetExitCode(kExitOk);
#else
    (void)p;
    throw ConfigError("scw vehicle ocd", "plant.model", tuning::NoOcdMessage());
#endif
  });

  auto* init =
      cmd->add_subcommand("init", "Write the built-in vehicle set (EAV24/25 class) as plain YAML");
  init->add_option("-o,--output", o->out, "Output file (e.g. params/vehicles/eav24.yaml)")
      ->required();
  init->callback([o] {
    io::WriteFileAtomic(
        o->out,
        params::ToPlainYaml(
            params::VehicleParams{},
            "EAV24/25-class car (A2RL, Dallara SF23 based): the plant's built-in default set.\n"
            "Public estimates, no validated set exists; every field's source or assumption is in\n"
            "params/schema/ (vehicle_params.h and the files it includes). Calibrated to public\n"
            "data: tyre friction to the public EAV g-g-v fit with mu_x >= mu_y (scw vehicle gg),\n"
            "front cornering stiffness for a positive understeer gradient (scw vehicle balance),\n"
            "brake delay for a 150 ms total response, LSD. Aerodynamic side force in wind\n"
            "(side_force_area, side_force_arm): stated assumptions, no public data.\n"
            "Regenerate: scw vehicle init -o params/vehicles/eav24.yaml"));
    std::cerr << "wrote " << o->out << '\n';
    SetExitCode(kExitOk);
  });

  auto* val = cmd->add_subcommand("validate", "Strictly load a vehicle file (exit 2 on problems)");
  val->add_option("FILE", o->vehicle, "Vehicle file")->required();
  val->callback([o] {
    const auto p = LoadVehicle(o->vehicle);
    std::cout << o->vehicle << ": ok (" << p.name << ")\n";
    SetExitCode(kExitOk);
  });
}

const CommandRegistrar kRegistrar(20, &AddVehicle);

}  // namespace
}  // namespace scw::cli
