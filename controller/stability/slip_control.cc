#include "controller/stability/slip_control.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "controller/common/low_pass.h"
#include "controller/stability/vehicle_model.h"

namespace scw::controller {
namespace {

double Select(SlipSelector sel, double a, double b) {
  return sel == SlipSelector::kMin ? std::min(a, b) : std::max(a, b);
}

/// Index (left or right of the axle starting at `left`) whose raw slip the selector picks; ties
/// go to the right wheel.
std::size_t PickWheel(SlipSelector sel, const Wheels& slip, std::size_t left) {
  const bool left_wins =
      sel == SlipSelector::kMin ? slip[left] < slip[left + 1] : slip[left] > slip[left + 1];
  return left_wins ? left : left + 1;
}

double AxleWeighted(const Wheels& slip, const Wheels& fz, std::size_t left, bool* ok) {
  const double sum = fz[left] + fz[left + 1];
  *ok = sum > 1e-6;
  return *ok ? (fz[left] * slip[left] + fz[left + 1] * slip[left + 1]) / sum : 0.0;
}

}  // namespace

WheelSlipSignals SelectSlipSource(SlipSelector selector, bool use_virtual_slips, bool load_weighted,
                                  const Wheels& slip, const Wheels& virtual_slip, const Wheels& fz,
                                  const Wheels& slip_rate, const Wheels& slip_angle_abs) noexcept {
  WheelSlipSignals out;
  out.slip_angle_abs = slip_angle_abs;
  const std::size_t front_pick = PickWheel(selector, slip, kFL);
  const std::size_t rear_pick = PickWheel(selector, slip, kRL);
  bool ok_front = false;
  bool ok_rear = false;
  const double w_front = AxleWeighted(slip, fz, kFL, &ok_front);
  const double w_rear = AxleWeighted(slip, fz, kRL, &ok_rear);
  const Wheels weighted{ok_front ? w_front : slip[kFL], ok_front ? w_front : slip[kFR],
                        ok_rear ? w_rear : slip[kRL], ok_rear ? w_rear : slip[kRR]};
  const Wheels axle_rate{slip_rate[front_pick], slip_rate[front_pick], slip_rate[rear_pick],
                         slip_rate[rear_pick]};
  if (use_virtual_slips && load_weighted) {
    out.slip = {weighted[kFL], weighted[kFR], virtual_slip[kRL], virtual_slip[kRL]};
    out.slip_rate = axle_rate;
  } else if (use_virtual_slips) {
    out.slip = virtual_slip;
    out.slip_rate = {slip_rate[kFL], slip_rate[kFR], slip_rate[rear_pick], slip_rate[rear_pick]};
  } else if (load_weighted) {
    out.slip = weighted;
    out.slip_rate = axle_rate;
  } else {
    out.slip = slip;
    out.slip_rate = slip_rate;
  }
  return out;
}

WheelSlipSignals DistributeSlips(SlipOperationMode mode, SlipSelector selector,
                                 const WheelSlipSignals& src) noexcept {
  auto axle = [&](WheelSlipSignals& out, std::size_t left) {
    const double slip = Select(selector, src.slip[left], src.slip[left + 1]);
    const double alpha = std::max(src.slip_angle_abs[left], src.slip_angle_abs[left + 1]);
    const std::size_t rate_wheel =
        std::abs(src.slip[left]) > std::abs(src.slip[left + 1]) ? left : left + 1;
    const double rate = src.slip_rate[rate_wheel];
    for (std::size_t i = left; i < left + 2; ++i) {
      out.slip[i] = slip;
      out.slip_angle_abs[i] = alpha;
      out.slip_rate[i] = rate;
    }
  };
  WheelSlipSignals out;
  switch (mode) {
    case SlipOperationMode::kIndividual:
      return src;
    case SlipOperationMode::kAxleSplit:
      axle(out, kFL);
      axle(out, kRL);
      return out;
    case SlipOperationMode::kAllTogether: {
      const double slip =
          selector == SlipSelector::kMin ? MinElement(src.slip) : MaxElement(src.slip);
      std::size_t first = 0;
      while (first < 3 && !(src.slip[first] == slip)) ++first;
      out.slip = {slip, slip, slip, slip};
      const double alpha = MaxElement(src.slip_angle_abs);
      out.slip_angle_abs = {alpha, alpha, alpha, alpha};
      const double rate = src.slip_rate[first];
      out.slip_rate = {rate, rate, rate, rate};
      return out;
    }
    case SlipOperationMode::kRearOnly:
      axle(out, kRL);
      return out;
  }
  return out;
}

SlipControl::SlipControl(const params::StabilityParams& p, const params::StabilityOptions& options)
    : p_(p),
      options_(options),
      abs_mode_(SlipOperationModeFromInt(p.SlipControl.ABS.operation_mode,
                                         SlipOperationMode::kAxleSplit)),
      tc_mode_(
          SlipOperationModeFromInt(p.SlipControl.TC.operation_mode, SlipOperationMode::kRearOnly)),
      sample_time_(std::max(p.tS, 1e-6)),
      k_axle_front_(AxlePressurePerForce(p.tires.front_left.radius.radius_20mps, p.vehicle.brake)),
      k_axle_rear_(AxlePressurePerForce(p.tires.rear_left.radius.radius_20mps, p.vehicle.brake)),
      abs_front_(p, true),
      abs_rear_(p, false),
      tc_front_(p, true),
      tc_rear_(p, false) {
  Problems problems = params::Validate(p);
  problems.Append(params::Validate(options));
  const int window = p.SlipControl.ABS.moving_average_fx_window_length;
  if (window > static_cast<int>(kMaxFxWindowLength)) {
    problems.Add("SlipControl.ABS.moving_average_fx_window_length",
                 std::to_string(window) + " exceeds the controller's fixed ring-buffer capacity " +
                     std::to_string(kMaxFxWindowLength) + " (kMaxFxWindowLength)");
  }
  if (!problems.empty()) throw ConfigError("", problems.items());
}

SlipControl::Output SlipControl::Step(const Input& in, State* s) const noexcept {
  Output out;
  const auto& abs_p = p_.SlipControl.ABS;
  const auto& tc_p = p_.SlipControl.TC;

  // 1. Raw slip rates and filtered slip-angle magnitudes.
  Wheels rate{};
  Wheels alpha_abs{};
  const LowPass alpha_filter(p_.SlipControl.slip_angle_filter_pole);
  for (std::size_t i = 0; i < 4; ++i) {
    rate[i] = (in.slip_pct[i] - s->prev_slip[i]) / sample_time_;
    s->prev_slip[i] = in.slip_pct[i];
    alpha_abs[i] = std::abs(alpha_filter.Step(in.slip_angle[i], &s->slip_angle_filtered[i]));
  }

  // 2./3. Sources and distribution.
  out.abs_input = DistributeSlips(abs_mode_, SlipSelector::kMin,
                                  SelectSlipSource(SlipSelector::kMin, abs_p.use_virtual_slips,
                                                   abs_p.slip_vertical_load_weighted, in.slip_pct,
                                                   in.virtual_slip_pct, in.fz, rate, alpha_abs));
  out.tc_input = DistributeSlips(
      tc_mode_, SlipSelector::kMax,
      SelectSlipSource(SlipSelector::kMax, tc_p.use_virtual_slips, tc_p.slip_vertical_load_weighted,
                       in.slip_pct, in.virtual_slip_pct, in.fz, rate, alpha_abs));

  // 4. Gear flanks and "allowed".
  if (!s->gear_initialised && options_.ignore_initial_gear_change) {
    s->gear_seen = in.gear;
    s->gear_request_seen = in.gear_request;
  }
  s->gear_initialised = true;
  if (in.gear != s->gear_seen) {
    s->gear_seen = in.gear;
    s->t_gear = in.t;
  }
  if (in.gear_request != s->gear_request_seen) {
    s->gear_request_seen = in.gear_request;
    s->t_gear_request = in.t;
  }
  const double since_gear = in.t - s->t_gear;
  const bool abs_base = abs_p.enabled && in.slip_valid && in.v_x > abs_p.min_activation_velocity;
  const bool abs_rear_ok = since_gear > abs_p.activation_time_after_gearshift ||
                           IsActive(s->abs[kRL].phase) || IsActive(s->abs[kRR].phase);
  const bool tc_base = tc_p.enabled && in.slip_valid && in.v_x > tc_p.min_activation_velocity;
  const bool tc_rear_ok = since_gear > tc_p.activation_time_after_gearshift ||
                          IsActive(s->tc[kRL].phase) || IsActive(s->tc[kRR].phase);

  // 5. Wheel controllers, ABS first.
  const double bias = FrontBrakeBias(in.v_x, p_.P_VDC_brake_bias_front, p_.brake_bias_shift);
  Wheels k_w{};
  for (std::size_t i = 0; i < 4; ++i) {
    k_w[i] = IsFront(i) ? k_axle_front_ / in.mu[i] * bias : k_axle_rear_ / in.mu[i] * (1.0 - bias);
  }
  for (std::size_t i = 0; i < 4; ++i) {
    const AbsWheelController::Input wi{.allowed = abs_base && (IsFront(i) || abs_rear_ok),
                                       .slip = out.abs_input.slip[i],
                                       .slip_angle_abs = out.abs_input.slip_angle_abs[i],
                                       .slip_rate = out.abs_input.slip_rate[i],
                                       .pressure_in = in.pressure_in[i],
                                       .mu = in.mu[i],
                                       .pressure_per_force = k_w[i],
                                       .long_fx = in.long_fx,
                                       .esc_active = in.esc_active,
                                       .v_x = in.v_x};
    out.abs_pressure[i] = (IsFront(i) ? abs_front_ : abs_rear_).Step(wi, &s->abs[i]).pressure;
    out.abs_phase[i] = s->abs[i].phase;
  }
  for (std::size_t i = 0; i < 4; ++i) {
    const bool allowed =
        tc_base && (IsFront(i) ? tc_mode_ != SlipOperationMode::kRearOnly : tc_rear_ok);
    const TcWheelController::Input wi{.allowed = allowed,
                                      .slip = out.tc_input.slip[i],
                                      .slip_angle_abs = out.tc_input.slip_angle_abs[i],
                                      .pressure_in = in.pressure_in[i],
                                      .pressure_per_force = k_w[i],
                                      .long_fx = in.long_fx,
                                      .t = in.t};
    out.tc_pressure[i] = (IsFront(i) ? tc_front_ : tc_rear_).Step(wi, &s->tc[i]).pressure;
    out.tc_phase[i] = s->tc[i].phase;
  }

  // 6. Output selection.
  out.abs_latched = std::any_of(out.abs_phase.begin(), out.abs_phase.end(), IsActive);
  const std::size_t tc_first = tc_mode_ == SlipOperationMode::kRearOnly ? kRL : kFL;
  out.tc_latched = std::any_of(out.tc_phase.begin() + static_cast<std::ptrdiff_t>(tc_first),
                               out.tc_phase.end(), IsActive);
  out.active = out.abs_latched || out.tc_latched;
  const double f = in.long_fx;
  if (out.abs_latched && f < 0.0 && !in.esc_active) {
    out.pressure = out.abs_pressure;
  } else if (out.tc_latched && f > 0.0 && !in.esc_active) {
    out.pressure = out.tc_pressure;
  } else if (in.esc_active) {
    out.pressure = out.abs_latched ? out.abs_pressure : in.pressure_in;
    if (out.tc_latched) {
      out.pressure[kRL] = out.tc_pressure[kRL];
      out.pressure[kRR] = out.tc_pressure[kRR];
    }
  } else {
    out.pressure = in.pressure_in;
  }

  // 7. Gear-shift rear pressure reduction.
  const auto& shift = p_.SlipControl.shift_pressure_reduction;
  const double since_request_ms = std::floor((in.t - s->t_gear_request) * 1000.0 + 1e-6);
  const double start_ms = shift.duration_gearshift_initiation * 1000.0;
  const double end_ms = start_ms + shift.duration_pressure_reduction * 1000.0;
  if (start_ms < since_request_ms && since_request_ms < end_ms) {
    const double factor = std::clamp(shift.reduction_factor, 0.0, 1.0);
    out.pressure[kRL] *= factor;
    out.pressure[kRR] *= factor;
    out.shift_reduction = true;
  }

  // 8. Throttle cut.
  out.throttle = in.throttle;
  if (in.slip_valid && !(MaxElement(out.tc_input.slip) <= tc_p.max_slip_throttle_cut)) {
    out.throttle = 0.0;
    out.throttle_cut = true;
  }
  return out;
}

}  // namespace scw::controller
