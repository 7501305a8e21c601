#include "controller/stability/countersteer.h"

#include <algorithm>
#include <cmath>

namespace scw::controller {

double CountersteerCommand(double steering_request, double alpha_front, double alpha_rear,
                           const params::CountersteerParams& cs,
                           const params::VehicleSteering& limits, bool* active) noexcept {
  double out = steering_request;
  *active = cs.enabled && std::abs(alpha_rear) > std::abs(alpha_front) &&
            std::abs(alpha_rear) > cs.enable_sideslip;
  if (*active) out = steering_request + cs.steering_factor * (alpha_front - alpha_rear);
  return std::clamp(out, limits.min_angle, limits.max_angle);
}

Countersteer::Countersteer(const params::StabilityParams& p)
    : cs_(p.countersteer_system),
      limits_(p.vehicle.steering),
      geometry_(ChassisGeometry::From(p)),
      filter_(LowPass::FromTimeConstant(p.countersteer_system.slip_angle_filter_Ts,
                                        std::max(p.tS, 1e-6))) {
  params::ValidateOrThrow(p);
}

Countersteer::Output Countersteer::Step(const Input& in, State* s) const noexcept {
  Output out;
  out.alpha_front_filtered = s->alpha_front_filtered;
  out.alpha_rear_filtered = s->alpha_rear_filtered;
  const double fz_front = in.fz[kFL] + in.fz[kFR];
  const double fz_rear = in.fz[kRL] + in.fz[kRR];
  const bool loads_ok =
      std::isfinite(fz_front) && std::isfinite(fz_rear) && fz_front > 1e-6 && fz_rear > 1e-6;
  if (!in.slip_angle_valid || !loads_ok) {
    out.steering = std::clamp(in.steering_request, limits_.min_angle, limits_.max_angle);
    return out;
  }
  const Wheels alpha = SlipAngles(in.v_x, in.v_y, in.yaw_rate, in.steering, geometry_);
  const double alpha_f = (in.fz[kFL] * alpha[kFL] + in.fz[kFR] * alpha[kFR]) / fz_front;
  const double alpha_r = (in.fz[kRL] * alpha[kRL] + in.fz[kRR] * alpha[kRR]) / fz_rear;
  out.alpha_front_filtered = filter_.Step(alpha_f, &s->alpha_front_filtered);
  out.alpha_rear_filtered = filter_.Step(alpha_r, &s->alpha_rear_filtered);
  out.steering = CountersteerCommand(in.steering_request, out.alpha_front_filtered,
                                     out.alpha_rear_filtered, cs_, limits_, &out.active);
  return out;
}

}  // namespace scw::controller
