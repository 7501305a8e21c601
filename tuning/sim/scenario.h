// Scenario files and their resolution into everything one closed-loop run needs.
//
// Resolution (once per scenario; the tuner then runs many stability parameter sets on it):
//   track     built-in Yas Marina North, a piecewise .yaml definition or a .csv centre line
//   vehicle   built-in EAV24-class car or a params/vehicles/*.yaml file; the scenario's grip
//             factors multiply the vehicle's; the scenario's `plant` section (actuator model,
//             brake dead time, ...) changes only the simulated car (plant_vehicle)
//   reference controller::planning::PrepareReference (controller/planning/reference.h):
//             minimum-curvature racing line (or centre line, or a given raceline file) with the
//             forward–backward velocity profile from the plant's own g-g-v envelope times the
//             acceleration scaling GG and the limit fraction, late braking applied
//   stability the car's params file (or the built-in defaults); the vehicle constants the car's
//             vehicle handler would inject (mass, yaw inertia, geometry, radii, ratios, aero,
//             steering limits) are taken from the vehicle unless the file sets them
//   motion    pure pursuit with the tracking params file (or the shipped values) and the
//             longitudinal controller with its knowledge of the car from the vehicle
// Relative file names in a scenario file are relative to that file's folder.
//
// Cache: the track and the reference go through the caller's ReferenceCache
// (controller/planning/reference_cache.h): whoever resolves many scenarios (the batch evaluator,
// a sweep) owns one and passes it, so the expensive steps are computed once per distinct input
// and shared between scenarios and threads (which wait for a computation in flight). Without one,
// a call prepares with a cache of its own over the process's disk cache (tuning/sim/prep_cache.h).
// Results are the same with or without a cache, bit for bit.
#pragma once

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "controller/motion/longitudinal.h"
#include "controller/motion/path.h"
#include "controller/planning/ggv.h"
#include "controller/planning/reference_cache.h"
#include "params/schema/scenario_params.h"
#include "params/schema/stability_params.h"
#include "params/schema/tracking_params.h"
#include "params/schema/vehicle_params.h"
#include "plant/track/track.h"

namespace scw::tuning {

/// Whether the scenario drives the PMPC within the provided limits (motion.controller=pmpc,
/// motion.pmpc.limits=provided): its reference is then planned at motion.pmpc.target_fraction of
/// GG × limit_fraction (the limits the PMPC may use).
bool PmpcWithinProvidedLimits(const params::ScenarioParams& spec);

struct ResolvedScenario {
  params::ScenarioParams spec;
  std::string source;  ///< scenario file or "built-in"
  std::shared_ptr<const plant::Track> track;
  std::shared_ptr<const controller::motion::Path> path;  ///< reference line with speed profile
  double ideal_lap_time = 0.0;    ///< [s] of the reference (limits × limit_fraction × GG)
  double limit_lap_time = 0.0;    ///< [s] on the same line at the plant's full g-g-v limits
  params::VehicleParams vehicle;  ///< grip factors applied: the car the software knows
  /// The simulated car: `vehicle` with the scenario's `plant` section applied
  /// (tuning/sim/plant_variation.h); the planner, the motion controllers and the stability node's
  /// vehicle constants keep `vehicle`. Equal to `vehicle` when the section is at its defaults.
  params::VehicleParams plant_vehicle;
  params::StabilityParams stability;        ///< base set, vehicle keys injected
  std::set<std::string> stability_present;  ///< keys the stability file set
  params::TrackingParams tracking;
  controller::motion::LongitudinalModel longitudinal_model;
  /// The plant's steady-state g-g-v table the reference was planned with (unscaled; the planner
  /// used it × limit_fraction × GG). The MPC motion controllers constrain their plans with it.
  controller::planning::GgvTable ggv;
};

/// Loads a scenario file (plain YAML, strict) and applies `overrides` ("key=value").
params::ScenarioParams LoadScenario(const std::string& path,
                                    const std::vector<std::string>& overrides = {});
/// The built-in default scenario with `overrides` applied.
params::ScenarioParams DefaultScenario(const std::vector<std::string>& overrides = {});

/// Builds everything a run needs. `base_dir` resolves relative file names ("" = current folder);
/// `cache` (may be null) is the caller's preparation cache (see above). Throws ConfigError on bad
/// files. A scenario of kind `maneuver` gets ResolveCar (no track).
ResolvedScenario Resolve(const params::ScenarioParams& spec, const std::string& base_dir = "",
                         const std::string& source = "built-in",
                         controller::planning::ReferenceCache* cache = nullptr);

/// The car of a scenario without a track or a reference: the vehicle (grip factors, sensor noise,
/// plant_step), the stability base set (vehicle constants injected) and the longitudinal model,
/// resolved exactly as Resolve does; track and path stay null. What a maneuver needs
/// (tuning/maneuver/maneuver.h); Resolve returns this for a scenario of kind `maneuver`.
ResolvedScenario ResolveCar(const params::ScenarioParams& spec, const std::string& base_dir = "",
                            const std::string& source = "built-in");

/// The stability set a run uses: `candidate` with the vehicle constants injected (except keys in
/// `present`) and the scenario's subsystem switches applied (a subsystem runs if enabled in the
/// set AND in the scenario).
params::StabilityParams PrepareStability(const ResolvedScenario& sc,
                                         params::StabilityParams candidate);

/// `p` with a subsystem enabled only where both the set and the switches enable it.
params::StabilityParams ApplySubsystemSwitches(params::StabilityParams p,
                                               const params::SubsystemSwitches& sw);

/// Vehicle constants the car's vehicle handler injects into the stability node (spec §7.2),
/// taken from the plant's vehicle parameters; keys in `present` are left as they are.
void InjectVehicleConstants(const params::VehicleParams& vehicle,
                            const std::set<std::string>& present, params::StabilityParams* p);

/// The longitudinal controller's knowledge of the car.
controller::motion::LongitudinalModel LongitudinalModelFor(const params::VehicleParams& v);

}  // namespace scw::tuning
