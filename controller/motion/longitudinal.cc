#include "controller/motion/longitudinal.h"

#include <algorithm>
#include <cmath>

namespace scw::controller::motion {
namespace {
constexpr double kG = 9.81;

// Index i with xs[i] <= x < xs[i+1] (clamped) and the fraction within.
void Locate(const std::vector<double>& xs, double x, std::size_t* i, double* t) {
  const std::size_t n = xs.size();
  if (x <= xs.front()) {
    *i = 0, *t = 0.0;
    return;
  }
  if (x >= xs.back()) {
    *i = n - 2, *t = 1.0;
    return;
  }
  std::size_t k = 0;
  while (k + 2 < n && x >= xs[k + 1]) ++k;
  *i = k;
  *t = (x - xs[k]) / (xs[k + 1] - xs[k]);
}
}  // namespace

LongitudinalController::LongitudinalController(const params::LongitudinalParams& p,
                                               LongitudinalModel model, double sample_time)
    : p_(p),
      m_(std::move(model)),
      ts_(sample_time),
      fb_filter_(LowPass::FromTimeConstant(p.feedback_time_constant, sample_time)),
      d_filter_(LowPass::FromTimeConstant(p.derivative_time_constant, sample_time)) {
  Problems pr = params::Validate(p_);
  if (m_.map_speed.size() < 2 || m_.map_throttle.size() < 2 ||
      m_.map_torque.size() != m_.map_speed.size() * m_.map_throttle.size())
    pr.Add("engine map", "needs >= 2 speed and throttle breakpoints and speed x throttle torques");
  if (m_.gear_ratios.empty()) pr.Add("gear_ratios", "needs at least one gear");
  if (!(m_.mass > 0) || !(m_.brake_gain_front > 0) || !(m_.brake_gain_rear > 0) ||
      !(m_.radius_front > 0) || !(m_.radius_rear > 0) || !(sample_time > 0))
    pr.Add("model", "mass, radii, brake gains and the sample time must be positive");
  if (!pr.empty()) throw ConfigError("longitudinal controller", pr.items());
}

double LongitudinalController::EngineTorque(double omega_e, double throttle) const noexcept {
  std::size_t i, j;
  double ti, tj;
  Locate(m_.map_speed, omega_e, &i, &ti);
  Locate(m_.map_throttle, throttle, &j, &tj);
  const std::size_t nt = m_.map_throttle.size();
  auto at = [&](std::size_t a, std::size_t b) { return m_.map_torque[a * nt + b]; };
  const double low = at(i, j) + ti * (at(i + 1, j) - at(i, j));
  const double high = at(i, j + 1) + ti * (at(i + 1, j + 1) - at(i, j + 1));
  return low + tj * (high - low);
}

double LongitudinalController::DriveForce(double omega_e, int gear,
                                          double throttle) const noexcept {
  const int g = std::clamp(gear, 1, static_cast<int>(m_.gear_ratios.size()));
  const double ratio = m_.gear_ratios[static_cast<std::size_t>(g - 1)] * m_.final_drive;
  const double w = std::isfinite(omega_e) ? omega_e : 0.0;
  return EngineTorque(w, throttle) * ratio * m_.efficiency / m_.radius_rear;
}

double LongitudinalController::ThrottleFor(double omega_e, double torque) const noexcept {
  const auto& th = m_.map_throttle;
  double prev = EngineTorque(omega_e, th.front());
  if (torque <= prev) return th.front();
  for (std::size_t j = 1; j < th.size(); ++j) {
    const double cur = EngineTorque(omega_e, th[j]);
    if (torque <= cur) {
      const double f = cur > prev ? (torque - prev) / (cur - prev) : 1.0;
      return std::clamp(th[j - 1] + f * (th[j] - th[j - 1]), 0.0, 1.0);
    }
    prev = cur;
  }
  return std::clamp(th.back(), 0.0, 1.0);
}

LongitudinalOutput LongitudinalController::Step(const LongitudinalInput& in,
                                                State* s) const noexcept {
  LongitudinalOutput out;
  const double v = std::isfinite(in.speed) ? std::max(0.0, in.speed) : 0.0;
  const double ax_req = std::isfinite(in.ax_request) ? in.ax_request : 0.0;
  const double ax = std::isfinite(in.a_x) ? in.a_x : ax_req;
  const double q = 0.5 * m_.air_density * v * v;
  const double ff = p_.rotational_inertia_factor * m_.mass * ax_req + q * m_.drag_area +
                    m_.rolling_resistance * (m_.mass * kG + q * m_.downforce_area);
  const double e = ax_req - ax;
  if (!s->initialised) {
    s->e_prev = e;
    s->force = ff;
    s->initialised = true;
  }
  const double p_term = std::clamp(p_.kp * e, -p_.feedback_limit, p_.feedback_limit);
  const double d_term = d_filter_.Step(p_.kd * (e - s->e_prev) / ts_, &s->d);
  s->e_prev = e;
  const double fb = fb_filter_.Step(p_term + d_term, &s->fb);
  const bool hold = p_.hold_during_esc && in.esc_active;
  double force = ff + (in.slip_control_active || hold ? 0.0 : fb);
  const double dmax = p_.max_force_rate * ts_;
  force = std::clamp(force, s->force - dmax, s->force + (hold ? 0.0 : dmax));
  force = std::clamp(force, p_.force_min, p_.force_max);
  if (!std::isfinite(force)) force = 0.0;
  s->force = force;
  out.force = force;

  const int g = std::clamp(in.gear, 1, static_cast<int>(m_.gear_ratios.size()));
  const double ratio = m_.gear_ratios[static_cast<std::size_t>(g - 1)] * m_.final_drive;
  const double omega_e = std::isfinite(in.engine_speed) ? in.engine_speed : 0.0;
  // Engine drag at closed throttle, as a force at the rear wheels (≤ 0 normally).
  const double f_engine_brake = EngineTorque(omega_e, 0.0) * ratio * m_.efficiency / m_.radius_rear;
  if (force >= std::min(0.0, f_engine_brake)) {
    const double torque = force * m_.radius_rear / (ratio * m_.efficiency);
    out.throttle = ThrottleFor(omega_e, torque);
  } else {
    const double fb_total = -(force - std::min(0.0, f_engine_brake));  // > 0
    const double b = p_.brake_bias_front;
    const double pf = b * fb_total * m_.radius_front / (2.0 * m_.brake_gain_front);
    const double prr = (1.0 - b) * fb_total * m_.radius_rear / (2.0 * m_.brake_gain_rear);
    out.brake_bar = {std::min(pf, m_.max_pressure), std::min(pf, m_.max_pressure),
                     std::min(prr, m_.max_pressure), std::min(prr, m_.max_pressure)};
  }
  return out;
}

}  // namespace scw::controller::motion
