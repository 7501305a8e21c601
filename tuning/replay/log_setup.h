// The setup file of a controller log: what the stability controller of the recorded run used
// besides its params file and the logged signals (issue 15, "replay reproduces the simulation it
// was recorded from"; docs/replay.md).
//
// The car's vehicle handler injects the vehicle constants (mass, yaw inertia, geometry, tyre radii,
// gear ratios, aero, steering limits) into the stability node; the closed loop does the same from
// the simulated car (scenario.h, InjectVehicleConstants), and a scenario may switch subsystems off
// (subsystems.esc/cs/abs/tc, release_compat). None of that is in the params file, so a replay with
// the same params file alone runs other constants (the node's code defaults) and differs from the
// run. `scw simulate --controller-log LOG` therefore writes `LOG.setup.yaml` next to the log: a
// plain YAML file (loaded strictly, like every workspace file) with
//
//   source, stability_file, vehicle_file   who wrote the log, from which files (information)
//   log_rows, log_bytes                    the log it belongs to (a log of another size is refused)
//   subsystems                             the scenario's switches
//   (params/schema/scenario_params.h) vehicle, tires                         every vehicle.* and
//   tires.* key of the node, with the
//                                          value the controller ran with
//
// The log itself stays a plain CSV (one header row, then numbers) that every reader takes. A log
// without a setup file (older logs, the car's recordings) replays as before.
//
// `scw replay LOG --params F` applies a setup file found next to the log: the recorded value of
// every vehicle.* / tires.* key that F does not set (the closed loop's rule: keys the file sets
// win) and the recorded switches (a subsystem runs if F enables it AND the run did; release_compat
// if either asks for it). The replay of a simulated log with the run's params file then reproduces
// the run's controller outputs bit for bit.
#pragma once

#include <set>
#include <string>

#include "params/schema/field.h"
#include "params/schema/scenario_params.h"
#include "params/schema/stability_params.h"

namespace scw::tuning {
struct ResolvedScenario;
}  // namespace scw::tuning

namespace scw::tuning::replay {

class ControllerLogWriter;

struct ControllerLogSetup {
  std::string source;          ///< what wrote the log (information)
  std::string stability_file;  ///< params file of the run ("" = built-in defaults; information)
  std::string vehicle_file;    ///< vehicle file of the run ("" = built-in; information)
  int log_rows = 0;            ///< data rows of the log
  double log_bytes = 0.0;      ///< size of the log [bytes]
  params::SubsystemSwitches subsystems{};
  params::NodeVehicleParams vehicle{};
  params::TiresParams tires{};

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.source, {.key = "source", .doc = "What wrote the log (information only)."});
    v.Field(s.stability_file,
            {.key = "stability_file",
             .doc = "Stability params file of the recorded run; empty: the built-in defaults "
                    "(information only: replay uses --params)."});
    v.Field(s.vehicle_file, {.key = "vehicle_file",
                             .doc = "Vehicle file of the recorded run; empty: the built-in car "
                                    "(information only)."});
    v.Field(s.log_rows,
            {.key = "log_rows", .lo = 0, .doc = "Data rows of the log this file belongs to."});
    v.Field(s.log_bytes, {.key = "log_bytes",
                          .unit = "byte",
                          .lo = 0.0,
                          .doc = "Size of the log this file belongs to; scw replay refuses the "
                                 "setup for a log of another size."});
    v.Nested("subsystems", s.subsystems);
    v.Nested("vehicle", s.vehicle);
    v.Nested("tires", s.tires);
  }
};

/// `LOG.setup.yaml`: where the setup file of the log `log_path` lives.
std::string SetupPathFor(const std::string& log_path);

/// The setup the closed loop gives its controller for the candidate set `stability`
/// (RunClosedLoop: PrepareStability(sc, stability) and the scenario's switches).
ControllerLogSetup ClosedLoopSetup(const ResolvedScenario& sc,
                                   const params::StabilityParams& stability);

/// The setup file's text (a comment header naming the log, then the fields).
std::string SetupYaml(const ControllerLogSetup& setup, const std::string& log_path);

/// Finishes `log`: with a log written to a file, writes the setup file (with the log's rows and
/// size filled in) and then commits the log; if committing the log fails, the new setup file is
/// removed again. A log written to `-`, a FIFO or a device gets no setup file. Returns the setup
/// file's path, or "" when none was written. Throws std::runtime_error naming the path on a
/// write error.
std::string CommitWithSetup(ControllerLogWriter& log, ControllerLogSetup setup);

/// Loads a setup file strictly. Throws ConfigError listing every problem.
ControllerLogSetup LoadSetup(const std::string& path);

/// Throws ConfigError (naming `setup_path`) when the regular file `log_path` is not the size the
/// setup records: the setup belongs to another log.
void CheckSetupMatchesLog(const ControllerLogSetup& setup, const std::string& setup_path,
                          const std::string& log_path);

/// `p` (loaded from a file that set the keys `present`) with the recorded value of every
/// vehicle.* and tires.* key the file does not set. Not validated.
params::StabilityParams WithRecordedVehicle(params::StabilityParams p,
                                            const std::set<std::string>& present,
                                            const ControllerLogSetup& setup);

}  // namespace scw::tuning::replay
