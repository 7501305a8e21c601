#include "plant/vehicle/ggv.h"

#include <algorithm>
#include <cmath>

#include "plant/vehicle/vehicle.h"

namespace scw::plant {
namespace {

// Target slips of the ideal slip controllers; beyond the force peak an integral slip loop is
// unstable, its oscillation only lowers the average, so the sweep picks the best stable one.
constexpr double kTargetSlips[] = {0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09, 0.10, 0.12};

params::VehicleParams IdealActuators(params::VehicleParams p) {
  p.brakes.delay = 0.0;
  p.brakes.time_constant = 0.0;
  p.brakes.rate_limit = 100000.0;
  p.brakes.max_pressure = 500.0;
  p.steering.delay = 0.0;
  p.steering.time_constant = 0.0;
  p.steering.rate_limit = 20.0;
  p.sensors.noise = false;
  return p;
}

double LateralLimit(const Vehicle& veh, double v, bool* lock_limited) {
  const double h = veh.time_step();
  const double l = veh.params().chassis.wheelbase;
  const double max_angle = veh.params().steering.max_angle;
  // Steering needed for ~45 m/s^2 with a generous understeer allowance: beyond any limit.
  const double steer_end = std::min(max_angle, (l / (v * v) + 0.001) * 45.0);
  const double ramp_time = 10.0;
  State s = veh.MakeState({.speed = v});
  Actuators u;
  double integral = 0.0, best = 0.0;
  const int steps = static_cast<int>(ramp_time / h);
  // Quasi-steady samples are judged over windows of ~50 ms (mean a_y, yaw acceleration).
  const int window = std::max(1, static_cast<int>(0.05 / h));
  double ay_sum = 0.0, r_start = s.x[kYawRate];
  bool in_band = true;
  for (int k = 0; k < steps; ++k) {
    const double t = k * h;
    const double e = v - s.x[kVx];
    integral = std::clamp(integral + e * h, -5.0, 5.0);
    const double cmd = 0.4 * e + 0.3 * integral + 0.05;
    u.throttle = std::clamp(cmd, 0.0, 1.0);
    const double brake = std::clamp(-40.0 * (cmd + 0.2), 0.0, 200.0);
    u.brake_pressure_req = {brake, brake, brake, brake};
    u.steer_req = steer_end * std::min(1.0, t / ramp_time);
    veh.Step(u, &s);
    if (s.status != kStatusOk) break;
    const double beta = std::atan2(s.x[kVy], std::max(std::abs(s.x[kVx]), 1.0));
    if (std::abs(beta) > 0.25) break;
    // Quasi-steady cornering only: small yaw acceleration over the window (a breakaway transient
    // has a large one).
    ay_sum += s.out.a_y;
    in_band = in_band && std::abs(s.x[kVx] - v) <= 0.02 * v;
    if ((k + 1) % window == 0) {
      const double ay = ay_sum / window;
      const double r_dot = (s.x[kYawRate] - r_start) / (window * h);
      if (in_band && std::abs(r_dot) <= 0.3) best = std::max(best, ay);
      if (best > 5.0 && ay < 0.9 * best) break;  // past the limit (plough or spin)
      ay_sum = 0.0;
      r_start = s.x[kYawRate];
      in_band = true;
    }
  }
  *lock_limited =
      steer_end >= max_angle && s.steering.angle >= 0.999 * max_angle && s.out.a_y >= 0.98 * best;
  return best;
}

double BrakingLimit(const Vehicle& veh, double v, double target_slip) {
  const double h = veh.time_step();
  const double dv = std::max(5.0, 0.15 * v);
  State s = veh.MakeState({.speed = v + dv});
  Actuators u;
  PerWheel<double> p{};
  double sum = 0.0;
  long n = 0;
  const int max_steps = static_cast<int>(10.0 / h);
  for (int k = 0; k < max_steps && s.x[kVx] > v - 0.02 * v; ++k) {
    for (std::size_t i = 0; i < 4; ++i) {
      // Integral slip control: more pressure while the slip is below the target magnitude.
      p[i] = std::clamp(p[i] + h * 4000.0 * (s.out.kappa[i] + target_slip), 0.0, 500.0);
    }
    u.brake_pressure_req = p;
    veh.Step(u, &s);
    if (s.status != kStatusOk) return 0.0;
    if (std::abs(s.x[kVx] - v) <= 0.02 * v) {
      sum += -s.out.a_x;
      ++n;
    }
  }
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

double TractionLimit(const Vehicle& veh, double v, double target_slip) {
  const double h = veh.time_step();
  const double dv = std::max(3.0, 0.1 * v);
  State s = veh.MakeState({.speed = std::max(0.0, v - dv)});
  Actuators u;
  double throttle = 1.0, sum = 0.0;
  long n = 0;
  const int max_steps = static_cast<int>(30.0 / h);
  for (int k = 0; k < max_steps && s.x[kVx] < v + 0.02 * v; ++k) {
    const double slip = std::max(s.out.kappa[kRL], s.out.kappa[kRR]);
    throttle = std::clamp(throttle + h * 20.0 * (target_slip - slip), 0.0, 1.0);
    u.throttle = throttle;
    veh.Step(u, &s);
    if (s.status != kStatusOk) break;
    const bool shifting = s.gearbox.phase == ShiftPhase::kShifting ||
                          s.gearbox.time_in_phase < 0.05;  // torque rebuilds after engagement
    if (!shifting && std::abs(s.x[kVx] - v) <= 0.02 * v) {
      sum += s.out.a_x;
      ++n;
    }
  }
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace

GgvPoint ComputeGgvPoint(const params::VehicleParams& p, double speed) {
  const Vehicle veh(IdealActuators(p));
  params::VehicleParams no_drag = IdealActuators(p);
  no_drag.aero.drag_area = 0.0;
  no_drag.wheels.rolling_resistance = 0.0;
  const Vehicle veh_lateral(no_drag);
  GgvPoint g;
  g.speed = speed;
  g.lateral_max = LateralLimit(veh_lateral, speed, &g.lateral_lock_limited);
  for (double slip : kTargetSlips)
    g.braking_max = std::max(g.braking_max, BrakingLimit(veh, speed, slip));
  for (double slip : kTargetSlips)
    g.traction_max = std::max(g.traction_max, TractionLimit(veh, speed, slip));
  return g;
}

}  // namespace scw::plant
