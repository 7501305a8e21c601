#include "controller/stability/esc.h"

#include <algorithm>
#include <cmath>

#include "controller/common/interp.h"
#include "controller/stability/vehicle_model.h"

namespace scw::controller {

EscThresholds EscThresholdsAt(double speed, const params::EscParams& p) noexcept {
  return {Interp(speed, p.threshold_velocities, p.beta_threshold_activate),
          Interp(speed, p.threshold_velocities, p.psi_dot_error_threshold_activate),
          Interp(speed, p.threshold_velocities, p.beta_error_threshold_activate),
          p.beta_threshold_deactivate,
          p.psi_dot_error_threshold_deactivate,
          p.beta_error_threshold_deactivate,
          p.min_activation_velocity};
}

EscPhase NextEscPhase(EscPhase phase, const EscSignals& s, const EscThresholds& th) noexcept {
  switch (phase) {
    case EscPhase::kInactive: {
      const bool activate =
          s.enabled && s.speed > th.min_velocity && std::abs(s.beta) > th.beta_activate &&
          std::abs(s.e_beta) > th.beta_error_activate &&
          std::abs(s.e_psi) > th.psi_dot_error_activate && s.yaw_rate * s.e_psi < 0.0 &&
          s.beta * s.e_beta < 0.0 && s.e_beta * s.e_psi < 0.0;
      return activate ? EscPhase::kActive : EscPhase::kInactive;
    }
    case EscPhase::kActive: {
      const bool deactivate =
          !s.enabled || s.speed < th.min_velocity ||
          (std::abs(s.beta) < th.beta_deactivate && std::abs(s.e_beta) < th.beta_error_deactivate &&
           std::abs(s.e_psi) < th.psi_dot_error_deactivate);
      return deactivate ? EscPhase::kInactive : EscPhase::kActive;
    }
  }
  return EscPhase::kInactive;
}

EscActivationTerms EscActivationRatios(const EscSignals& s, const EscThresholds& th) noexcept {
  const bool oversteer = s.speed > th.min_velocity && s.yaw_rate * s.e_psi < 0.0 &&
                         s.beta * s.e_beta < 0.0 && s.e_beta * s.e_psi < 0.0;
  if (!oversteer) return {};
  const auto ratio = [](double value, double threshold) {
    if (!(threshold > 0.0)) return kMaxEscMargin;
    const double r = std::min(kMaxEscMargin, std::abs(value) / threshold);
    return std::isfinite(r) ? r : 0.0;
  };
  return {.beta = ratio(s.beta, th.beta_activate),
          .beta_error = ratio(s.e_beta, th.beta_error_activate),
          .yaw_rate_error = ratio(s.e_psi, th.psi_dot_error_activate)};
}

namespace {
double SmallestTerm(const EscActivationTerms& t) noexcept {
  return std::min({t.beta, t.beta_error, t.yaw_rate_error});
}
}  // namespace

double EscActivationMargin(const EscSignals& s, const EscThresholds& th) noexcept {
  return SmallestTerm(EscActivationRatios(s, th));
}

EscReference EscReferences(double speed, double steering_request, double ay_request,
                           double yaw_rate_request, double beta_request,
                           const EscReferenceModel& m) noexcept {
  EscReference ref;
  const bool has_yaw = std::isfinite(yaw_rate_request);
  const bool has_beta = std::isfinite(beta_request);
  if (!has_yaw || !has_beta) {
    if (std::isfinite(ay_request)) {
      const double v = std::max(speed, 3.0);
      ref.curvature = ay_request / (v * v);
    } else {
      const double cf = m.stiffness_front;
      const double cr = m.stiffness_rear;
      ref.curvature = steering_request /
                      (m.wheelbase + m.mass * speed * speed * (m.l_rear * cr - m.l_front * cf) /
                                         (cf * cr * m.wheelbase));
    }
  }
  ref.yaw_rate = has_yaw ? yaw_rate_request : ref.curvature * speed;
  ref.beta = has_beta ? beta_request
                      : ref.curvature * (m.l_rear - m.l_front * m.mass * speed * speed /
                                                        (m.stiffness_rear * m.wheelbase));
  return ref;
}

Wheels AllocateYawMoment(double yaw_moment, const Wheels& pressure, const Wheels& mu,
                         double pressure_per_force, double track_width,
                         double max_pressure) noexcept {
  Wheels p = pressure;
  const double a = yaw_moment * (2.0 / track_width) * pressure_per_force;
  if (a > 0.0) {
    const double release = std::min(p[kFR], a / (2.0 * mu[kFR]));
    p[kFR] -= release;
    p[kFL] += std::min((a - release * mu[kFR]) / mu[kFL], std::max(0.0, max_pressure - p[kFL]));
  } else {
    const double abs_a = -a;
    const double release = std::min(p[kFL], abs_a / (2.0 * mu[kFL]));
    p[kFL] -= release;
    p[kFR] += std::min((abs_a - release * mu[kFL]) / mu[kFR], std::max(0.0, max_pressure - p[kFR]));
  }
  return p;
}

Esc::Esc(const params::StabilityParams& p)
    : p_(p.ESC),
      model_{p.vehicle.mass.total,
             p.vehicle.dimension.wheelbase,
             p.vehicle.dimension.distance_to_front_axle,
             p.vehicle.dimension.wheelbase - p.vehicle.dimension.distance_to_front_axle,
             p.tire_stiffness_front,
             p.tire_stiffness_rear},
      psi_filter_(p.ESC.tS_psi_dot),
      beta_filter_(p.ESC.tS_beta),
      yaw_inertia_(p.vehicle.inertia.yaw),
      track_width_(p.vehicle.dimension.trackwidth),
      k_wheel_(WheelPressurePerForce(p.tires.front_left.radius.radius_20mps, p.vehicle.brake)),
      max_pressure_(std::max(p.ESC.max_brake_pressure, 0.0)) {
  params::ValidateOrThrow(p);
  const double ts = std::max(p.tS, 1e-6);
  const double i_max = p.ESC.max_integrator_yaw_moment;
  pid_psi_ = Pid({.kp = p.ESC.kp_psi_dot,
                  .ki = p.ESC.ki_psi_dot,
                  .kd = p.ESC.kd_psi_dot,
                  .integrator_min = -i_max,
                  .integrator_max = i_max,
                  .sample_time = ts});
  pid_beta_ = Pid({.kp = p.ESC.kp_beta,
                   .ki = p.ESC.ki_beta,
                   .kd = p.ESC.kd_beta,
                   .integrator_min = -i_max,
                   .integrator_max = i_max,
                   .sample_time = ts});
  const auto n = p.ESC.threshold_velocities.size();
  thresholds_usable_ = n > 0 && p.ESC.beta_threshold_activate.size() == n &&
                       p.ESC.psi_dot_error_threshold_activate.size() == n &&
                       p.ESC.beta_error_threshold_activate.size() == n;
}

Esc::Output Esc::Step(const Input& in, State* s) const noexcept {
  Output out;
  const double v = std::hypot(in.v_x, in.v_y);
  const double beta = std::atan2(in.v_y, in.v_x);
  const bool enabled = p_.enabled && in.slip_angle_valid;

  out.reference = EscReferences(v, in.steering_request, in.ay_request, in.yaw_rate_request,
                                in.beta_request, model_);
  const double e_psi = psi_filter_.Step(out.reference.yaw_rate - in.yaw_rate, &s->e_psi_filtered);
  const double e_beta = beta_filter_.Step(out.reference.beta - beta, &s->e_beta_filtered);
  out.e_psi_filtered = e_psi;
  out.e_beta_filtered = e_beta;

  if (thresholds_usable_) {
    const EscSignals sig{enabled, v, beta, in.yaw_rate, e_psi, e_beta};
    const EscThresholds th = EscThresholdsAt(v, p_);
    out.activation_terms = EscActivationRatios(sig, th);
    out.activation_margin = SmallestTerm(out.activation_terms);
    s->phase = NextEscPhase(s->phase, sig, th);
  } else {
    s->phase = EscPhase::kInactive;
  }
  const bool active = s->phase == EscPhase::kActive;
  out.active = active;

  const PidFlags flags = PidFlags::Gated(active);
  const double u_psi = pid_psi_.Step(e_psi, flags, &s->pid_psi);
  const double u_beta = pid_beta_.Step(-e_beta, flags, &s->pid_beta);
  out.yaw_moment = active ? yaw_inertia_ * (u_psi + u_beta) : 0.0;

  out.pressure = in.pressure_in;
  if (out.yaw_moment != 0.0) {
    out.pressure = AllocateYawMoment(out.yaw_moment, in.pressure_in, in.mu, k_wheel_, track_width_,
                                     max_pressure_);
  }
  out.pressure = Clamp(out.pressure, 0.0, max_pressure_);
  return out;
}

}  // namespace scw::controller
