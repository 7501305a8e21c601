#include "tuning/sim/scenario.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <utility>

#include "controller/planning/reference.h"
#include "params/io/load.h"
#include "params/io/override.h"
#include "params/io/write.h"
#include "params/schema/grip_scaling.h"
#include "tuning/sim/events.h"
#include "tuning/sim/plant_choice.h"
#include "tuning/sim/plant_variation.h"
#include "tuning/sim/prep_cache.h"
#include "tuning/sim/track_csv.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

std::string ResolvePath(const std::string& base_dir, const std::string& file) {
  if (file.empty() || base_dir.empty() || fs::path(file).is_absolute()) return file;
  return (fs::path(base_dir) / file).lexically_normal().string();
}

}  // namespace

params::ScenarioParams LoadScenario(const std::string& path,
                                    const std::vector<std::string>& overrides) {
  auto spec = params::LoadPlainFile<params::ScenarioParams>(path);
  params::ApplyOverrides(spec, overrides);
  return spec;
}

params::ScenarioParams DefaultScenario(const std::vector<std::string>& overrides) {
  params::ScenarioParams spec;
  params::ApplyOverrides(spec, overrides);
  return spec;
}

void InjectVehicleConstants(const params::VehicleParams& v, const std::set<std::string>& present,
                            params::StabilityParams* p) {
  auto set = [&](const char* key, double* field, double value) {
    if (!present.count(key)) *field = value;
  };
  auto& n = p->vehicle;
  set("vehicle.mass.total", &n.mass.total, v.chassis.mass);
  set("vehicle.inertia.yaw", &n.inertia.yaw, v.chassis.yaw_inertia);
  set("vehicle.dimension.wheelbase", &n.dimension.wheelbase, v.chassis.wheelbase);
  set("vehicle.dimension.distance_to_front_axle", &n.dimension.distance_to_front_axle,
      v.chassis.cg_to_front_axle);
  set("vehicle.dimension.track_width_front", &n.dimension.track_width_front, v.chassis.track_front);
  set("vehicle.dimension.track_width_rear", &n.dimension.track_width_rear, v.chassis.track_rear);
  // vehicle.dimension.trackwidth is NOT provided by the car's vehicle handler (spec §7.2): the
  // node keeps its own default, and so do we.
  set("vehicle.dimension.cog_height", &n.dimension.cog_height, v.chassis.cg_height);
  set("tires.front_left.radius.radius_20mps", &p->tires.front_left.radius.radius_20mps,
      v.wheels.radius_front);
  set("tires.rear_left.radius.radius_20mps", &p->tires.rear_left.radius.radius_20mps,
      v.wheels.radius_rear);
  set("vehicle.drivetrain.transmission_ratio", &n.drivetrain.transmission_ratio,
      v.gearbox.final_drive_ratio);
  if (!present.count("vehicle.drivetrain.gear_ratios")) n.drivetrain.gear_ratios = v.gearbox.ratios;
  if (!present.count("tires.front_left.radius.velocity_scaling.velocity") &&
      !present.count("tires.front_left.radius.velocity_scaling.factor")) {
    // The plant's rolling radius does not grow with speed.
    p->tires.front_left.radius.velocity_scaling.factor.assign(
        p->tires.front_left.radius.velocity_scaling.velocity.size(), 1.0);
  }
  const double area = 1.0;
  set("vehicle.aero.air_density", &n.aero.air_density, v.aero.air_density);
  set("vehicle.aero.cross_track_area", &n.aero.cross_track_area, area);
  const double cl_a = v.aero.downforce_area_front + v.aero.downforce_area_rear;
  set("vehicle.aero.lift_coeff", &n.aero.lift_coeff, -cl_a / area);
  set("vehicle.aero.front_downforce_share", &n.aero.front_downforce_share,
      cl_a > 0 ? v.aero.downforce_area_front / cl_a : 0.5);
  set("vehicle.steering.min_angle", &n.steering.min_angle, -v.steering.max_angle);
  set("vehicle.steering.max_angle", &n.steering.max_angle, v.steering.max_angle);
}

controller::motion::LongitudinalModel LongitudinalModelFor(const params::VehicleParams& v) {
  controller::motion::LongitudinalModel m;
  m.mass = v.chassis.mass;
  m.air_density = v.aero.air_density;
  m.drag_area = v.aero.drag_area;
  m.downforce_area = v.aero.downforce_area_front + v.aero.downforce_area_rear;
  m.rolling_resistance = v.wheels.rolling_resistance;
  m.radius_front = v.wheels.radius_front;
  m.radius_rear = v.wheels.radius_rear;
  m.gear_ratios = v.gearbox.ratios;
  m.final_drive = v.gearbox.final_drive_ratio;
  m.efficiency = (v.gearbox.efficiency.empty() ? 1.0 : v.gearbox.efficiency.front()) *
                 v.gearbox.final_drive_efficiency;
  for (double rpm : v.engine.map_speed_rpm) m.map_speed.push_back(rpm * M_PI / 30.0);
  m.map_throttle = v.engine.map_throttle;
  m.map_torque = v.engine.map_torque;
  m.brake_gain_front = v.brakes.torque_gain_front;
  m.brake_gain_rear = v.brakes.torque_gain_rear;
  m.max_pressure = v.brakes.max_pressure;
  return m;
}

namespace {

std::string Where(const params::ScenarioParams& spec, const std::string& source) {
  return source == "built-in" ? "scenario " + spec.name : source;
}

/// The vehicle of a scenario with its grip factors and sensor-noise switch; `*nominal` receives
/// the vehicle file's own values (the planner's, with plan_with_nominal_grip).
void ResolveVehicle(const params::ScenarioParams& spec, const std::string& base_dir,
                    const std::string& where, ResolvedScenario* sc,
                    params::VehicleParams* nominal) {
  sc->vehicle =
      spec.vehicle.empty()
          ? params::VehicleParams{}
          : params::LoadPlainFile<params::VehicleParams>(ResolvePath(base_dir, spec.vehicle));
  *nominal = sc->vehicle;
  params::ScaleGrip(spec.grip, &sc->vehicle.grip);
  sc->vehicle.sensors.noise = sc->vehicle.sensors.noise || spec.sensor_noise;
  params::ValidateOrThrow(sc->vehicle, where + " (vehicle with the scenario's grip)");
}

/// The car's stability file (or defaults) with the vehicle handler's constants.
void ResolveStability(const params::ScenarioParams& spec, const std::string& base_dir,
                      const std::string& where, ResolvedScenario* sc) {
  if (!spec.stability.empty()) {
    params::LoadReport rep;
    sc->stability = params::LoadRosFile<params::StabilityParams>(
        ResolvePath(base_dir, spec.stability), params::kStabilityNodeKey, &rep);
    sc->stability_present = rep.present;
  }
  InjectVehicleConstants(sc->vehicle, sc->stability_present, &sc->stability);
  params::ValidateOrThrow(sc->stability, where + " (stability parameters)");
}

/// The scenario's own plant step (docs/plant-step.md). Applied last: the racing line, the g-g-v
/// table and everything planned from them do not depend on it, so the memos are shared with the
/// same scenario at the vehicle's step.
// The simulated car (the scenario's plant section, docs/plant-calibration.md): after everything
// the car's software is built from, before the plant step (the brake lag that keeps the total
// response is found at the vehicle's own step, so it is the same at any plant_step).
void ApplyPlantSection(const params::ScenarioParams& spec, const std::string& where,
                       ResolvedScenario* sc) {
  try {
    sc->plant_vehicle = ApplyPlantVariation(sc->vehicle, spec.plant);
  } catch (const ConfigError& e) {
    throw ConfigError(where, e.problems());
  }
  params::ValidateOrThrow(sc->plant_vehicle,
                          where + " (vehicle with the scenario's plant section)");
}

// The scenario's own plant step (docs/plant-step.md), for the car's software and the simulated car.
void ApplyPlantStep(const params::ScenarioParams& spec, const std::string& where,
                    ResolvedScenario* sc) {
  if (spec.plant_step > 0.0) {
    sc->vehicle.simulation.time_step = spec.plant_step;
    sc->plant_vehicle.simulation.time_step = spec.plant_step;
    params::ValidateOrThrow(sc->vehicle, where + " (vehicle with the scenario's plant_step)");
    params::ValidateOrThrow(sc->plant_vehicle, where + " (vehicle with the scenario's plant_step)");
    const double ts = sc->stability.tS;
    const double ratio = ts / spec.plant_step;
    if (!(std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio))
      throw ConfigError(where, "plant_step",
                        "must divide the controller period tS = " + params::FormatDouble(ts) +
                            " s, got " + params::FormatDouble(spec.plant_step) + " s");
  }
}

}  // namespace

bool PmpcWithinProvidedLimits(const params::ScenarioParams& spec) {
  return spec.motion.controller == "pmpc" && spec.motion.pmpc.limits == "provided";
}

namespace {

/// The scenario's track and the reference planned on it (controller/planning/reference.h), for
/// the planned car: the vehicle file's own grip with plan_with_nominal_grip, else the scenario's.
void ResolveReference(const params::ScenarioParams& spec, const std::string& base_dir,
                      const std::string& where, const params::VehicleParams& planned,
                      controller::planning::ReferenceCache& cache, ResolvedScenario* sc) {
  namespace planning = controller::planning;
  planning::ReferenceOptions o;
  const std::string& line = spec.motion.raceline;
  o.line = line == "centerline"                ? planning::LineKind::kCentreLine
           : line == "optimal" || line.empty() ? planning::LineKind::kOptimal
                                               : planning::LineKind::kGiven;
  // The files first, read once into the track and the given line; then the planning on them.
  const ScenarioTrack files = LoadScenarioTrack(
      ResolvePath(base_dir, spec.track),
      o.line == planning::LineKind::kGiven ? ResolvePath(base_dir, line) : std::string(), cache);
  sc->track = files.track;
  o.given_line = files.given_line;
  o.given_source = files.line_file;
  o.line_margin = spec.motion.raceline_margin;
  o.limit_scale = spec.gg_scale * spec.limit_fraction;
  // The PMPC within the provided limits follows a profile it can keep to (mpc_params.h, limits).
  if (PmpcWithinProvidedLimits(spec)) o.limit_scale *= spec.motion.pmpc.target_fraction;
  o.brake_bias_front = spec.motion.longitudinal.brake_bias_front;
  o.late_braking = spec.events.late_braking;
  o.source = where;
  const planning::PreparedReference ref = planning::PrepareReference(*sc->track, planned, o, cache);
  sc->path = ref.path;
  sc->ggv = *ref.ggv;
  sc->ideal_lap_time = ref.ideal_lap_time;
  sc->limit_lap_time = ref.limit_lap_time;
  // Critical situations: a corner the track does not have is a configuration error now, not in
  // the middle of a batch.
  try {
    const EventSchedule check(spec.events, *sc->track);
  } catch (const ConfigError& e) {
    throw ConfigError(where, e.problems());
  }
}

/// The motion controllers' tracking parameters: the file's (or the shipped values), steering
/// limits from the vehicle.
void ResolveTracking(const params::ScenarioParams& spec, const std::string& base_dir,
                     ResolvedScenario* sc) {
  if (!spec.motion.params.empty())
    sc->tracking = params::LoadRosFile<params::TrackingParams>(
        ResolvePath(base_dir, spec.motion.params), params::kTrackingNodeKey);
  sc->tracking.vehicle.min_angle = -sc->vehicle.steering.max_angle;
  sc->tracking.vehicle.max_angle = sc->vehicle.steering.max_angle;
}

/// Resolve and ResolveCar: the car always, the track, reference and tracking parameters only
/// `with_reference`. The order of the steps is the order of the errors a bad scenario reports.
ResolvedScenario ResolveScenario(const params::ScenarioParams& spec, const std::string& base_dir,
                                 const std::string& source, bool with_reference,
                                 controller::planning::ReferenceCache* cache) {
  ResolvedScenario sc;
  sc.spec = spec;
  sc.source = source;
  const std::string where = Where(spec, source);
  // A plant this build lacks fails before anything is prepared.
  if (spec.plant.model == "ocd" && !kHaveOcdPlant)
    throw ConfigError(where, "plant.model", NoOcdMessage());
  params::VehicleParams nominal;
  ResolveVehicle(spec, base_dir, where, &sc, &nominal);
  if (with_reference) {
    // Without a caller's cache: one for this call, over the process's disk cache.
    std::optional<controller::planning::ReferenceCache> own;
    if (cache == nullptr) cache = &own.emplace(&PrepCache::Process());
    ResolveReference(spec, base_dir, where, spec.plan_with_nominal_grip ? nominal : sc.vehicle,
                     *cache, &sc);
  }
  ResolveStability(spec, base_dir, where, &sc);
  if (with_reference) ResolveTracking(spec, base_dir, &sc);
  sc.longitudinal_model = LongitudinalModelFor(sc.vehicle);
  // The simulated car and the scenario's own plant step, applied last (the reference does not
  // depend on them).
  ApplyPlantSection(spec, where, &sc);
  ApplyPlantStep(spec, where, &sc);
  // The plant model (plant.model) can simulate the simulated car (tuning/sim/plant_choice.h).
  CheckPlantModel(spec.plant.model, sc.plant_vehicle, where);
  return sc;
}

}  // namespace

ResolvedScenario ResolveCar(const params::ScenarioParams& spec, const std::string& base_dir,
                            const std::string& source) {
  return ResolveScenario(spec, base_dir, source, false, nullptr);
}

ResolvedScenario Resolve(const params::ScenarioParams& spec, const std::string& base_dir,
                         const std::string& source, controller::planning::ReferenceCache* cache) {
  // A maneuver drives no track and follows no reference (tuning/maneuver/maneuver.h).
  return ResolveScenario(spec, base_dir, source, spec.kind != "maneuver", cache);
}

params::StabilityParams PrepareStability(const ResolvedScenario& sc, params::StabilityParams p) {
  InjectVehicleConstants(sc.vehicle, sc.stability_present, &p);
  return ApplySubsystemSwitches(std::move(p), sc.spec.subsystems);
}

params::StabilityParams ApplySubsystemSwitches(params::StabilityParams p,
                                               const params::SubsystemSwitches& sw) {
  p.ESC.enabled = p.ESC.enabled && sw.esc;
  p.countersteer_system.enabled = p.countersteer_system.enabled && sw.cs;
  p.SlipControl.ABS.enabled = p.SlipControl.ABS.enabled && sw.abs;
  p.SlipControl.TC.enabled = p.SlipControl.TC.enabled && sw.tc;
  return p;
}

}  // namespace scw::tuning
