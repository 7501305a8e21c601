// Brake and steering actuator models (discrete, advanced once per plant step of length h).
//
// Contract
//   Brakes, per wheel i:  p_req,i [bar] -> clamp to [0, max_pressure] -> pure delay of
//     n_b = round(delay / h) steps -> first-order lag (time constant tau_b) with rate limit:
//       dp = clamp((1 - exp(-h/tau_b)) (p_del - p), -rate h, +rate h),  p += dp
//     -> brake capacity T_b,i = k_b,i p_i [N*m] (front/rear gain), a friction torque that opposes
//     the wheel's rotation and never reverses it (applied in plant::Vehicle).
//   Steering: delta_req [rad] (> 0 = left) -> clamp to +-max_angle -> delay of round(delay/h)
//     steps -> first-order lag with rate limit (as above, [rad/s]) -> clamp to +-max_angle.
//   A step in the request therefore starts to move the output exactly n steps later.
// Source: spec plant-and-track.md §2.5 and §9; paper delays 0.15 s (brake), 0.03 s (steering).
// Immutable configuration; the mutable part (*ActuatorState) belongs to the caller's State.
#pragma once

#include "params/schema/per_wheel.h"
#include "params/schema/vehicle_actuator_params.h"
#include "plant/actuator/delay_line.h"

namespace scw::plant {

/// First-order lag with rate limit, discretised exactly for the lag part.
struct LagRateLimit {
  LagRateLimit() = default;
  LagRateLimit(double time_constant, double rate_limit, double h);
  double gain = 1.0;      ///< 1 - exp(-h/tau)
  double max_step = 0.0;  ///< rate_limit * h
  double Apply(double y, double target) const noexcept;
};

struct SteeringActuatorState {
  DelayLine<double> delay;
  double angle = 0.0;  ///< road-wheel angle [rad]
};

struct BrakeActuatorState {
  DelayLine<PerWheel<double>> delay;
  PerWheel<double> pressure{};  ///< at the callipers [bar]
};

class SteeringActuator {
 public:
  SteeringActuator(const params::SteeringParams& p, double h);
  SteeringActuatorState MakeState(double angle) const;
  /// Advances one step; returns the road-wheel angle [rad] to use during the step.
  double Step(double request, SteeringActuatorState* s) const noexcept;
  int delay_steps() const noexcept { return delay_steps_; }

 private:
  int delay_steps_ = 0;
  double max_angle_ = 0.0;
  LagRateLimit lag_;
};

class BrakeActuator {
 public:
  BrakeActuator(const params::BrakeParams& p, double h);
  BrakeActuatorState MakeState() const;
  /// Advances one step; returns the calliper pressures [bar] to use during the step.
  const PerWheel<double>& Step(const PerWheel<double>& request,
                               BrakeActuatorState* s) const noexcept;
  int delay_steps() const noexcept { return delay_steps_; }

 private:
  int delay_steps_ = 0;
  double max_pressure_ = 0.0;
  LagRateLimit lag_;
};

/// Time [s] from a step request of `step_bar` on every wheel (from 0 bar) until the pressure at the
/// wheel first reaches `fraction` of the step (63 % = the usual "response time"); the delay, the
/// lag and the rate limit all count. Returns +inf if it is not reached within 2 s.
double BrakeStepResponseTime(const params::BrakeParams& p, double h, double step_bar = 80.0,
                             double fraction = 0.632) noexcept;

}  // namespace scw::plant
