// scw maneuver NAME — one standard open-loop maneuver (tuning/maneuver/maneuver.h): the plant
// with the stability controller and a driving robot's input program, no motion controller; prints
// the standard's metrics and pass/fail, writes a trace, a JSON result and a figure.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "params/io/atomic_file.h"
#include "params/io/csv.h"
#include "params/io/override.h"
#include "params/io/write.h"
#include "tuning/cli/command.h"
#include "tuning/cli/maneuver_plot_script.h"  // generated: generated::kManeuverPlotScript
#include "tuning/cli/python_script.h"
#include "tuning/maneuver/maneuver.h"
#include "tuning/maneuver/maneuver_report.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/plant_choice.h"
#include "tuning/sim/scenario.h"

namespace scw::cli {
namespace {

struct ManeuverCliOptions {
  std::string name, scenario, stability, vehicle, subsystems = "all", trace, json, plot;
  std::vector<std::string> overrides;
  bool print = false;
};

/// "esc,abs" → the switches (only the listed subsystems run); "all", "none".
params::SubsystemSwitches ParseSubsystems(const std::string& text) {
  params::SubsystemSwitches sw;
  if (text == "all") return sw;
  sw.esc = sw.cs = sw.abs = sw.tc = false;
  if (text == "none") return sw;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item == "esc")
      sw.esc = true;
    else if (item == "cs")
      sw.cs = true;
    else if (item == "abs")
      sw.abs = true;
    else if (item == "tc")
      sw.tc = true;
    else
      throw ConfigError(
          "scw maneuver", "--subsystems",
          "unknown subsystem '" + item + "' (a comma list of esc, cs, abs, tc; or all, none)");
  }
  return sw;
}

int RunManeuverCommand(const ManeuverCliOptions& o) {
  namespace fs = std::filesystem;
  params::ScenarioParams spec =
      o.scenario.empty() ? tuning::DefaultScenario() : tuning::LoadScenario(o.scenario);
  spec.kind = "maneuver";
  spec.maneuver.name = o.name;
  if (spec.name == "default") spec.name = o.name;
  if (!o.vehicle.empty()) spec.vehicle = fs::absolute(o.vehicle).string();
  if (!o.stability.empty()) spec.stability = fs::absolute(o.stability).string();
  const params::SubsystemSwitches sw = ParseSubsystems(o.subsystems);
  spec.subsystems.esc = sw.esc;
  spec.subsystems.cs = sw.cs;
  spec.subsystems.abs = sw.abs;
  spec.subsystems.tc = sw.tc;
  params::ApplyOverrides(spec, o.overrides);
  if (o.print) {
    std::cout << params::ToPlainYaml(spec);
    return kExitOk;
  }
  const std::string base =
      o.scenario.empty() ? std::string() : fs::path(o.scenario).parent_path().string();
  const auto t0 = std::chrono::steady_clock::now();
  const tuning::ResolvedScenario sc =
      tuning::Resolve(spec, base, o.scenario.empty() ? "built-in" : o.scenario);
  for (const std::string& n : tuning::PlantNotes(spec.plant.model, sc.plant_vehicle))
    std::cerr << "note: plant.model=" << spec.plant.model << ": " << n << '\n';
  std::unique_ptr<io::CsvWriter> trace;
  if (!o.trace.empty()) trace = std::make_unique<io::CsvWriter>(o.trace, tuning::TraceHeader());
  tuning::ManeuverOptions mo;
  mo.trace = trace.get();
  const tuning::ManeuverResult r = tuning::RunManeuver(sc, sc.stability, mo);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (trace) trace->Commit();
  tuning::ManeuverConditions conditions;
  if (!spec.vehicle.empty()) conditions.vehicle = spec.vehicle;
  if (!spec.stability.empty()) conditions.stability = spec.stability;
  conditions.subsystems = spec.subsystems;
  const std::string json = tuning::ManeuverJson(r, 2, conditions);
  if (!o.json.empty()) io::WriteFileAtomic(o.json, json);
  std::cout << tuning::FormatManeuver(r, conditions);
  const tuning::RunMetrics s = r.Summary();
  char line[160];
  std::snprintf(line, sizeof line, "%d run(s), %.1f s simulated in %.2f s\n",
                static_cast<int>(r.runs.size()), s.time, wall);
  std::cerr << line;
  if (!o.plot.empty()) {
    // The figure is drawn from the JSON result: a temporary copy when --json is not given.
    std::string src = o.json;
    fs::path tmp;
    if (src.empty()) {
      tmp = fs::path(o.plot).concat(".result.json");
      io::WriteFileAtomic(tmp.string(), json);
      src = tmp.string();
    }
    std::string message;
    const bool ok = RunPythonScript(generated::kManeuverPlotScript, {src, o.plot}, &message);
    if (!tmp.empty()) fs::remove(tmp);
    if (!ok) std::cerr << "note: no plot written: " << message << "\n";
  }
  return s.aborted() || s.criteria_failed > 0 ? kExitFailed : kExitOk;
}

void AddManeuver(CLI::App& app) {
  auto o = std::make_shared<ManeuverCliOptions>();
  auto* cmd = app.add_subcommand(
      "maneuver",
      "Run a standard open-loop maneuver (robot inputs, the stability controller in the loop, no "
      "motion controller) and print the standard's metrics and pass/fail (docs/maneuvers.md); "
      "exit 1 when a criterion fails");
  cmd->add_option("name", o->name, "The maneuver (docs/maneuvers.md)")
      ->required()
      ->check(CLI::IsMember(tuning::ManeuverNames()));
  cmd->add_option("--scenario", o->scenario,
                  "Scenario file to start from (its vehicle, stability file, grip, plant step, "
                  "abort limits and maneuver section)");
  cmd->add_option("--stability", o->stability, "Stability params file (car's ROS 2 layout)");
  cmd->add_option("--vehicle", o->vehicle, "Vehicle file (params/vehicles/*.yaml)");
  cmd->add_option("--subsystems", o->subsystems,
                  "Subsystems that run: all (default), none, or a comma list of esc, cs, abs, tc");
  cmd->add_option("--set", o->overrides,
                  "Override a scenario key, e.g. --set maneuver.speed=40 (after the options "
                  "above)")
      ->take_all();
  cmd->add_option("--trace", o->trace,
                  "Write the trace CSV of every run (scw simulate's columns; `lap` = the run)");
  cmd->add_option("--json", o->json, "Write the result (metrics, criteria, signals) as JSON");
  cmd->add_option("--plot", o->plot,
                  "Draw the figure (PNG; needs python3-matplotlib: without it a note, no error)");
  cmd->add_flag("--print-scenario", o->print, "Print the scenario as YAML and exit");
  cmd->callback([o] { SetExitCode(RunManeuverCommand(*o)); });
}

const CommandRegistrar kRegistrar(25, &AddManeuver);

}  // namespace
}  // namespace scw::cli
