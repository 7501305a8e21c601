#include "tuning/sim/scenario.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <utility>

#include "params/io/load.h"
#include "params/io/override.h"
#include "params/io/write.h"
#include "params/schema/grip_scaling.h"
#include "params/schema/track_params.h"
#include "plant/track/builtin_tracks.h"
#include "plant/track/yas_north.h"
#include "tuning/sim/events.h"
#include "tuning/sim/plant_envelope.h"
#include "tuning/sim/plant_variation.h"
#include "tuning/sim/prep_cache.h"
#include "tuning/sim/track_csv.h"
#include "tuning/sim/trajectory/racing_line.h"
#include "tuning/sim/trajectory/velocity_profile.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

std::string ResolvePath(const std::string& base_dir, const std::string& file) {
  if (file.empty() || base_dir.empty() || fs::path(file).is_absolute()) return file;
  return (fs::path(base_dir) / file).lexically_normal().string();
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

plant::Track LoadTrack(const std::string& file) {
  if (file.empty()) return plant::YasNorthTrack();
  // A built-in name has no extension; a scenario file's directory may have been put before it.
  if (const fs::path path(file); !path.has_extension()) {
    if (auto track = plant::BuiltInTrack(path.filename().string())) return *std::move(track);
    throw ConfigError(file, "track",
                      "unknown built-in track (known: " + plant::BuiltInTrackNames() +
                          "); a track file needs the extension .csv, .yaml or .yml");
  }
  if (EndsWith(file, ".csv")) return tuning::LoadTrackCsv(file);
  if (EndsWith(file, ".yaml") || EndsWith(file, ".yml"))
    return plant::Track::FromDefinition(params::LoadPlainFile<params::TrackParams>(file), file);
  throw ConfigError(file, "track", "unknown track file type (expected .csv, .yaml or .yml)");
}

/// Process-wide memo of expensive, pure preparation steps (racing line, g-g-v table, full-limit
/// lap), keyed by a text that determines the result. Thread-safe and single-flight: the first
/// caller of a key computes it outside the lock, concurrent callers of that key wait for its
/// result. Values are immutable once stored; a failed computation is not kept.
template <class T>
class Memo {
 public:
  template <class Make>
  std::shared_ptr<const T> Get(const std::string& key, Make&& make) {
    std::promise<std::shared_ptr<const T>> promise;
    std::shared_future<std::shared_ptr<const T>> result;
    bool first = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto [it, inserted] = items_.try_emplace(key);
      if (inserted) {
        it->second = promise.get_future().share();
        first = true;
      }
      result = it->second;
    }
    if (first) {
      try {
        promise.set_value(std::make_shared<const T>(make()));
      } catch (...) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          items_.erase(key);
        }
        promise.set_exception(std::current_exception());  // waiters see the same error
      }
    }
    return result.get();
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_future<std::shared_ptr<const T>>> items_;
};

/// The track of a scenario, shared within the process: a built-in track is a pure function of its
/// name, a track file's of the file's bytes (building Yas Marina North from its clothoids is about
/// a quarter of a scenario's preparation). A file that cannot be read gets LoadTrack's error.
/// `key` receives the text that determines the track ("" for a file that cannot be read).
std::shared_ptr<const plant::Track> SharedTrack(const std::string& file, std::string* key) {
  static Memo<plant::Track> tracks;
  *key = "built-in:" + file;
  if (fs::path(file).has_extension()) {
    try {
      *key = "file:" + file + "\n" + params::ReadTextFile(file);
    } catch (const std::exception&) {
      key->clear();
      return std::make_shared<const plant::Track>(LoadTrack(file));
    }
  }
  return tracks.Get(*key, [&] { return LoadTrack(file); });
}

/// Exact text of every input of PlantEnvelope: the vehicle as the params writer emits it (doubles
/// in shortest round-trip form) and the brake bias. The sensor-noise switch is left out of the key
/// (written as false): PlantEnvelope switches noise off itself.
std::string GgvKey(params::VehicleParams v, double brake_bias_front) {
  v.sensors.noise = false;
  return params::ToPlainYaml(v) + "|brake_bias_front: " + params::FormatDouble(brake_bias_front);
}

/// The preparation cache's arrays of a g-g-v table: its columns in the order of GgvTable::Visit.
CachedArrays GgvToArrays(const controller::planning::GgvTable& t) {
  CachedArrays a;
  params::ForEachField(t, [&](const std::string&, const std::vector<double>& column,
                              const params::Meta&) { a.push_back(column); });
  return a;
}

/// A g-g-v table from the preparation cache's arrays (GgvToArrays), if valid.
std::optional<controller::planning::GgvTable> GgvFromArrays(const CachedArrays& a) {
  controller::planning::GgvTable t;
  std::size_t i = 0;
  bool complete = true;
  params::ForEachField(t,
                       [&](const std::string&, std::vector<double>& column, const params::Meta&) {
                         if (i < a.size())
                           column = a[i++];
                         else
                           complete = false;
                       });
  if (!complete || i != a.size()) return std::nullopt;
  try {
    t.Validate("cache");
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return t;
}

/// The planner's g-g-v table: the plant's own combined envelope (tuning/sim/plant_envelope.h), per
/// vehicle and brake bias, shared within the process.
std::shared_ptr<const controller::planning::GgvTable> PlantGgv(const std::string& key,
                                                               const params::VehicleParams& v,
                                                               double brake_bias_front) {
  static Memo<controller::planning::GgvTable> memo;
  return memo.Get(key, [&] {
    const PrepCache& cache = PrepCache::Process();
    if (const auto hit = cache.Load("ggv", key))
      if (auto table = GgvFromArrays(*hit)) return *std::move(table);
    controller::planning::GgvTable table = PlantEnvelope(v, brake_bias_front);
    cache.Store("ggv", key, GgvToArrays(table));
    return table;
  });
}

/// The minimum-curvature line of `track` (its text `track_key`, "" = not cacheable): its
/// optimised offsets go through the preparation cache, the line is built from them.
plant::Track OptimalLine(const plant::Track& track, const std::string& track_key,
                         const RacingLineOptions& ro) {
  if (track_key.empty()) return MinimumCurvatureLine(track, ro).line;
  const std::string key = track_key + "\nmargin: " + params::FormatDouble(ro.margin);
  const PrepCache& cache = PrepCache::Process();
  if (const auto hit = cache.Load("line", key); hit && hit->size() == 1) {
    RacingLineOptions known = ro;
    known.known_offset = &hit->front();
    RacingLine line = MinimumCurvatureLine(track, known);
    if (line.status == "known") return std::move(line.line);
  }
  RacingLine line = MinimumCurvatureLine(track, ro);
  cache.Store("line", key, {line.offset});
  return std::move(line.line);
}

std::shared_ptr<const controller::motion::Path> ToPath(const ReferenceTrajectory& r) {
  std::vector<controller::motion::PathPoint> pts(r.size());
  for (std::size_t i = 0; i < r.size(); ++i)
    pts[i] = {r.s[i], r.x[i], r.y[i], r.psi[i], r.kappa[i], r.v[i], r.a_x[i]};
  // The velocity profile may repeat the closing node at s = length: drop it.
  while (pts.size() > 3 && pts.back().s >= r.length) pts.pop_back();
  return std::make_shared<controller::motion::Path>(std::move(pts), r.length);
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

ResolvedScenario ResolveCar(const params::ScenarioParams& spec, const std::string& base_dir,
                            const std::string& source) {
  ResolvedScenario sc;
  sc.spec = spec;
  sc.source = source;
  const std::string where = Where(spec, source);
  params::VehicleParams nominal;
  ResolveVehicle(spec, base_dir, where, &sc, &nominal);
  ResolveStability(spec, base_dir, where, &sc);
  sc.longitudinal_model = LongitudinalModelFor(sc.vehicle);
  ApplyPlantSection(spec, where, &sc);
  ApplyPlantStep(spec, where, &sc);
  return sc;
}

ResolvedScenario Resolve(const params::ScenarioParams& spec, const std::string& base_dir,
                         const std::string& source) {
  // A maneuver drives no track and follows no reference (tuning/maneuver/maneuver.h).
  if (spec.kind == "maneuver") return ResolveCar(spec, base_dir, source);
  ResolvedScenario sc;
  sc.spec = spec;
  sc.source = source;
  const std::string where = Where(spec, source);

  // Vehicle (with the scenario's grip factors).
  params::VehicleParams nominal;
  ResolveVehicle(spec, base_dir, where, &sc, &nominal);

  // Track and reference line.
  std::string track_key;
  const std::shared_ptr<const plant::Track> track =
      SharedTrack(ResolvePath(base_dir, spec.track), &track_key);
  sc.track = track;
  auto compute_line = [&]() -> plant::Track {
    if (spec.motion.raceline == "centerline") return *track;
    if (spec.motion.raceline == "optimal" || spec.motion.raceline.empty()) {
      RacingLineOptions ro;
      ro.margin = spec.motion.raceline_margin;
      return OptimalLine(*track, track_key, ro);
    }
    return LoadRacingLine(ResolvePath(base_dir, spec.motion.raceline), *track).line;
  };
  // The line depends only on the track file and the line options: shared within the process.
  static Memo<plant::Track> lines;
  const std::string line_key = ResolvePath(base_dir, spec.track) + "|" + spec.motion.raceline +
                               "|" + ResolvePath(base_dir, spec.motion.raceline) + "|" +
                               params::FormatDouble(spec.motion.raceline_margin);
  const plant::Track& line = *lines.Get(line_key, compute_line);
  VelocityProfileOptions vo;
  vo.gg_scale = spec.gg_scale * spec.limit_fraction;
  const params::VehicleParams& planned = spec.plan_with_nominal_grip ? nominal : sc.vehicle;
  const double brake_bias = spec.motion.longitudinal.brake_bias_front;
  const std::string ggv_key = GgvKey(planned, brake_bias);
  const auto ggv = PlantGgv(ggv_key, planned, brake_bias);
  const ReferenceTrajectory ref = ComputeVelocityProfile(line, *ggv, vo);
  sc.ggv = *ggv;
  sc.path = ToPath(ref);
  // Critical situations: a corner the track does not have is a configuration error now, not in
  // the middle of a batch; late braking moves brake points of the reference the controller sees.
  try {
    const EventSchedule check(spec.events, *track);
    if (!spec.events.late_braking.s.empty())
      sc.path = std::make_shared<const controller::motion::Path>(
          LateBrakingPath(*sc.path, spec.events.late_braking, *track));
  } catch (const ConfigError& e) {
    throw ConfigError(where, e.problems());
  }
  sc.ideal_lap_time = ref.lap_time;
  // The full-limit lap depends only on the line and the table.
  static Memo<double> limit_laps;
  sc.limit_lap_time = *limit_laps.Get(ggv_key + "\n" + line_key, [&] {
    return ComputeVelocityProfile(line, *ggv, VelocityProfileOptions{}).lap_time;
  });

  // Stability parameters: the car's file (or defaults) with the vehicle handler's constants.
  ResolveStability(spec, base_dir, where, &sc);

  // Motion control.
  if (!spec.motion.params.empty())
    sc.tracking = params::LoadRosFile<params::TrackingParams>(
        ResolvePath(base_dir, spec.motion.params), params::kTrackingNodeKey);
  sc.tracking.vehicle.min_angle = -sc.vehicle.steering.max_angle;
  sc.tracking.vehicle.max_angle = sc.vehicle.steering.max_angle;
  sc.longitudinal_model = LongitudinalModelFor(sc.vehicle);

  // The simulated car and the scenario's own plant step, applied last (the memos above do not
  // depend on them).
  ApplyPlantSection(spec, where, &sc);
  ApplyPlantStep(spec, where, &sc);
  return sc;
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
