#include "plant/actuator/actuators.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scw::plant {
namespace {
int DelaySteps(double delay, double h) { return static_cast<int>(std::lround(delay / h)); }
}  // namespace

LagRateLimit::LagRateLimit(double time_constant, double rate_limit, double h)
    : gain(time_constant > 0.0 ? 1.0 - std::exp(-h / time_constant) : 1.0),
      max_step(rate_limit * h) {}

double LagRateLimit::Apply(double y, double target) const noexcept {
  return y + std::clamp(gain * (target - y), -max_step, max_step);
}

SteeringActuator::SteeringActuator(const params::SteeringParams& p, double h)
    : delay_steps_(DelaySteps(p.delay, h)),
      max_angle_(p.max_angle),
      lag_(p.time_constant, p.rate_limit, h) {}

SteeringActuatorState SteeringActuator::MakeState(double angle) const {
  angle = std::clamp(angle, -max_angle_, max_angle_);
  return {DelayLine<double>(static_cast<std::size_t>(delay_steps_), angle), angle};
}

double SteeringActuator::Step(double request, SteeringActuatorState* s) const noexcept {
  // NaN requests are treated as "hold": a broken command must not poison the plant.
  if (!std::isfinite(request)) request = s->angle;
  const double delayed = s->delay.Shift(std::clamp(request, -max_angle_, max_angle_));
  s->angle = std::clamp(lag_.Apply(s->angle, delayed), -max_angle_, max_angle_);
  return s->angle;
}

BrakeActuator::BrakeActuator(const params::BrakeParams& p, double h)
    : delay_steps_(DelaySteps(p.delay, h)),
      max_pressure_(p.max_pressure),
      lag_(p.time_constant, p.rate_limit, h) {}

BrakeActuatorState BrakeActuator::MakeState() const {
  return {DelayLine<PerWheel<double>>(static_cast<std::size_t>(delay_steps_), PerWheel<double>{}),
          PerWheel<double>{}};
}

const PerWheel<double>& BrakeActuator::Step(const PerWheel<double>& request,
                                            BrakeActuatorState* s) const noexcept {
  PerWheel<double> clamped;
  for (std::size_t i = 0; i < 4; ++i)
    clamped[i] = std::isfinite(request[i]) ? std::clamp(request[i], 0.0, max_pressure_) : 0.0;
  const PerWheel<double> delayed = s->delay.Shift(clamped);
  for (std::size_t i = 0; i < 4; ++i)
    s->pressure[i] = std::clamp(lag_.Apply(s->pressure[i], delayed[i]), 0.0, max_pressure_);
  return s->pressure;
}

double BrakeStepResponseTime(const params::BrakeParams& p, double h, double step_bar,
                             double fraction) noexcept {
  const BrakeActuator act(p, h);
  BrakeActuatorState s = act.MakeState();
  const PerWheel<double> req{step_bar, step_bar, step_bar, step_bar};
  const double target = fraction * std::min(step_bar, p.max_pressure);
  for (int k = 0; k * h < 2.0; ++k) {
    const PerWheel<double>& out = act.Step(req, &s);
    // The pressure returned by step k acts during [k h, (k + 1) h]: reached at its end.
    if (out[0] >= target) return (k + 1) * h;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace scw::plant
