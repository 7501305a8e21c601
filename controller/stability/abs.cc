#include "controller/stability/abs.h"

#include <algorithm>
#include <cmath>

#include "controller/stability/vehicle_model.h"

namespace scw::controller {
namespace {
constexpr double kForceHysteresis = 100.0;  // [N], hard-coded in the reference
constexpr double kBaseTargetReduction = 0.9;
constexpr double kMinTargetReduction = 0.33;
}  // namespace

double ThresholdScale(double slip_angle_abs, double slip_angle_max, double reduction) noexcept {
  return 1.0 - std::clamp(slip_angle_abs / std::max(slip_angle_max, 1e-6), 0.0, 1.0) * reduction;
}

double NormalisedSlipError(double slip, double scaled_hold_reduce) noexcept {
  return std::clamp(
      std::abs((scaled_hold_reduce - slip) / std::max(std::abs(scaled_hold_reduce), 1e-6)), 0.1,
      1.0);
}

bool AbsActivate(const AbsSignals& s, const params::AbsAxleParams& a,
                 double min_long_force) noexcept {
  return s.slip <= s.scale * a.slip_threshold_hold_reduce && s.slip_rate < 0.0 &&
         (s.long_fx < min_long_force - kForceHysteresis || s.esc_active) && s.allowed;
}

bool AbsDeactivate(const AbsSignals& s, const params::AbsAxleParams& a,
                   double min_long_force) noexcept {
  return (s.long_fx > min_long_force && !s.esp_trigger) ||
         (s.slip > s.scale * a.slip_threshold_hold_reduce && s.esp_trigger) || !s.allowed;
}

AbsTransition NextAbsPhase(SlipPhase phase, const AbsSignals& s, const params::AbsAxleParams& a,
                           double min_long_force) noexcept {
  const double r = s.scale;
  const double lambda = s.slip;
  const double rate = s.slip_rate;
  switch (phase) {
    case SlipPhase::kInactive:
      if (AbsActivate(s, a, min_long_force)) return {SlipPhase::kHold, AbsAction::kLatch};
      return {SlipPhase::kInactive, AbsAction::kNone};
    case SlipPhase::kHold:
      if (AbsDeactivate(s, a, min_long_force)) return {SlipPhase::kInactive, AbsAction::kNone};
      if (lambda < r * a.slip_threshold_hold_reduce && rate < 0.0)
        return {SlipPhase::kReduce, AbsAction::kReduceStep};
      if (lambda > r * a.slip_threshold_hold_increase && rate > 0.0)
        return {SlipPhase::kIncrease, AbsAction::kEnterIncrease};
      return {SlipPhase::kHold, AbsAction::kNone};
    case SlipPhase::kReduce:
      if (AbsDeactivate(s, a, min_long_force)) return {SlipPhase::kInactive, AbsAction::kNone};
      if (lambda > r * a.slip_threshold_hold_increase && rate > 0.0)
        return {SlipPhase::kIncrease, AbsAction::kEnterIncrease};
      if (rate > 0.0 || lambda > r * a.slip_threshold_reduce_hold)
        return {SlipPhase::kHold, AbsAction::kNone};
      return {SlipPhase::kReduce, AbsAction::kReduceStep};
    case SlipPhase::kIncrease:
      if (AbsDeactivate(s, a, min_long_force)) return {SlipPhase::kInactive, AbsAction::kNone};
      if (lambda < r * a.slip_threshold_hold_reduce && rate < 0.0)
        return {SlipPhase::kReduce, AbsAction::kCapToInitial};
      if ((rate < 0.0 || lambda < r * a.slip_threshold_increase_hold) &&
          lambda < r * a.slip_threshold_safe)
        return {SlipPhase::kHold, AbsAction::kNone};
      if (s.epsilon > 0.999) {
        if (lambda > r * a.slip_threshold_safe ||
            (lambda > r * a.slip_threshold_reduce_hold && rate > 0.0))
          return {SlipPhase::kIncrease, AbsAction::kTargetIncrease};
        return {SlipPhase::kIncrease, AbsAction::kNone};
      }
      return {SlipPhase::kIncrease, AbsAction::kIncreaseStep};
  }
  return {SlipPhase::kInactive, AbsAction::kNone};
}

double ApplyAbsAction(AbsAction action, double epsilon, double error,
                      const params::AbsAxleParams& a, bool use_error_in_increase) noexcept {
  const double gain = use_error_in_increase ? error : 1.0;
  switch (action) {
    case AbsAction::kNone:
      return epsilon;
    case AbsAction::kLatch:
      return a.reduce_initial_pressure_ratio;
    case AbsAction::kReduceStep:
      return std::clamp(epsilon - error * a.reduce_step, 0.0, 1.0);
    case AbsAction::kIncreaseStep:
      return std::clamp(epsilon + gain * a.increase_step, 0.0, 1.0);
    case AbsAction::kEnterIncrease:
      return std::max(a.increase_initial_pressure_ratio,
                      std::clamp(epsilon + gain * a.increase_step, 0.0, 1.0));
    case AbsAction::kCapToInitial:
      return std::min(epsilon, a.reduce_initial_pressure_ratio);
    case AbsAction::kTargetIncrease:
      return epsilon + gain * a.increase_step_target_increase;
  }
  return epsilon;
}

AbsWheelController::AbsWheelController(const params::StabilityParams& p, bool front)
    : axle_(front ? p.SlipControl.ABS.front : p.SlipControl.ABS.rear),
      min_long_force_(p.SlipControl.ABS.min_long_force),
      slip_angle_max_(p.SlipControl.ABS.slip_angle_max),
      threshold_reduction_(p.SlipControl.ABS.slip_threshold_reduction_factor),
      use_error_in_increase_(p.SlipControl.ABS.use_error_in_increase),
      window_(static_cast<std::size_t>(
          std::clamp<int>(p.SlipControl.ABS.moving_average_fx_window_length, 1,
                          static_cast<int>(kMaxFxWindowLength)))),
      mass_(p.vehicle.mass.total),
      downforce_coeff_(-0.5 * p.vehicle.aero.air_density * p.vehicle.aero.cross_track_area *
                       p.vehicle.aero.lift_coeff) {}

AbsWheelController::Output AbsWheelController::Step(const Input& in, State* s) const noexcept {
  Output out;
  // 1. Velocity-dependent target reduction (state before the transition).
  double rf = kBaseTargetReduction;
  if (s->phase != SlipPhase::kInactive) {
    const double c = downforce_coeff_;
    const double fz_lat = mass_ * kGravity + c * s->v_latched * s->v_latched;
    if (!(std::abs(fz_lat) < 1e-6)) {
      rf = kBaseTargetReduction *
           std::clamp(1.0 - c * (s->v_latched * s->v_latched - in.v_x * in.v_x) / fz_lat,
                      kMinTargetReduction, 1.0);
    }
  }
  out.target_reduction = rf;

  // 2. Threshold scale and slip error.
  const double r = ThresholdScale(in.slip_angle_abs, slip_angle_max_, threshold_reduction_);
  const double e = NormalisedSlipError(in.slip, r * axle_.slip_threshold_hold_reduce);

  // 3. Brake-friction compensation of the latched pressure.
  s->p_latched = (s->mu_prev / in.mu) * s->p_latched;
  s->mu_prev = in.mu;

  // 4. Transition.
  const AbsSignals sig{in.slip,       in.slip_rate,   r,          in.long_fx,
                       in.esc_active, s->esp_trigger, in.allowed, s->epsilon};
  const AbsTransition tr = NextAbsPhase(s->phase, sig, axle_, min_long_force_);
  if (tr.action == AbsAction::kLatch) {
    s->f_latched = in.long_fx;
    s->p_latched = in.pressure_in;
    s->v_latched = in.v_x;
    s->esp_trigger = in.long_fx >= min_long_force_ - kForceHysteresis;
  }
  s->epsilon = ApplyAbsAction(tr.action, s->epsilon, e, axle_, use_error_in_increase_);
  s->phase = tr.next;
  const bool inactive = s->phase == SlipPhase::kInactive;

  // 5. Force target.
  double f_out = std::max(s->epsilon * rf * s->f_latched, in.long_fx);
  if (inactive) f_out = in.long_fx;

  // 6. Safety limiter.
  s->force_out_mean.Push(std::min(f_out, 0.0), window_);
  s->force_in_mean.Push(std::min(in.long_fx, 0.0), window_);
  const double k_s = axle_.fx_safety_threshold_factor;
  if (!inactive && s->force_out_mean.Mean(window_) > k_s * s->force_in_mean.Mean(window_)) {
    f_out = std::min(k_s * in.long_fx, f_out);
    out.safety_active = true;
  }
  out.force_target = f_out;

  // 7. Pressure.
  double p;
  if (!in.esc_active || out.safety_active) {
    const double dp = in.pressure_per_force * (f_out - rf * s->f_latched);
    p = inactive ? in.pressure_in : std::max(rf * s->p_latched - dp, 0.0);
  } else {
    p = inactive ? in.pressure_in : std::max(rf * s->epsilon * s->p_latched, 0.0);
  }
  out.pressure = std::min(in.pressure_in, p);
  return out;
}

}  // namespace scw::controller
