// scw replay — recorded controller inputs through the stability controller, open loop (issue 10,
// docs/replay.md).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>
#include <utility>

#include "controller/stability/stability_controller.h"
#include "params/io/load.h"
#include "params/schema/stability_params.h"
#include "params/schema/vehicle_params.h"
#include "tuning/cli/command.h"
#include "tuning/replay/log_setup.h"
#include "tuning/replay/replay.h"
#include "tuning/sim/scenario.h"

namespace scw::cli {
namespace {

struct ReplayOptions {
  std::string log;
  std::string params;
  std::string compare;
  std::string out;
  std::string vehicle;
  std::string node = params::kStabilityNodeKey;
  bool release_compat = false;
  bool no_log_setup = false;
  bool estimate_loads = false;
  bool columns = false;
};

bool SameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec) && !ec;
}

int RunReplay(const ReplayOptions& o) {
  if (o.columns) {
    std::cout << tuning::replay::ColumnsMarkdown();
    return kExitOk;
  }
  // Checked here rather than by CLI11 so that --columns works alone.
  if (o.log.empty()) throw CLI::RequiredError("LOG");
  if (o.params.empty()) throw CLI::RequiredError("--params");
  if (!o.out.empty() && SameFile(o.out, o.log))
    throw ConfigError(o.out, "-o", "the output would overwrite the log; choose another file");

  // What the recorded controller used besides its params file (tuning/replay/log_setup.h).
  const std::string setup_path = tuning::replay::SetupPathFor(o.log);
  std::error_code ec;
  const bool use_setup = !o.no_log_setup && std::filesystem::exists(setup_path, ec);
  tuning::replay::ControllerLogSetup setup;
  if (use_setup) {
    setup = tuning::replay::LoadSetup(setup_path);
    tuning::replay::CheckSetupMatchesLog(setup, setup_path, o.log);
  }
  params::VehicleParams vehicle;
  if (!o.vehicle.empty()) vehicle = params::LoadPlainFile<params::VehicleParams>(o.vehicle);

  params::StabilityOptions options;
  options.release_compat = o.release_compat || (use_setup && setup.subsystems.release_compat);
  // A params file with the vehicle constants and switches of the recorded run, as the closed
  // loop gives them to its controller (keys the file sets win).
  auto load = [&](const std::string& file) {
    params::LoadReport report;
    params::StabilityParams p = params::LoadRosFile<params::StabilityParams>(file, o.node, &report);
    std::string source = file;
    if (!o.vehicle.empty()) {
      tuning::InjectVehicleConstants(vehicle, report.present, &p);
      source += " with the vehicle constants of " + o.vehicle;
    } else if (use_setup) {
      p = tuning::replay::WithRecordedVehicle(std::move(p), report.present, setup);
      source += " with the vehicle constants of " + setup_path;
    }
    // release_compat is a controller option, not a key: ORed into the options above.
    if (use_setup) p = tuning::ApplySubsystemSwitches(std::move(p), setup.subsystems);
    params::ValidateOrThrow(p, source);
    return controller::StabilityController(p, options);
  };
  const controller::StabilityController a = load(o.params);

  // Say where the vehicle constants come from: a wrong source silently changes every output.
  if (!o.vehicle.empty())
    std::cerr << "vehicle constants: from " << o.vehicle
              << " (as the closed loop injects them) for the vehicle.*/tires.* keys the params "
                 "file does not set\n";
  else if (use_setup)
    std::cerr << "vehicle constants: recorded with the log (" << setup_path << ", " << setup.source
              << ") for the vehicle.*/tires.* keys the params file does not set; "
                 "--no-log-setup to ignore them\n";
  else
    std::cerr << "vehicle constants: the params file's vehicle.*/tires.* keys, else the node's "
                 "code defaults ("
              << (o.no_log_setup ? "--no-log-setup" : "no " + setup_path)
              << "; --vehicle FILE to inject a vehicle's as the closed loop does)\n";
  if (use_setup) {
    const auto& sw = setup.subsystems;
    std::string off;
    for (const auto& [on, name] : {std::pair{sw.esc, "ESC"}, std::pair{sw.cs, "countersteer"},
                                   std::pair{sw.abs, "ABS"}, std::pair{sw.tc, "TC"}})
      if (!on) off += std::string(off.empty() ? "" : ", ") + name;
    if (!off.empty())
      std::cerr << "subsystems switched off in the recorded run, and here: " << off << "\n";
    if (sw.release_compat && !o.release_compat)
      std::cerr << "release_compat: on in the recorded run, and here\n";
  }
  tuning::replay::ReplayInputOptions input;
  input.estimate_loads = o.estimate_loads;

  if (o.compare.empty()) {
    const tuning::replay::ReplaySummary s = tuning::replay::ReplayLog(o.log, a, o.out, input);
    if (o.out.empty()) {
      std::cout << tuning::replay::FormatSummary(s);
      if (options.release_compat)
        std::cout << "(release_compat: long_fx ignored, TC cannot activate)\n";
    } else {
      std::cerr << "wrote " << o.out << " (" << s.rows << " rows, " << s.invalid_rows
                << " invalid)\n";
    }
    return kExitOk;
  }

  const controller::StabilityController b = load(o.compare);
  const tuning::replay::ComparisonSummary c =
      tuning::replay::CompareOnLog(o.log, a, b, o.out, input);
  std::cout << tuning::replay::FormatComparison(c, o.params, o.compare);
  if (options.release_compat)
    std::cout << "(release_compat: long_fx ignored, TC cannot activate)\n";
  if (!o.out.empty()) std::cerr << "wrote " << o.out << " (outputs of " << o.params << ")\n";
  return kExitOk;
}

void AddReplay(CLI::App& app) {
  auto o = std::make_shared<ReplayOptions>();
  auto* cmd = app.add_subcommand(
      "replay",
      "Run the stability controller open loop over a recorded controller log (CSV) and report "
      "where ESC, countersteer, ABS and TC intervene; --compare runs two parameter sets");
  cmd->footer(
      "Log format, output columns and the summary: docs/replay.md.\n"
      "Exit codes: 0 ok, 1 the output could not be written, 2 bad log, params file or "
      "arguments (the message names the line and column).");
  cmd->add_option("LOG", o->log, "Controller log (CSV, one row per controller step; required)");
  cmd->add_option("--params", o->params,
                  "Stability params file, the car's ROS 2 layout (required); its vehicle.* and "
                  "tires.* keys win over the recorded or injected vehicle constants");
  cmd->add_option("--compare", o->compare,
                  "Second params file: print where its outputs differ from --params");
  cmd->add_option("-o,--output", o->out,
                  "Write one output row per log row to this CSV (with --compare: the outputs "
                  "of --params)");
  cmd->add_flag("--release-compat", o->release_compat,
                "Behave like the released node: long_fx ignored (TC never activates)");
  cmd->add_option("--vehicle", o->vehicle,
                  "Vehicle file (params/vehicles/*.yaml): inject its constants into the params "
                  "files as the closed loop does, instead of those recorded with the log");
  cmd->add_flag("--no-log-setup", o->no_log_setup,
                "Ignore LOG.setup.yaml (the vehicle constants and subsystem switches recorded "
                "by scw simulate): vehicle constants from the params file or the node's code "
                "defaults");
  cmd->add_flag("--estimate-loads", o->estimate_loads,
                "Ignore the log's vertical loads (fz_* columns): the controller estimates its own "
                "from its vehicle constants");
  cmd->add_option("--node", o->node, "Node key in the params files")->capture_default_str();
  cmd->add_flag("--columns", o->columns,
                "Print the tables of the log's input columns and the output columns (Markdown) "
                "and exit");
  cmd->callback([o] { SetExitCode(RunReplay(*o)); });
}

const CommandRegistrar kRegistrar(60, &AddReplay);

}  // namespace
}  // namespace scw::cli
