#include "controller/stability/tc.h"

#include <algorithm>
#include <cmath>

#include "controller/common/low_pass.h"
#include "controller/stability/abs.h"

namespace scw::controller {

bool TcActivate(const TcSignals& s, const params::TcAxleParams& a) noexcept {
  return s.slip >= s.scale * a.slip_threshold_hold_reduce && s.allowed && s.long_fx > 0.0;
}

bool TcDeactivate(const TcSignals& s, double deactivation_duration) noexcept {
  return s.time_since_exceed > deactivation_duration || !s.allowed;
}

TcTransition NextTcPhase(SlipPhase phase, const TcSignals& s, const params::TcAxleParams& a,
                         double deactivation_duration) noexcept {
  const double r = s.scale;
  const double lambda = s.slip;
  const double rate = s.slip_rate;
  switch (phase) {
    case SlipPhase::kInactive:
      if (TcActivate(s, a)) return {SlipPhase::kHold, TcAction::kLatch};
      return {SlipPhase::kInactive, TcAction::kNone};
    case SlipPhase::kHold:
      if (TcDeactivate(s, deactivation_duration)) return {SlipPhase::kInactive, TcAction::kNone};
      if (lambda > r * a.slip_threshold_hold_reduce && rate > 0.0)
        return {SlipPhase::kReduce, TcAction::kReduceStep};
      if (lambda <= r * a.slip_threshold_hold_increase && rate < 0.0)
        return {SlipPhase::kIncrease, TcAction::kIncreaseStep};
      return {SlipPhase::kHold, TcAction::kNone};
    case SlipPhase::kReduce:
      if (TcDeactivate(s, deactivation_duration)) return {SlipPhase::kInactive, TcAction::kNone};
      if (lambda <= r * a.slip_threshold_hold_increase && rate < 0.0)
        return {SlipPhase::kIncrease, TcAction::kIncreaseStep};
      if (rate < 0.0 || lambda < r * a.slip_threshold_reduce_hold)
        return {SlipPhase::kHold, TcAction::kNone};
      return {SlipPhase::kReduce, TcAction::kReduceStep};
    case SlipPhase::kIncrease:
      if (TcDeactivate(s, deactivation_duration)) return {SlipPhase::kInactive, TcAction::kNone};
      if (lambda > r * a.slip_threshold_hold_reduce && rate > 0.0)
        return {SlipPhase::kReduce, TcAction::kCapToInitial};
      if ((rate > 0.0 || lambda > r * a.slip_threshold_increase_hold) &&
          lambda > r * a.slip_threshold_safe)
        return {SlipPhase::kHold, TcAction::kNone};
      return {SlipPhase::kIncrease, TcAction::kIncreaseStep};
  }
  return {SlipPhase::kInactive, TcAction::kNone};
}

double ApplyTcAction(TcAction action, double epsilon, double error, const params::TcAxleParams& a,
                     bool use_error_in_increase) noexcept {
  switch (action) {
    case TcAction::kNone:
      return epsilon;
    case TcAction::kLatch:
      return a.reduce_initial_pressure_ratio;
    case TcAction::kReduceStep:
      return std::clamp(epsilon - error * a.reduce_step, 0.0, 1.0);
    case TcAction::kIncreaseStep:
      return std::clamp(epsilon + (use_error_in_increase ? error : 1.0) * a.increase_step, 0.0,
                        1.0);
    case TcAction::kCapToInitial:
      return std::min(epsilon, a.reduce_initial_pressure_ratio);
  }
  return epsilon;
}

TcWheelController::TcWheelController(const params::StabilityParams& p, bool front)
    : axle_(front ? p.SlipControl.TC.front : p.SlipControl.TC.rear),
      filter_pole_(std::clamp(p.SlipControl.TC.slip_filter_pole, 0.0, 1.0)),
      sample_time_(std::max(p.tS, 1e-6)),
      deactivation_duration_(p.SlipControl.TC.deactivation_duration),
      slip_angle_max_(p.SlipControl.TC.slip_angle_max),
      threshold_reduction_(p.SlipControl.TC.slip_threshold_reduction_factor),
      use_error_in_increase_(p.SlipControl.TC.use_error_in_increase) {}

TcWheelController::Output TcWheelController::Step(const Input& in, State* s) const noexcept {
  Output out;
  // 1. Input conditioning.
  const double old = s->slip_filtered;
  const double lambda = LowPass(filter_pole_).Step(in.slip, &s->slip_filtered);
  const double rate = (lambda - old) / sample_time_;
  const double f = in.long_fx;
  if (s->phase != SlipPhase::kInactive && std::abs(f) >= 1e-6) {
    s->epsilon = std::clamp(1.0 - (s->force_prev / f) * (1.0 - s->epsilon), 0.0, 1.0);
  }
  s->force_prev = f;
  out.slip_filtered = lambda;

  // 2. Threshold scale and slip error.
  const double r = ThresholdScale(in.slip_angle_abs, slip_angle_max_, threshold_reduction_);
  const double e = NormalisedSlipError(lambda, r * axle_.slip_threshold_hold_reduce);

  // 3. Transition.
  const TcSignals sig{lambda, rate, r, f, in.allowed, in.t - s->t_exceed};
  const TcTransition tr = NextTcPhase(s->phase, sig, axle_, deactivation_duration_);
  s->epsilon = ApplyTcAction(tr.action, s->epsilon, e, axle_, use_error_in_increase_);
  s->phase = tr.next;

  // 4. Output.
  double f_out = s->epsilon * f;
  const double p_tc = f_out <= f ? in.pressure_per_force * (f - f_out) : 0.0;
  double p = std::max(in.pressure_in, p_tc);
  if (s->phase == SlipPhase::kInactive || f < 0.0) {
    f_out = f;
    p = in.pressure_in;
  }
  out.force_target = f_out;
  out.pressure = p;

  // 5. Deactivation timer.
  if (lambda >= r * axle_.slip_threshold_hold_reduce) s->t_exceed = in.t;
  return out;
}

}  // namespace scw::controller
