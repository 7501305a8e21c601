#include "tuning/sim/plant_variation.h"

#include <cmath>
#include <optional>
#include <string>

#include "params/schema/field.h"
#include "plant/actuator/actuators.h"

namespace scw::tuning {
namespace {

// Response times are whole numbers of steps; compare them with a small tolerance.
bool NotLater(double t, double limit, double h) { return t <= limit + 1e-6 * h; }

std::string Ms(double seconds) { return params::FormatNumber(std::round(seconds * 1e4) / 1e4); }

// One version of the paper's simulator: its brakes' dead time and lag (no rate limit: the
// schema's largest) and its steering's dead time, PT1 and rate limit (plant_variation.h).
struct SimulatorActuation {
  double brake_delay, brake_lag, steer_delay, steer_lag, steer_rate;
};
constexpr SimulatorActuation kOcdCurrent{0.0, 0.0, 0.06, 0.06, 0.5};
constexpr SimulatorActuation kOcdIv2024{0.01, 0.03, 0.05, 0.05, 1.0};

// The simulator version a `plant.actuators` value names; nullptr for any other value.
const SimulatorActuation* SimulatorNamed(const std::string& model) {
  if (model == "paper_sim") return &kOcdCurrent;
  if (model == "paper_sim_v1") return &kOcdIv2024;
  return nullptr;
}

params::BrakeParams SimulatorBrakes(const params::BrakeParams& vehicle,
                                    const SimulatorActuation& sim) {
  params::BrakeParams b = vehicle;
  b.delay = sim.brake_delay;
  b.time_constant = sim.brake_lag;
  b.rate_limit = 100000.0;
  return b;
}

params::SteeringParams SimulatorSteering(const params::SteeringParams& vehicle,
                                         const SimulatorActuation& sim) {
  params::SteeringParams s = vehicle;
  s.delay = sim.steer_delay;
  s.time_constant = sim.steer_lag;
  s.rate_limit = sim.steer_rate;
  return s;
}

}  // namespace

params::BrakeParams PaperSimBrakes(const params::BrakeParams& vehicle) {
  return SimulatorBrakes(vehicle, kOcdCurrent);
}

params::SteeringParams PaperSimSteering(const params::SteeringParams& vehicle) {
  return SimulatorSteering(vehicle, kOcdCurrent);
}

params::BrakeParams PaperSimV1Brakes(const params::BrakeParams& vehicle) {
  return SimulatorBrakes(vehicle, kOcdIv2024);
}

params::SteeringParams PaperSimV1Steering(const params::SteeringParams& vehicle) {
  return SimulatorSteering(vehicle, kOcdIv2024);
}

double BrakeTotalResponse(const params::BrakeParams& brakes, double h) {
  return plant::BrakeStepResponseTime(brakes, h);
}

DeadTimeRange FeasibleBrakeDeadTimes(const params::BrakeParams& brakes, double h) {
  params::BrakeParams rate_only = brakes;
  rate_only.delay = 0.0;
  rate_only.time_constant = 0.0;
  DeadTimeRange r;
  r.total = BrakeTotalResponse(brakes, h);
  r.max = r.total - BrakeTotalResponse(rate_only, h);
  return r;
}

namespace {

constexpr double kMaxLag = 1.0;  // the schema's bound of brakes.time_constant

// The total response of `brakes` with dead time d, as a function of the lag.
auto ResponseOfLag(const params::BrakeParams& brakes, double h, double d) {
  params::BrakeParams b = brakes;
  b.delay = d;
  return [b, h](double tau) mutable {
    b.time_constant = tau;
    return BrakeTotalResponse(b, h);
  };
}

// Whether some lag in [0, kMaxLag] keeps the total response of `brakes` with dead time d.
bool DeadTimeFeasible(const params::BrakeParams& brakes, double h, double d) {
  const double total = BrakeTotalResponse(brakes, h);
  auto response = ResponseOfLag(brakes, h, d);
  return d >= 0.0 && NotLater(response(0.0), total, h) &&
         !NotLater(response(kMaxLag), total - 0.5 * h, h);
}

// Every violation of a brake dead time and a rear-tyre fall-off, listed together (STYLE §6);
// an absent value is not checked, nor the brakes' own dead time or a fall-off of 1 (no change).
Problems CheckSplitAndFalloff(const params::BrakeParams& brakes, double h,
                              std::optional<double> dead_time_or_none,
                              const params::Mf52Params& rear, double falloff) {
  Problems pr;
  const double dead_time = dead_time_or_none.value_or(brakes.delay);
  if (dead_time != brakes.delay && !DeadTimeFeasible(brakes, h, dead_time)) {
    const DeadTimeRange range = FeasibleBrakeDeadTimes(brakes, h);
    pr.Add("plant.brake_dead_time",
           Ms(dead_time) + " s is outside the feasible range 0-" + Ms(range.max) +
               " s: the brakes' total response (63 % of an 80 bar step) is " + Ms(range.total) +
               " s, and the rate limit of " + params::FormatNumber(brakes.rate_limit) +
               " bar/s alone needs " + Ms(range.total - range.max) + " s");
  }
  const params::FalloffBound bound = params::FalloffBoundOf(rear);
  if (falloff != 1.0 && !bound.has_peak)
    pr.Add("plant.rear_tire_falloff",
           "needs a rear tyre whose " + std::string(bound.name) +
               " lies in (1, 2) (a force peak and a positive sliding force); the vehicle's is " +
               params::FormatNumber(bound.c) + ", so only 1 is accepted");
  else if (falloff != 1.0 && !(falloff >= 0.0 && falloff * rear.falloff < bound.limit))
    pr.Add("plant.rear_tire_falloff",
           params::FormatNumber(falloff) + " is outside the feasible range 0 <= falloff < " +
               params::FormatNumber(std::floor(bound.limit / rear.falloff * 100.0) / 100.0) +
               " (the sliding force of the rear tyre's " + bound.name + " = " +
               params::FormatNumber(bound.c) + " would fall to zero or below)");
  return pr;
}

void ThrowIfAny(const Problems& pr) {
  if (!pr.empty()) throw ConfigError("", pr.items());
}

// The split of a feasible dead time (checked before).
params::BrakeParams SplitAt(const params::BrakeParams& brakes, double h, double dead_time) {
  // The actuator's own dead time keeps its own lag: the vehicle file's split bit for bit.
  if (dead_time == brakes.delay) return brakes;
  const double total = BrakeTotalResponse(brakes, h);
  auto response = ResponseOfLag(brakes, h, dead_time);
  // Smallest lag that reaches T, then smallest lag that is later than T: the middle of the two
  // gives T itself (the response time is a whole number of steps).
  auto first_lag = [&](auto later) {
    double lo = 0.0, hi = kMaxLag;
    if (later(response(lo))) return lo;
    for (int i = 0; i < 80; ++i) {
      const double mid = 0.5 * (lo + hi);
      (later(response(mid)) ? hi : lo) = mid;
    }
    return hi;
  };
  const double reaches = first_lag([&](double t) { return !NotLater(t, total - 0.5 * h, h); });
  const double exceeds = first_lag([&](double t) { return !NotLater(t, total, h); });
  params::BrakeParams b = brakes;
  b.delay = dead_time;
  b.time_constant = 0.5 * (reaches + exceeds);
  return b;
}

// The fall-off of a tyre with a force peak and a feasible fall-off (checked before).
params::Mf52Params FalloffAt(const params::Mf52Params& tire, double falloff) {
  if (falloff == 1.0) return tire;
  params::Mf52Params t = tire;
  t.falloff = tire.falloff * falloff;
  return t;
}

}  // namespace

params::BrakeParams BrakesWithDeadTime(const params::BrakeParams& brakes, double h,
                                       double dead_time) {
  ThrowIfAny(CheckSplitAndFalloff(brakes, h, dead_time, params::Mf52Params{}, 1.0));
  return SplitAt(brakes, h, dead_time);
}

params::Mf52Params WithFalloff(const params::Mf52Params& tire, double falloff) {
  ThrowIfAny(CheckSplitAndFalloff(params::BrakeParams{}, 0.001, std::nullopt, tire, falloff));
  return FalloffAt(tire, falloff);
}

params::VehicleParams ApplyPlantVariation(const params::VehicleParams& vehicle,
                                          const params::PlantVariationParams& plant) {
  params::VehicleParams v = vehicle;
  const double h = v.simulation.time_step;
  // Check everything first, every violation listed; then apply, in the documented order.
  Problems pr;
  const SimulatorActuation* sim = SimulatorNamed(plant.actuators);
  const bool known = sim != nullptr || plant.actuators == "vehicle";
  if (!known)
    pr.Add("plant.actuators",
           "'" + plant.actuators + "' is not one of " + std::string(kActuatorModels));
  if (sim != nullptr) {
    v.brakes = SimulatorBrakes(v.brakes, *sim);
    v.steering = SimulatorSteering(v.steering, *sim);
  }
  // The dead time is judged on the selected actuator only (an unknown one has no total response).
  std::optional<double> dead_time;
  if (known && plant.brake_dead_time >= 0.0) dead_time = plant.brake_dead_time;
  pr.Append(CheckSplitAndFalloff(v.brakes, h, dead_time, v.tires.rear, plant.rear_tire_falloff));
  ThrowIfAny(pr);
  if (plant.brake_dead_time >= 0.0) v.brakes = SplitAt(v.brakes, h, plant.brake_dead_time);
  if (plant.steering_delay >= 0.0) v.steering.delay = plant.steering_delay;
  v.tires.rear = FalloffAt(v.tires.rear, plant.rear_tire_falloff);
  if (plant.yaw_inertia_scale != 1.0) v.chassis.yaw_inertia *= plant.yaw_inertia_scale;
  if (plant.grip_scaling != "vehicle") v.tires.grip_scaling = plant.grip_scaling;
  return v;
}

}  // namespace scw::tuning
