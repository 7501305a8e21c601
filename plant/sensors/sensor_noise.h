// Optional seeded sensor noise.
//
// Contract: adds independent zero-mean Gaussian samples with the standard deviations of
// params::SensorParams to the continuous channels of a Measurement (positions, heading,
// velocities, yaw rate, accelerations, wheel speeds, steering angle, brake pressures, engine
// speed). Gear, wheel loads, throttle and status stay exact. Normal variates come from
// std::mt19937_64 (its output sequence is fixed by the C++ standard) through the workspace's own
// Box-Muller transform, so a seed gives the same noise with every standard library.
#pragma once

#include <cstdint>
#include <random>

#include "params/schema/vehicle_actuator_params.h"
#include "plant/sensors/measurement.h"

namespace scw::plant {

/// Standard normal variates, deterministic across standard libraries.
class NormalSource {
 public:
  explicit NormalSource(std::uint64_t seed = 1) : rng_(seed) {}
  double Next() noexcept;

 private:
  double Uniform() noexcept;  // in (0, 1)
  std::mt19937_64 rng_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

struct SensorNoiseState {
  explicit SensorNoiseState(std::uint64_t seed = 1) : normal(seed) {}
  NormalSource normal;
};

/// Adds noise in place (no-op when p.noise is false).
void AddSensorNoise(const params::SensorParams& p, Measurement* m, SensorNoiseState* s) noexcept;

}  // namespace scw::plant
