// Vehicle kinematics, vertical loads and brake force ↔ pressure factors shared by slip estimation,
// slip control, ESC and countersteer (stability-control spec §2.2–§2.6, §3.3, §4.6).
//
// Frames and signs (spec §0.2): body frame at the CoG, x forward, y left; yaw rate ψ̇ > 0 turns
// left; steering δ (tyre angle) > 0 left, applied to both front wheels (no Ackermann). Wheel order
// FL, FR, RL, RR.
//
// Wheel ground velocity (CoG velocity v_x, v_y, yaw rate ψ̇):
//   v_x,w,i = v_x + Δ_i,  Δ_i = (tw_axle/2)·ψ̇·(−1 left, +1 right)          [m/s]
//   v_y,w = v_y + l_f·ψ̇ (front), v_y − l_r·ψ̇ (rear)                          [m/s]
// Tyre frame (fronts rotated by δ, rears not):
//   v_x,t = cos δ·v_x,w + sin δ·v_y,w,  v_y,t = −sin δ·v_x,w + cos δ·v_y,w
// Tyre slip angle α = −atan2(v_y,t, max(1, v_x,t)) [rad]; α > 0 gives a leftward force.
//
// Dynamic tyre radius r(v) = r_20·interp(v; velocity, factor) [m] (extrapolated, spec §2.2).
//
// Quasi-static vertical loads (spec §2.6). The reference's load function is not public; this is
// the workspace's documented substitute (an ASSUMPTION, not the car's code):
//   static      Fz_f,stat = m·g·l_r/(2l) per front wheel, Fz_r,stat = m·g·l_f/(2l) per rear wheel
//   downforce   F_aero = ½·ρ·A·(−c_L)·v_x²; front wheels share s_f·F_aero/2 each, rears
//               (1 − s_f)·F_aero/2 each, s_f = vehicle.aero.front_downforce_share
//   long. transfer  ΔF_x = m·a_x·h/l: each front wheel −ΔF_x/2, each rear wheel +ΔF_x/2
//   lat. transfer   ΔF_y,axle = (axle static share)·m·a_y·h/tw_axle with share l_r/l (front) and
//               l_f/l (rear); a_y > 0 (left turn) loads the RIGHT wheels: left −ΔF_y, right +ΔF_y
//   h = vehicle.dimension.cog_height, g = 9.81 m/s²; each load floored at 0 N (wheel lift).
// Inputs v_x [m/s], a_x, a_y [m/s²] (raw, unfiltered); output [N].
//
// Brake force → pressure (spec §3.3, §4.6), r_pad, n_pad, d from vehicle.brake:
//   k_axle  = r_tyre / (2·r_pad·n_pad·π·(d/2)²·1e5)  [bar/N]: pressure on each wheel of an axle for
//             a total axle brake force (the 2 = two wheels), denominator floored at 1e-6
//   k_wheel = r_tyre / (r_pad·n_pad·π·(d/2)²·1e5)    [bar/N]: one wheel's force → its pressure
//   (ESC) both to be divided by the pad friction μ. Code-default geometry: k_axle,front =
//   0.0021895, k_axle,rear = 0.0022936, k_wheel,front = 0.0043790 bar/N (Appendix B).
// Brake bias b(v) = clamp(P_VDC_brake_bias_front + shift(v), 0, 1) with the extrapolated shift
// table (spec §3.3; 0.433 @ 7 m/s … 0.618 @ 80 m/s with the shipped values).
// Pad friction sanitising (spec §1.3 step 6): non-finite → 1e-6, else max(μ, 1e-6).
#pragma once

#include "controller/common/per_wheel_ops.h"
#include "params/schema/stability_params.h"

namespace scw::controller {

inline constexpr double kGravity = 9.81;  ///< [m/s²], the reference's value

struct ChassisGeometry {
  double wheelbase = 2.971;    ///< l [m]
  double l_front = 1.724;      ///< CoG → front axle [m]
  double l_rear = 1.247;       ///< CoG → rear axle [m] = l − l_f
  double track_front = 1.639;  ///< [m]
  double track_rear = 1.524;   ///< [m]

  static ChassisGeometry From(const params::StabilityParams& p) noexcept;
};

struct TyreVelocity {
  double longitudinal = 0.0;  ///< v_x,t [m/s]
  double lateral = 0.0;       ///< v_y,t [m/s]
};

/// Δ_i [m/s]: yaw-induced longitudinal speed offset of each wheel (left −, right +).
Wheels YawSpeedOffsets(double yaw_rate, const ChassisGeometry& g) noexcept;

/// Tyre-frame velocities of the four wheels for CoG velocity (v_x, v_y) [m/s], yaw rate [rad/s]
/// and front steering angle δ [rad].
PerWheel<TyreVelocity> TyreVelocities(double v_x, double v_y, double yaw_rate, double steering,
                                      const ChassisGeometry& g) noexcept;

/// α = −atan2(v_y,t, max(1, v_x,t)) [rad].
double TyreSlipAngle(const TyreVelocity& v) noexcept;

/// Raw slip angles of the four wheels (no low-speed fade) [rad].
Wheels SlipAngles(double v_x, double v_y, double yaw_rate, double steering,
                  const ChassisGeometry& g) noexcept;

/// r(v) = r_20·interp(v; scaling.velocity, scaling.factor) [m].
double DynamicTyreRadius(double radius_20mps, double speed,
                         const params::VelocityScaling& scaling) noexcept;

struct LoadModel {
  double mass = 800.0;                  ///< m [kg]
  ChassisGeometry geometry{};           ///< l, l_f, l_r, track widths
  double cog_height = 0.3;              ///< h [m]
  double air_density = 1.22;            ///< ρ [kg/m³]
  double area = 1.0;                    ///< A [m²]
  double lift_coeff = -1.65;            ///< c_L [–], negative = downforce
  double front_downforce_share = 0.45;  ///< s_f [–]

  static LoadModel From(const params::StabilityParams& p) noexcept;
};

/// Quasi-static vertical loads [N] (see the header comment).
Wheels QuasiStaticVerticalLoads(const LoadModel& m, double v_x, double a_x, double a_y) noexcept;

/// k_axle [bar/N] (before division by μ).
double AxlePressurePerForce(double tyre_radius, const params::VehicleBrake& brake) noexcept;
/// k_wheel = 2·k_axle [bar/N] (before division by μ).
double WheelPressurePerForce(double tyre_radius, const params::VehicleBrake& brake) noexcept;

/// Non-finite → 1e-6, else max(μ, 1e-6).
double SanitizeBrakeFriction(double mu) noexcept;

/// b(v) = clamp(bias + interp(v_x; vel_interp_mps, values), 0, 1); the shift is 0 if the two
/// arrays are empty or of unequal length.
double FrontBrakeBias(double v_x, double bias, const params::BrakeBiasShift& shift) noexcept;

}  // namespace scw::controller
