#include "controller/stability/stability_controller.h"

#include <algorithm>
#include <cmath>

#include "controller/common/interp.h"
#include "controller/common/state_visit.h"
#include "controller/stability/vehicle_model.h"

namespace scw::controller {
namespace {

// Plausibility limits of the sanitising step: beyond them a signal counts as unavailable
// (optional) or invalid (essential). They only keep every intermediate value finite.
constexpr double kMaxSpeed = 200.0;         // [m/s]
constexpr double kMaxYawRate = 50.0;        // [rad/s]
constexpr double kMaxAcceleration = 200.0;  // [m/s²]
constexpr double kMaxAngle = 1.5;           // [rad]
constexpr double kMaxWheelSpeed = 5000.0;   // [rad/s]
constexpr double kMaxEngineSpeed = 1.0e5;   // [rad/s]
constexpr double kMaxPressure = 1.0e4;      // [bar]
constexpr double kMaxForce = 1.0e7;         // [N]
constexpr double kMaxTemperature = 1.0e4;   // [°C]

bool Within(double x, double limit) { return std::isfinite(x) && std::abs(x) <= limit; }
double OrZero(double x, double limit) { return Within(x, limit) ? x : 0.0; }

bool AllWithin(const Wheels& w, double limit) {
  return Within(w[0], limit) && Within(w[1], limit) && Within(w[2], limit) && Within(w[3], limit);
}

bool Finite(double x) { return std::isfinite(x); }

bool OutputFinite(const StabilityOutput& o) {
  return Finite(o.steering) && AllFinite(o.brake_bar) && Finite(o.throttle) &&
         Finite(o.yaw_moment) && Finite(o.yaw_rate_ref) && AllFinite(o.slip_pct) &&
         AllFinite(o.slip_angle);
}

}  // namespace

StabilityController::StabilityController(const params::StabilityParams& p,
                                         const params::StabilityOptions& options)
    : p_(p),
      options_(options),
      slip_estimator_(p),
      esc_(p),
      slip_control_(p, options),
      countersteer_(p) {
  // The sub-controllers have validated p (and SlipControl the options and the ring-buffer size).
  const auto& map = p.vehicle.brake.friction;
  friction_map_usable_ = !map.temperature.empty() && !map.coefficient.empty() &&
                         map.temperature.size() == map.coefficient.size();
}

StabilityOutput StabilityController::PassThrough(const Input& in) const noexcept {
  Output out;
  const auto& lim = p_.vehicle.steering;
  out.steering = std::clamp(Finite(in.steering_request) ? in.steering_request : 0.0, lim.min_angle,
                            lim.max_angle);
  const double p_max = std::max(p_.ESC.max_brake_pressure, 0.0);
  for (std::size_t i = 0; i < 4; ++i) {
    const double p = in.brake_request_bar[i];
    out.brake_bar[i] = std::clamp(Finite(p) ? p : 0.0, 0.0, p_max);
  }
  out.throttle = std::clamp(Finite(in.throttle_request) ? in.throttle_request : 0.0, 0.0, 1.0);
  out.gear = in.gear_request;
  out.valid = false;
  return out;
}

StabilityOutput StabilityController::Step(const Input& in, State* s) const noexcept {
  // 1. Validity of the essential inputs (odometry, tracking request, longitudinal request).
  const bool essential = Finite(in.t) && Within(in.v_x, kMaxSpeed) && Within(in.v_y, kMaxSpeed) &&
                         Within(in.yaw_rate, kMaxYawRate) && Finite(in.steering_request) &&
                         AllWithin(in.brake_request_bar, kMaxPressure) &&
                         Finite(in.throttle_request);
  if (!essential) return PassThrough(in);

  const bool accel_ok = Within(in.a_x, kMaxAcceleration) && Within(in.a_y, kMaxAcceleration);
  const double a_x = accel_ok ? in.a_x : 0.0;
  const double a_y = accel_ok ? in.a_y : 0.0;
  const bool steering_meas_ok = Within(in.steering_measured, kMaxAngle);
  const double delta = steering_meas_ok ? in.steering_measured : in.steering_request;
  const bool wheels_ok = AllWithin(in.wheel_speed, kMaxWheelSpeed);
  const bool engine_ok = Within(in.engine_speed, kMaxEngineSpeed);
  const bool fz_ok = AllWithin(in.fz_external, kMaxForce) && MinElement(in.fz_external) >= 0.0;
  const double long_fx = EffectiveLongFx(options_, OrZero(in.long_fx, kMaxForce));
  const bool slip_angle_valid = true;  // odometry ∧ (steering report ∨ tracking request)
  const bool slip_valid = slip_angle_valid && wheels_ok;

  Output out;
  out.valid = true;
  out.slip_angle_valid = slip_angle_valid;
  out.slip_valid = slip_valid;
  out.gear = in.gear_request;

  // 2. Slip estimation.
  const SlipEstimator::Input se_in{
      .v_x = in.v_x,
      .v_y = in.v_y,
      .yaw_rate = in.yaw_rate,
      .a_x = a_x,
      .a_y = a_y,
      .steering = delta,
      .wheel_speed = wheels_ok ? in.wheel_speed : Wheels{},
      .wheel_speeds_valid = wheels_ok,
      .front_pressure_max_bar = std::max(OrZero(in.brake_measured_bar[kFL], kMaxPressure),
                                         OrZero(in.brake_measured_bar[kFR], kMaxPressure)),
      .gear = in.gear,
      .engine_speed = engine_ok ? in.engine_speed : 0.0,
      .engine_speed_valid = engine_ok,
      .fz_external = fz_ok ? in.fz_external : Wheels{},
      .fz_external_valid = fz_ok};
  const SlipEstimator::Output slips = slip_estimator_.Step(se_in, &s->slip);

  // 3. Pad friction.
  const auto& brake = p_.vehicle.brake;
  Wheels mu{};
  for (std::size_t i = 0; i < 4; ++i) {
    const double temp = in.brake_temperature_degc[i];
    const double raw = (friction_map_usable_ && Within(temp, kMaxTemperature))
                           ? Interp(temp, brake.friction.temperature, brake.friction.coefficient)
                           : brake.friction_coeff;
    mu[i] = SanitizeBrakeFriction(raw);
  }

  // 4. ESC on the request.
  const Esc::Input esc_in{
      .v_x = in.v_x,
      .v_y = in.v_y,
      .yaw_rate = in.yaw_rate,
      .steering_request = in.steering_request,
      .ay_request = Within(in.ay_request, kMaxAcceleration) ? in.ay_request : kNotAvailable,
      .yaw_rate_request =
          Within(in.yaw_rate_request, kMaxYawRate) ? in.yaw_rate_request : kNotAvailable,
      .beta_request = Within(in.beta_request, kMaxAngle * 2.0) ? in.beta_request : kNotAvailable,
      .pressure_in = in.brake_request_bar,
      .mu = mu,
      .slip_angle_valid = slip_angle_valid};
  const Esc::Output esc = esc_.Step(esc_in, &s->esc);

  // 5. Slip control on the ESC output.
  const SlipControl::Input sc_in{.slip_pct = slips.slip_pct,
                                 .virtual_slip_pct = slips.virtual_slip_pct,
                                 .fz = slips.fz,
                                 .slip_angle = slips.slip_angle,
                                 .slip_valid = slip_valid,
                                 .pressure_in = esc.pressure,
                                 .mu = mu,
                                 .long_fx = long_fx,
                                 .esc_active = esc.active,
                                 .v_x = in.v_x,
                                 .t = in.t,
                                 .gear = in.gear,
                                 .gear_request = in.gear_request,
                                 .throttle = in.throttle_request};
  const SlipControl::Output sc = slip_control_.Step(sc_in, &s->slip_control);

  // 6. Countersteer.
  const Countersteer::Input cs_in{.v_x = in.v_x,
                                  .v_y = in.v_y,
                                  .yaw_rate = in.yaw_rate,
                                  .steering = delta,
                                  .steering_request = in.steering_request,
                                  .fz = slips.fz,
                                  .slip_angle_valid = slip_angle_valid};
  const Countersteer::Output cs = countersteer_.Step(cs_in, &s->countersteer);

  out.steering = cs.steering;
  out.brake_bar = sc.pressure;
  // The request is essential only as finite: clamp like the pass-through, so an absurd request
  // (1e12) never reaches the engine as more than full throttle.
  out.throttle = std::clamp(sc.throttle, 0.0, 1.0);
  out.esc_active = esc.active;
  out.cs_active = cs.active;
  out.slip_control_active = sc.active;
  out.abs_state = sc.abs_phase;
  out.tc_state = sc.tc_phase;
  out.yaw_moment = esc.yaw_moment;
  out.yaw_rate_ref = esc.reference.yaw_rate;
  out.esc_margin = esc.activation_margin;
  out.esc_margin_terms = esc.activation_terms;
  out.slip_pct = slips.slip_pct;
  out.slip_angle = slips.slip_angle;
  out.v_ref = slips.v_ref;
  out.fz = slips.fz;
  out.mu = mu;
  out.throttle_cut = sc.throttle_cut;
  out.shift_reduction = sc.shift_reduction;
  out.alpha_front_filtered = cs.alpha_front_filtered;
  out.alpha_rear_filtered = cs.alpha_rear_filtered;

  // 7. Guard.
  if (!OutputFinite(out) || !StateFinite(*s)) {
    *s = State{};
    return PassThrough(in);
  }
  return out;
}

}  // namespace scw::controller
