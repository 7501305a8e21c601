#include "tuning/sim/plant_variation.h"

#include <cmath>
#include <string>

#include "params/schema/field.h"
#include "plant/actuator/actuators.h"

namespace scw::tuning {
namespace {

// Response times are whole numbers of steps; compare them with a small tolerance.
bool NotLater(double t, double limit, double h) { return t <= limit + 1e-6 * h; }

std::string Ms(double seconds) { return params::FormatNumber(std::round(seconds * 1e4) / 1e4); }

// The largest fall-off shape factor C admits: 1 / (1 - sin(C pi/2)) (the sliding force reaches 0).
double FalloffLimit(double c) { return 1.0 / (1.0 - std::sin(c * M_PI / 2.0)); }

// The shape factor C' with sin(C' pi/2) = 1 - s (1 - sin(C pi/2)), C' in [1, 2).
double FalloffShape(double c, double falloff) {
  const double target = 1.0 - falloff * (1.0 - std::sin(c * M_PI / 2.0));
  return 2.0 - 2.0 / M_PI * std::asin(target);
}

}  // namespace

params::BrakeParams PaperSimBrakes(const params::BrakeParams& vehicle) {
  params::BrakeParams b = vehicle;
  b.delay = 0.0;
  b.time_constant = 0.0;
  b.rate_limit = 100000.0;
  return b;
}

params::SteeringParams PaperSimSteering(const params::SteeringParams& vehicle) {
  params::SteeringParams s = vehicle;
  s.delay = 0.06;
  s.time_constant = 0.06;
  s.rate_limit = 0.5;
  return s;
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

params::BrakeParams BrakesWithDeadTime(const params::BrakeParams& brakes, double h,
                                       double dead_time) {
  // The actuator's own dead time keeps its own lag: the vehicle file's split bit for bit.
  if (dead_time == brakes.delay) return brakes;
  const DeadTimeRange range = FeasibleBrakeDeadTimes(brakes, h);
  const double total = range.total;
  params::BrakeParams b = brakes;
  b.delay = dead_time;
  auto response = [&](double tau) {
    b.time_constant = tau;
    return BrakeTotalResponse(b, h);
  };
  const double kMaxLag = 1.0;  // the schema's bound of brakes.time_constant
  if (!(dead_time >= 0.0) || !NotLater(response(0.0), total, h) ||
      NotLater(response(kMaxLag), total - 0.5 * h, h))
    throw ConfigError("", "plant.brake_dead_time",
                      Ms(dead_time) + " s is outside the feasible range 0-" + Ms(range.max) +
                          " s: the brakes' total response (63 % of an 80 bar step) is " +
                          Ms(total) + " s, and the rate limit of " +
                          params::FormatNumber(brakes.rate_limit) + " bar/s alone needs " +
                          Ms(total - range.max) + " s");
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
  b.time_constant = 0.5 * (reaches + exceeds);
  return b;
}

params::Mf52Params WithFalloff(const params::Mf52Params& tire, double falloff) {
  if (falloff == 1.0) return tire;
  const struct {
    const char* name;
    double c;
  } shapes[] = {{"PCY1", tire.pcy1}, {"PCX1", tire.pcx1}};
  for (const auto& [name, c] : shapes)
    if (!(c > 1.0 && c < 2.0))
      throw ConfigError("", "plant.rear_tire_falloff",
                        "needs a rear tyre whose " + std::string(name) +
                            " lies in (1, 2) (a force peak and a positive sliding force); the "
                            "vehicle's is " +
                            params::FormatNumber(c) + ", so only 1 is accepted");
  const bool lateral_tighter = FalloffLimit(tire.pcy1) <= FalloffLimit(tire.pcx1);
  const auto& [name, c] = shapes[lateral_tighter ? 0 : 1];
  const double limit = FalloffLimit(c);
  if (!(falloff >= 0.0 && falloff < limit))
    throw ConfigError("", "plant.rear_tire_falloff",
                      params::FormatNumber(falloff) +
                          " is outside the feasible range 0 <= falloff < " +
                          params::FormatNumber(std::floor(limit * 100.0) / 100.0) +
                          " (the sliding force of the rear tyre's " + name + " = " +
                          params::FormatNumber(c) + " would fall to zero or below)");
  params::Mf52Params t = tire;
  t.pcy1 = FalloffShape(tire.pcy1, falloff);
  t.pcx1 = FalloffShape(tire.pcx1, falloff);
  return t;
}

params::VehicleParams ApplyPlantVariation(const params::VehicleParams& vehicle,
                                          const params::PlantVariationParams& plant) {
  params::VehicleParams v = vehicle;
  if (plant.actuators == "paper_sim") {
    v.brakes = PaperSimBrakes(v.brakes);
    v.steering = PaperSimSteering(v.steering);
  } else if (plant.actuators != "vehicle") {
    throw ConfigError("", "plant.actuators",
                      "'" + plant.actuators + "' is not one of vehicle|paper_sim");
  }
  const double h = v.simulation.time_step;
  if (plant.brake_dead_time >= 0.0)
    v.brakes = BrakesWithDeadTime(v.brakes, h, plant.brake_dead_time);
  if (plant.steering_delay >= 0.0) v.steering.delay = plant.steering_delay;
  if (plant.rear_tire_falloff != 1.0)
    v.tires.rear = WithFalloff(v.tires.rear, plant.rear_tire_falloff);
  if (plant.yaw_inertia_scale != 1.0) v.chassis.yaw_inertia *= plant.yaw_inertia_scale;
  return v;
}

}  // namespace scw::tuning
