#include "plant/vehicle/maneuver.h"

#include <algorithm>
#include <cmath>

namespace scw::plant {

double SlipLimitedThrottle(const Measurement& m, double rear_radius, double target_slip,
                           double throttle_max) noexcept {
  const double w = std::max(m.wheel_speed[kRL], m.wheel_speed[kRR]);
  const double slip = (w * rear_radius - m.v_x) / std::max(std::abs(m.v_x), 3.0);
  return std::clamp(throttle_max * (1.0 - 25.0 * (slip - target_slip)), 0.0, throttle_max);
}

Actuators ReferenceManeuverInput(double t, const Measurement& m, double rear_radius) noexcept {
  constexpr double kTwoPi = 6.283185307179586;
  const double tp = std::fmod(t, 20.0);
  Actuators u;
  if (tp < 8.0) {
    u.throttle = SlipLimitedThrottle(m, rear_radius, 0.03);
    u.steer_req = 0.01 * std::sin(kTwoPi * 0.5 * tp);
  } else if (tp < 10.0) {
    u.brake_pressure_req = {70.0, 70.0, 50.0, 50.0};
  } else if (tp < 16.0) {
    u.throttle = std::min(std::clamp(0.3 + 0.2 * (40.0 - m.v_x), 0.0, 1.0),
                          SlipLimitedThrottle(m, rear_radius, 0.03));
    u.steer_req = 0.05;
  } else {
    u.throttle = SlipLimitedThrottle(m, rear_radius, 0.03, 0.7);
    u.steer_req = 0.03 * std::sin(kTwoPi * 0.8 * tp);
  }
  return u;
}

ManeuverSummary RunReferenceManeuver(const Vehicle& v, double duration, State* s) noexcept {
  return RunReferenceManeuverOn(v, duration, s);
}

}  // namespace scw::plant
