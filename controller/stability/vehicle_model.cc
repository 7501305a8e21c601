#include "controller/stability/vehicle_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "controller/common/interp.h"

namespace scw::controller {

ChassisGeometry ChassisGeometry::From(const params::StabilityParams& p) noexcept {
  const auto& d = p.vehicle.dimension;
  return {d.wheelbase, d.distance_to_front_axle, d.wheelbase - d.distance_to_front_axle,
          d.track_width_front, d.track_width_rear};
}

Wheels YawSpeedOffsets(double yaw_rate, const ChassisGeometry& g) noexcept {
  const double f = 0.5 * g.track_front * yaw_rate;
  const double r = 0.5 * g.track_rear * yaw_rate;
  return {-f, f, -r, r};
}

PerWheel<TyreVelocity> TyreVelocities(double v_x, double v_y, double yaw_rate, double steering,
                                      const ChassisGeometry& g) noexcept {
  const Wheels dx = YawSpeedOffsets(yaw_rate, g);
  const double vy_front = v_y + g.l_front * yaw_rate;
  const double vy_rear = v_y - g.l_rear * yaw_rate;
  const double c = std::cos(steering);
  const double s = std::sin(steering);
  PerWheel<TyreVelocity> out;
  for (std::size_t i = 0; i < 2; ++i) {
    const double vx_w = v_x + dx[i];
    out[i] = {c * vx_w + s * vy_front, -s * vx_w + c * vy_front};
  }
  for (std::size_t i = 2; i < 4; ++i) out[i] = {v_x + dx[i], vy_rear};
  return out;
}

double TyreSlipAngle(const TyreVelocity& v) noexcept {
  return -std::atan2(v.lateral, std::max(1.0, v.longitudinal));
}

Wheels SlipAngles(double v_x, double v_y, double yaw_rate, double steering,
                  const ChassisGeometry& g) noexcept {
  const auto v = TyreVelocities(v_x, v_y, yaw_rate, steering, g);
  return {TyreSlipAngle(v[0]), TyreSlipAngle(v[1]), TyreSlipAngle(v[2]), TyreSlipAngle(v[3])};
}

double DynamicTyreRadius(double radius_20mps, double speed,
                         const params::VelocityScaling& scaling) noexcept {
  return radius_20mps * Interp(speed, scaling.velocity, scaling.factor);
}

LoadModel LoadModel::From(const params::StabilityParams& p) noexcept {
  const auto& v = p.vehicle;
  return {v.mass.total,
          ChassisGeometry::From(p),
          v.dimension.cog_height,
          v.aero.air_density,
          v.aero.cross_track_area,
          v.aero.lift_coeff,
          v.aero.front_downforce_share};
}

Wheels QuasiStaticVerticalLoads(const LoadModel& m, double v_x, double a_x, double a_y) noexcept {
  const auto& g = m.geometry;
  const double l = g.wheelbase;
  const double front_static = m.mass * kGravity * g.l_rear / (2.0 * l);
  const double rear_static = m.mass * kGravity * g.l_front / (2.0 * l);
  const double aero = 0.5 * m.air_density * m.area * (-m.lift_coeff) * v_x * v_x;
  const double front_aero = 0.5 * m.front_downforce_share * aero;
  const double rear_aero = 0.5 * (1.0 - m.front_downforce_share) * aero;
  const double long_transfer = 0.5 * m.mass * a_x * m.cog_height / l;
  const double lat_moment = m.mass * a_y * m.cog_height;
  const double lat_front = (g.l_rear / l) * lat_moment / g.track_front;
  const double lat_rear = (g.l_front / l) * lat_moment / g.track_rear;
  const double front = front_static + front_aero - long_transfer;
  const double rear = rear_static + rear_aero + long_transfer;
  return {std::max(0.0, front - lat_front), std::max(0.0, front + lat_front),
          std::max(0.0, rear - lat_rear), std::max(0.0, rear + lat_rear)};
}

double AxlePressurePerForce(double tyre_radius, const params::VehicleBrake& b) noexcept {
  const double half_d = 0.5 * b.piston_diameter;
  const double den =
      2.0 * b.pad_mean_radius * b.pad_number * std::numbers::pi * half_d * half_d * 1e5;
  return tyre_radius / std::max(den, 1e-6);
}

double WheelPressurePerForce(double tyre_radius, const params::VehicleBrake& b) noexcept {
  const double half_d = 0.5 * b.piston_diameter;
  const double den = b.pad_mean_radius * b.pad_number * std::numbers::pi * half_d * half_d * 1e5;
  return tyre_radius / std::max(den, 1e-6);
}

double SanitizeBrakeFriction(double mu) noexcept {
  if (!std::isfinite(mu)) return 1e-6;
  return std::max(mu, 1e-6);
}

double FrontBrakeBias(double v_x, double bias, const params::BrakeBiasShift& shift) noexcept {
  double delta = 0.0;
  if (!shift.values.empty() && shift.values.size() == shift.vel_interp_mps.size()) {
    delta = Interp(v_x, shift.vel_interp_mps, shift.values);
  }
  return std::clamp(bias + delta, 0.0, 1.0);
}

}  // namespace scw::controller
