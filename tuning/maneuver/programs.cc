#include "tuning/maneuver/programs.h"

#include <algorithm>
#include <cmath>

namespace scw::tuning {

double SineWithDwell::At(double t) const noexcept {
  const double w = 2.0 * M_PI * frequency;
  if (t < 0.0 || t >= Duration()) return 0.0;
  if (t < DwellStart()) return amplitude * std::sin(w * t);
  if (t < DwellStart() + dwell) return -amplitude;
  return amplitude * std::sin(w * (t - dwell));
}

double StepSteer(double t, double amplitude, double rise_time) noexcept {
  if (t <= 0.0) return 0.0;
  if (t >= rise_time) return amplitude;
  return amplitude * t / rise_time;
}

double RampSteer(double t, double rate) noexcept { return t <= 0.0 ? 0.0 : rate * t; }

std::vector<double> SineWithDwellFactors(const std::vector<double>& factors, double a_handwheel_deg,
                                         bool extend_to_270deg) {
  constexpr double kTarget = 270.0, kCap = 300.0;
  std::vector<double> series = factors;
  if (extend_to_270deg && !series.empty() && a_handwheel_deg > 0.0) {
    double f = series.back();
    while (f * a_handwheel_deg < kTarget) {
      f += 0.5;
      series.push_back(f);
    }
  }
  std::vector<double> out;
  const double cap_factor = a_handwheel_deg > 0.0 ? kCap / a_handwheel_deg : 0.0;
  for (double f : series) {
    if (a_handwheel_deg > 0.0 && f * a_handwheel_deg > kCap) {
      if (out.empty() || out.back() < cap_factor) out.push_back(cap_factor);
      break;
    }
    out.push_back(f);
  }
  return out;
}

PerWheel<double> BrakePressuresFor(double decel, double front_share,
                                   const params::VehicleParams& v) noexcept {
  const double force = v.chassis.mass * decel;
  const double pf =
      front_share * force * v.wheels.radius_front / (2.0 * v.brakes.torque_gain_front);
  const double pr =
      (1.0 - front_share) * force * v.wheels.radius_rear / (2.0 * v.brakes.torque_gain_rear);
  const double cap = v.brakes.max_pressure;
  return {std::min(pf, cap), std::min(pf, cap), std::min(pr, cap), std::min(pr, cap)};
}

double BrakeForceOf(const PerWheel<double>& p, const params::VehicleParams& v) noexcept {
  const double front = (p[0] + p[1]) * v.brakes.torque_gain_front / v.wheels.radius_front;
  const double rear = (p[2] + p[3]) * v.brakes.torque_gain_rear / v.wheels.radius_rear;
  return -(front + rear);
}

}  // namespace scw::tuning
