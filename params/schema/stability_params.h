// Parameters of the stability controller (ESC, ABS/TC slip control, countersteer), laid out
// exactly like the ROS 2 params file of the car's node `/core/control/StabilityController`
// (stability-control spec §7.1, §7.2, §8.1). Nested structs mirror the nested YAML maps, so the
// dotted key of every field is the ROS 2 parameter name.
//
// Defaults: for the 85 keys of the shipped file (§7.1) the values the car actually runs (the
// shipped YAML, with ESC.max_brake_pressure = 80.0, the later of its two entries). For the optional
// keys the node also declares (§7.2) the node's code defaults, which apply on the car whenever the
// file omits them. Keys marked "workspace only" are not declared by the node: it ignores them.
//
// Units: SI inside, except where the reference uses percent (slip, [%]) or bar (pressure).
// Several keys named "tS…" or "…_pole" are discrete low-pass POLES a ∈ [0,1] at the control
// period tS (y_k = a·y_{k-1} + (1−a)·u_k, τ = −tS/ln a); the docs below say which.
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

inline constexpr char kStabilityNodeKey[] = "/core/control/StabilityController";

struct BrakeBiasShift {
  std::vector<double> values{-0.101, -0.0475, 0.0};
  std::vector<double> vel_interp_mps{20.0, 35.0, 60.0};

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.values, {.key = "values",
                       .unit = "-",
                       .lo = -0.5,
                       .hi = 0.5,
                       .doc = "Additive shift of the front brake bias over speed (breakpoints in "
                              "vel_interp_mps). Linearly EXTRAPOLATED outside the breakpoints, as "
                              "on the car.",
                       .min_size = 2});
    v.Field(s.vel_interp_mps, {.key = "vel_interp_mps",
                               .unit = "m/s",
                               .lo = 0.0,
                               .hi = 150.0,
                               .doc = "Speed breakpoints of the brake-bias shift (ascending, same "
                                      "length as values).",
                               .min_size = 2,
                               .ascending = true});
  }
  static void CrossCheck(const BrakeBiasShift& p, Problems& pr) {
    if (p.values.size() != p.vel_interp_mps.size())
      pr.Add("values", "must have the same length as vel_interp_mps (" +
                           std::to_string(p.values.size()) + " vs " +
                           std::to_string(p.vel_interp_mps.size()) + ")");
  }
};

struct ShiftPressureReduction {
  double reduction_factor = 0.85;
  double duration_pressure_reduction = 0.05;
  double duration_gearshift_initiation = 0.15;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.reduction_factor,
            {.key = "reduction_factor",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Multiplier on the rear brake pressures inside the gear-shift window.",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.duration_pressure_reduction, {.key = "duration_pressure_reduction",
                                            .unit = "s",
                                            .lo = 0.0,
                                            .hi = 2.0,
                                            .doc = "Length of the rear pressure-reduction window.",
                                            .scale = Scale::kLinear,
                                            .resolution = 0.01});
    v.Field(s.duration_gearshift_initiation,
            {.key = "duration_gearshift_initiation",
             .unit = "s",
             .lo = 0.0,
             .hi = 2.0,
             .doc = "Delay from a gear-request change to the start of the window.",
             .scale = Scale::kLinear,
             .resolution = 0.01});
  }
};

/// Per-axle ABS parameters. Slip thresholds are negative percentages (braking); the intended
/// ordering is hold_increase ≤ increase_hold ≤ reduce_hold ≤ hold_reduce ≤ safe < 0.
struct AbsAxleParams {
  double reduce_initial_pressure_ratio = 0.7;
  double increase_initial_pressure_ratio = 0.45;
  double reduce_step = 0.038;
  double increase_step = 0.023;
  double increase_step_target_increase = 0.015;
  double slip_threshold_hold_reduce = -10.0;
  double slip_threshold_reduce_hold = -12.0;
  double slip_threshold_hold_increase = -25.0;
  double slip_threshold_increase_hold = -15.0;
  double slip_threshold_safe = -7.0;
  double fx_safety_threshold_factor = 0.4;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.reduce_initial_pressure_ratio,
            {.key = "reduce_initial_pressure_ratio",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Pressure ratio ε set at activation (pressure drops at once to about "
                    "0.9·ε·p_latched) and cap on re-entry to Reduce.",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.increase_initial_pressure_ratio, {.key = "increase_initial_pressure_ratio",
                                                .unit = "-",
                                                .lo = 0.0,
                                                .hi = 1.0,
                                                .doc = "Minimum ε on entering Increase.",
                                                .scale = Scale::kLinear,
                                                .resolution = 0.01});
    v.Field(s.reduce_step,
            {.key = "reduce_step",
             .unit = "1/step",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "ε decrement per control step in Reduce, multiplied by the normalised slip "
                    "error e ∈ [0.1, 1].",
             .scale = Scale::kLog,
             .resolution = 0.001});
    v.Field(s.increase_step, {.key = "increase_step",
                              .unit = "1/step",
                              .lo = 0.0,
                              .hi = 1.0,
                              .doc = "ε increment per control step in Increase while ε < 1.",
                              .scale = Scale::kLog,
                              .resolution = 0.001});
    v.Field(s.increase_step_target_increase,
            {.key = "increase_step_target_increase",
             .unit = "1/step",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "ε increment per step above 1 (target increase: lets the output follow a "
                    "rising request while latched; the output never exceeds the request).",
             .scale = Scale::kLog,
             .resolution = 0.001});
    v.Field(s.slip_threshold_hold_reduce,
            {.key = "slip_threshold_hold_reduce",
             .unit = "%",
             .lo = -100.0,
             .hi = 0.0,
             .doc = "λ_hr: activation threshold, Hold→Reduce and Increase→Reduce threshold and "
                    "reference of the slip error. Scaled by the slip-angle factor r.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.slip_threshold_reduce_hold, {.key = "slip_threshold_reduce_hold",
                                           .unit = "%",
                                           .lo = -100.0,
                                           .hi = 0.0,
                                           .doc = "λ_rh: Reduce→Hold when slip recovers above it.",
                                           .scale = Scale::kLinear,
                                           .resolution = 0.1});
    v.Field(s.slip_threshold_hold_increase,
            {.key = "slip_threshold_hold_increase",
             .unit = "%",
             .lo = -100.0,
             .hi = 0.0,
             .doc = "λ_hi: Hold/Reduce→Increase when slip is above it and rising.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.slip_threshold_increase_hold,
            {.key = "slip_threshold_increase_hold",
             .unit = "%",
             .lo = -100.0,
             .hi = 0.0,
             .doc = "λ_ih: Increase→Hold when slip falls below it (and below safe).",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.slip_threshold_safe,
            {.key = "slip_threshold_safe",
             .unit = "%",
             .lo = -100.0,
             .hi = 0.0,
             .doc = "λ_safe: slip considered safe; above it Increase may raise ε beyond 1.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.fx_safety_threshold_factor,
            {.key = "fx_safety_threshold_factor",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Safety limiter: minimum fraction of the requested braking force ABS keeps "
                    "(moving averages over moving_average_fx_window_length steps).",
             .scale = Scale::kLinear,
             .resolution = 0.01});
  }
  static void CrossCheck(const AbsAxleParams& p, Problems& pr) {
    if (!(p.slip_threshold_hold_increase <= p.slip_threshold_increase_hold))
      pr.Add("slip_threshold_hold_increase", "must be <= slip_threshold_increase_hold");
    if (!(p.slip_threshold_increase_hold <= p.slip_threshold_reduce_hold))
      pr.Add("slip_threshold_increase_hold", "must be <= slip_threshold_reduce_hold");
    if (!(p.slip_threshold_reduce_hold <= p.slip_threshold_hold_reduce))
      pr.Add("slip_threshold_reduce_hold", "must be <= slip_threshold_hold_reduce");
    if (!(p.slip_threshold_hold_reduce <= p.slip_threshold_safe))
      pr.Add("slip_threshold_hold_reduce", "must be <= slip_threshold_safe");
    if (!(p.slip_threshold_safe < 0.0))
      pr.Add("slip_threshold_safe", "must be negative (braking slip)");
  }
};

struct AbsParams {
  bool enabled = true;
  int operation_mode = 0;
  double min_activation_velocity = 5.0;
  double min_long_force = -2500.0;
  double activation_time_after_gearshift = 0.1;
  bool slip_vertical_load_weighted = false;
  bool use_virtual_slips = false;
  bool use_error_in_increase = false;
  double slip_angle_max = 0.07;
  double slip_threshold_reduction_factor = 0.3;
  int moving_average_fx_window_length = 50;
  AbsAxleParams front{};
  AbsAxleParams rear{.reduce_initial_pressure_ratio = 0.65,
                     .slip_threshold_hold_increase = -17.0,
                     .slip_threshold_increase_hold = -12.0};

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.enabled, {.key = "enabled", .doc = "Master enable of ABS."});
    v.Field(s.operation_mode,
            {.key = "operation_mode",
             .unit = "-",
             .lo = 0,
             .hi = 3,
             .doc = "Slip distribution: 0 wheel individual, 1 axle split (more-locking wheel of "
                    "each axle), 2 all wheels together, 3 rear axle only."});
    v.Field(s.min_activation_velocity, {.key = "min_activation_velocity",
                                        .unit = "m/s",
                                        .lo = 0.0,
                                        .hi = 50.0,
                                        .doc = "ABS allowed only for v_x above this speed.",
                                        .scale = Scale::kLinear,
                                        .resolution = 0.1});
    v.Field(s.min_long_force,
            {.key = "min_long_force",
             .unit = "N",
             .lo = -100000.0,
             .hi = 0.0,
             .doc = "Braking-request gate F_min: ABS arms when the requested force long_fx < "
                    "F_min − 100 N and disarms above F_min (ESC-triggered ABS bypasses it).",
             .scale = Scale::kLinear,
             .resolution = 10.0});
    v.Field(s.activation_time_after_gearshift,
            {.key = "activation_time_after_gearshift",
             .unit = "s",
             .lo = 0.0,
             .hi = 5.0,
             .doc = "Rear-wheel ABS is blocked for this time after an engaged-gear change.",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.slip_vertical_load_weighted,
            {.key = "slip_vertical_load_weighted",
             .doc = "Use the per-axle vertical-load-weighted slip instead of wheel slips."});
    v.Field(s.use_virtual_slips, {.key = "use_virtual_slips",
                                  .doc = "Use engine-speed based (virtual) rear wheel slips."});
    v.Field(s.use_error_in_increase,
            {.key = "use_error_in_increase",
             .doc = "Scale the Increase steps by the normalised slip error."});
    v.Field(s.slip_angle_max, {.key = "slip_angle_max",
                               .unit = "rad",
                               .lo = 1e-6,
                               .hi = 0.5,
                               .doc = "|slip angle| at which the threshold scaling saturates.",
                               .scale = Scale::kLinear,
                               .resolution = 0.001});
    v.Field(s.slip_threshold_reduction_factor,
            {.key = "slip_threshold_reduction_factor",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Maximum relative reduction of all slip thresholds at slip_angle_max "
                    "(r = 1 − clamp(|α|/α_max, 0, 1)·factor).",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.moving_average_fx_window_length,
            {.key = "moving_average_fx_window_length",
             .unit = "samples",
             .lo = 1,
             .hi = 256,
             .doc = "Window of the moving averages of the ABS safety limiter (the workspace "
                    "keeps fixed-size buffers of at most 256 samples)."});
    v.Nested("front", s.front);
    v.Nested("rear", s.rear);
  }
};

/// Per-axle TC parameters. Slip thresholds are positive percentages (driving); the intended
/// ordering is safe ≤ hold_reduce ≤ reduce_hold ≤ increase_hold ≤ hold_increase.
struct TcAxleParams {
  double reduce_initial_pressure_ratio = 0.82;
  double reduce_step = 0.04;
  double increase_step = 0.018;
  double slip_threshold_reduce_hold = 9.0;
  double slip_threshold_hold_increase = 15.0;
  double slip_threshold_increase_hold = 12.0;
  double slip_threshold_hold_reduce = 8.0;
  double slip_threshold_safe = 6.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.reduce_initial_pressure_ratio,
            {.key = "reduce_initial_pressure_ratio",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Retained fraction ε of the requested drive force at activation (lower ε → "
                    "more brake pressure on the driven wheels).",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.reduce_step, {.key = "reduce_step",
                            .unit = "1/step",
                            .lo = 0.0,
                            .hi = 1.0,
                            .doc = "ε decrement per step in Reduce (× normalised slip error).",
                            .scale = Scale::kLog,
                            .resolution = 0.001});
    v.Field(s.increase_step, {.key = "increase_step",
                              .unit = "1/step",
                              .lo = 0.0,
                              .hi = 1.0,
                              .doc = "ε increment per step in Increase.",
                              .scale = Scale::kLog,
                              .resolution = 0.001});
    v.Field(s.slip_threshold_reduce_hold,
            {.key = "slip_threshold_reduce_hold",
             .unit = "%",
             .lo = 0.0,
             .hi = 100.0,
             .doc = "λ_rh: Reduce→Hold when filtered slip falls below it.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.slip_threshold_hold_increase,
            {.key = "slip_threshold_hold_increase",
             .unit = "%",
             .lo = 0.0,
             .hi = 100.0,
             .doc = "λ_hi: Hold/Reduce→Increase when filtered slip is at or below it and falling.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.slip_threshold_increase_hold, {.key = "slip_threshold_increase_hold",
                                             .unit = "%",
                                             .lo = 0.0,
                                             .hi = 100.0,
                                             .doc = "λ_ih: Increase→Hold threshold.",
                                             .scale = Scale::kLinear,
                                             .resolution = 0.1});
    v.Field(s.slip_threshold_hold_reduce,
            {.key = "slip_threshold_hold_reduce",
             .unit = "%",
             .lo = 0.0,
             .hi = 100.0,
             .doc = "λ_hr: activation threshold and Hold→Reduce threshold; also restarts the "
                    "deactivation timer.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.slip_threshold_safe, {.key = "slip_threshold_safe",
                                    .unit = "%",
                                    .lo = 0.0,
                                    .hi = 100.0,
                                    .doc = "λ_safe: Increase→Hold needs the slip above it.",
                                    .scale = Scale::kLinear,
                                    .resolution = 0.1});
  }
  /// Ordering rules; reported with `prefix` ("rear." / "front.").
  static void CheckOrdering(const TcAxleParams& p, const std::string& prefix, Problems& pr) {
    if (!(p.slip_threshold_safe <= p.slip_threshold_hold_reduce))
      pr.Add(prefix + "slip_threshold_safe", "must be <= slip_threshold_hold_reduce");
    if (!(p.slip_threshold_hold_reduce <= p.slip_threshold_reduce_hold))
      pr.Add(prefix + "slip_threshold_hold_reduce", "must be <= slip_threshold_reduce_hold");
    if (!(p.slip_threshold_reduce_hold <= p.slip_threshold_increase_hold))
      pr.Add(prefix + "slip_threshold_reduce_hold", "must be <= slip_threshold_increase_hold");
    if (!(p.slip_threshold_increase_hold <= p.slip_threshold_hold_increase))
      pr.Add(prefix + "slip_threshold_increase_hold", "must be <= slip_threshold_hold_increase");
  }
};

struct TcParams {
  bool enabled = true;
  int operation_mode = 3;
  double min_activation_velocity = 1.0;
  double activation_time_after_gearshift = 0.1;
  double deactivation_duration = 0.5;
  bool use_virtual_slips = false;
  bool use_error_in_increase = false;
  bool slip_vertical_load_weighted = true;
  double slip_filter_pole = 0.8;
  double max_slip_throttle_cut = 25.0;
  double slip_threshold_reduction_factor = 0.48;
  double slip_angle_max = 0.07;
  TcAxleParams rear{};
  /// Optional in the node file (front TC is inert in operation mode 3); node code defaults.
  TcAxleParams front{.reduce_initial_pressure_ratio = 0.95,
                     .reduce_step = 0.2,
                     .increase_step = 0.05,
                     .slip_threshold_reduce_hold = 12.0,
                     .slip_threshold_hold_increase = 5.0,
                     .slip_threshold_increase_hold = 5.0,
                     .slip_threshold_hold_reduce = 10.0,
                     .slip_threshold_safe = 7.0};

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.enabled,
            {.key = "enabled", .doc = "Master enable of TC (the throttle cut works regardless)."});
    v.Field(s.operation_mode,
            {.key = "operation_mode",
             .unit = "-",
             .lo = 0,
             .hi = 3,
             .doc = "Slip distribution: 0 wheel individual, 1 axle split (more-spinning wheel), "
                    "2 all wheels together, 3 rear axle as one unit."});
    v.Field(s.min_activation_velocity, {.key = "min_activation_velocity",
                                        .unit = "m/s",
                                        .lo = 0.0,
                                        .hi = 50.0,
                                        .doc = "TC allowed only for v_x above this speed.",
                                        .scale = Scale::kLinear,
                                        .resolution = 0.1});
    v.Field(s.activation_time_after_gearshift,
            {.key = "activation_time_after_gearshift",
             .unit = "s",
             .lo = 0.0,
             .hi = 5.0,
             .doc = "Rear-wheel TC is blocked for this time after an engaged-gear change.",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.deactivation_duration,
            {.key = "deactivation_duration",
             .unit = "s",
             .lo = 0.0,
             .hi = 10.0,
             .doc = "TC deactivates this long after the filtered slip last reached the "
                    "activation threshold (simulation time).",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.use_virtual_slips, {.key = "use_virtual_slips",
                                  .doc = "Use engine-speed based (virtual) rear wheel slips."});
    v.Field(s.use_error_in_increase,
            {.key = "use_error_in_increase",
             .doc = "Scale the Increase steps by the normalised slip error."});
    v.Field(s.slip_vertical_load_weighted,
            {.key = "slip_vertical_load_weighted",
             .doc = "Use the per-axle vertical-load-weighted slip instead of wheel slips."});
    v.Field(s.slip_filter_pole,
            {.key = "slip_filter_pole",
             .unit = "- (pole)",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Discrete low-pass POLE on the TC slip (0.8 ↔ τ ≈ 45 ms at 100 Hz).",
             .scale = Scale::kLinear,
             .resolution = 0.001});
    v.Field(s.max_slip_throttle_cut,
            {.key = "max_slip_throttle_cut",
             .unit = "%",
             .lo = 0.0,
             .hi = 100.0,
             .doc = "Throttle forced to 0 while the largest TC-input slip exceeds this value.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.slip_threshold_reduction_factor,
            {.key = "slip_threshold_reduction_factor",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Maximum relative reduction of all TC slip thresholds at slip_angle_max.",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.slip_angle_max, {.key = "slip_angle_max",
                               .unit = "rad",
                               .lo = 1e-6,
                               .hi = 0.5,
                               .doc = "|slip angle| at which the TC threshold scaling saturates.",
                               .scale = Scale::kLinear,
                               .resolution = 0.001});
    v.Nested("rear", s.rear);
    v.Nested("front", s.front, /*optional=*/true);
  }
  static void CrossCheck(const TcParams& p, Problems& pr) {
    TcAxleParams::CheckOrdering(p.rear, "rear.", pr);
    // The node's code defaults of the (optional) front block are not ordered; they are inert in
    // operation mode 3 (rear only), so the ordering is only required when fronts are controlled.
    if (p.operation_mode != 3) TcAxleParams::CheckOrdering(p.front, "front.", pr);
  }
};

struct SlipControlParams {
  double slip_angle_filter_pole = 0.7;
  ShiftPressureReduction shift_pressure_reduction{};
  AbsParams ABS{};
  TcParams TC{};

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.slip_angle_filter_pole,
            {.key = "slip_angle_filter_pole",
             .unit = "- (pole)",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Discrete low-pass POLE on the wheel slip angles used for threshold scaling "
                    "(0.7 ↔ τ ≈ 28 ms at 100 Hz).",
             .scale = Scale::kLinear,
             .resolution = 0.001});
    v.Nested("shift_pressure_reduction", s.shift_pressure_reduction);
    v.Nested("ABS", s.ABS);
    v.Nested("TC", s.TC);
  }
};

struct EscParams {
  bool enabled = true;
  double max_brake_pressure = 80.0;
  double tS_psi_dot = 0.92;
  double kp_psi_dot = 8.0;
  double ki_psi_dot = 1.0;
  double kd_psi_dot = 0.6;
  double tS_beta = 0.9;
  double kp_beta = 25.0;
  double ki_beta = 8.0;
  double kd_beta = 1.0;
  double max_integrator_yaw_moment = 1325.0;
  std::vector<double> threshold_velocities{25.0, 50.0};
  std::vector<double> beta_threshold_activate{0.035, 0.0174};
  double beta_threshold_deactivate = 0.035;
  std::vector<double> psi_dot_error_threshold_activate{0.0401, 0.0349};
  double psi_dot_error_threshold_deactivate = 0.026;
  std::vector<double> beta_error_threshold_activate{0.061, 0.035};
  double beta_error_threshold_deactivate = 0.018;
  double min_activation_velocity = 7.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.enabled, {.key = "enabled", .doc = "Master enable of ESC."});
    v.Field(s.max_brake_pressure,
            {.key = "max_brake_pressure",
             .unit = "bar",
             .lo = 0.0,
             .hi = 300.0,
             .doc = "Head-room limit of the ESC pressure build-up AND global clamp of all four "
                    "wheel pressures every step (active or not). The shipped file sets it twice "
                    "(60.0, 80.0); the node keeps the last."});
    v.Field(s.tS_psi_dot,
            {.key = "tS_psi_dot",
             .unit = "- (pole)",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Discrete low-pass POLE (not a time) on the yaw-rate error (0.92 ↔ τ ≈ "
                    "120 ms at 100 Hz).",
             .scale = Scale::kLinear,
             .resolution = 0.001});
    v.Field(s.kp_psi_dot, {.key = "kp_psi_dot",
                           .unit = "1/s",
                           .lo = 0.0,
                           .hi = 1000.0,
                           .doc = "Yaw-rate P gain (× I_z gives N·m per rad/s).",
                           .scale = Scale::kLog,
                           .resolution = 0.01});
    v.Field(s.ki_psi_dot, {.key = "ki_psi_dot",
                           .unit = "1/s^2",
                           .lo = 0.0,
                           .hi = 1000.0,
                           .doc = "Yaw-rate I gain (conditional integration, reset while "
                                  "inactive).",
                           .scale = Scale::kLog,
                           .resolution = 0.001});
    v.Field(s.kd_psi_dot, {.key = "kd_psi_dot",
                           .unit = "-",
                           .lo = 0.0,
                           .hi = 100.0,
                           .doc = "Yaw-rate D gain (difference quotient, no extra filter).",
                           .scale = Scale::kLog,
                           .resolution = 0.001});
    v.Field(s.tS_beta, {.key = "tS_beta",
                        .unit = "- (pole)",
                        .lo = 0.0,
                        .hi = 1.0,
                        .doc = "Discrete low-pass POLE (not a time) on the sideslip error (0.9 "
                               "↔ τ ≈ 95 ms at 100 Hz).",
                        .scale = Scale::kLinear,
                        .resolution = 0.001});
    v.Field(s.kp_beta, {.key = "kp_beta",
                        .unit = "1/s^2",
                        .lo = 0.0,
                        .hi = 1000.0,
                        .doc = "Sideslip P gain.",
                        .scale = Scale::kLog,
                        .resolution = 0.01});
    v.Field(s.ki_beta, {.key = "ki_beta",
                        .unit = "1/s^3",
                        .lo = 0.0,
                        .hi = 1000.0,
                        .doc = "Sideslip I gain.",
                        .scale = Scale::kLog,
                        .resolution = 0.01});
    v.Field(s.kd_beta, {.key = "kd_beta",
                        .unit = "1/s",
                        .lo = 0.0,
                        .hi = 100.0,
                        .doc = "Sideslip D gain.",
                        .scale = Scale::kLog,
                        .resolution = 0.001});
    v.Field(s.max_integrator_yaw_moment,
            {.key = "max_integrator_yaw_moment",
             .unit = "rad/s^2",
             .lo = 0.0,
             .hi = 1e6,
             .doc = "Conditional-integration bound of BOTH integrators, in PID-output units "
                    "(yaw acceleration) before multiplication by I_z — despite the name not a "
                    "moment: 1325 rad/s² × 1000 kg·m² ≈ 1.3 MN·m, i.e. effectively no "
                    "anti-windup.",
             .scale = Scale::kLog,
             .resolution = 1.0});
    v.Field(s.threshold_velocities,
            {.key = "threshold_velocities",
             .unit = "m/s",
             .lo = 0.0,
             .hi = 150.0,
             .doc = "Speed breakpoints of the activation thresholds (ascending; thresholds are "
                    "linearly EXTRAPOLATED outside, as on the car).",
             .resolution = 0.1,
             .min_size = 2,
             .ascending = true});
    v.Field(s.beta_threshold_activate, {.key = "beta_threshold_activate",
                                        .unit = "rad",
                                        .lo = 0.0,
                                        .hi = 1.0,
                                        .doc = "|β| activation threshold at each breakpoint.",
                                        .scale = Scale::kLinear,
                                        .resolution = 0.001,
                                        .min_size = 2});
    v.Field(s.beta_threshold_deactivate,
            {.key = "beta_threshold_deactivate",
             .unit = "rad",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "|β| deactivation threshold (all three deactivation conditions must hold).",
             .scale = Scale::kLinear,
             .resolution = 0.001});
    v.Field(s.psi_dot_error_threshold_activate,
            {.key = "psi_dot_error_threshold_activate",
             .unit = "rad/s",
             .lo = 0.0,
             .hi = 2.0,
             .doc = "|filtered yaw-rate error| activation threshold at each breakpoint.",
             .scale = Scale::kLinear,
             .resolution = 0.001,
             .min_size = 2});
    v.Field(s.psi_dot_error_threshold_deactivate,
            {.key = "psi_dot_error_threshold_deactivate",
             .unit = "rad/s",
             .lo = 0.0,
             .hi = 2.0,
             .doc = "|filtered yaw-rate error| deactivation threshold.",
             .scale = Scale::kLinear,
             .resolution = 0.001});
    v.Field(s.beta_error_threshold_activate,
            {.key = "beta_error_threshold_activate",
             .unit = "rad",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "|filtered sideslip error| activation threshold at each breakpoint.",
             .scale = Scale::kLinear,
             .resolution = 0.001,
             .min_size = 2});
    v.Field(s.beta_error_threshold_deactivate,
            {.key = "beta_error_threshold_deactivate",
             .unit = "rad",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "|filtered sideslip error| deactivation threshold.",
             .scale = Scale::kLinear,
             .resolution = 0.001});
    v.Field(s.min_activation_velocity,
            {.key = "min_activation_velocity",
             .unit = "m/s",
             .lo = 0.0,
             .hi = 100.0,
             .doc = "Speed gate: activation needs v > this, v < this deactivates.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
  }
  static void CrossCheck(const EscParams& p, Problems& pr) {
    const auto n = p.threshold_velocities.size();
    auto same = [&](const std::vector<double>& a, const char* key) {
      if (a.size() != n)
        pr.Add(key, "must have the same length as threshold_velocities (" +
                        std::to_string(a.size()) + " vs " + std::to_string(n) +
                        "); with unequal lengths ESC can never activate");
    };
    same(p.beta_threshold_activate, "beta_threshold_activate");
    same(p.psi_dot_error_threshold_activate, "psi_dot_error_threshold_activate");
    same(p.beta_error_threshold_activate, "beta_error_threshold_activate");
  }
};

struct CountersteerParams {
  bool enabled = true;
  double slip_angle_filter_Ts = 0.15;
  double enable_sideslip = 0.009;
  double steering_factor = 1.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.enabled, {.key = "enabled",
                        .doc = "Enable the countersteer correction (the "
                               "steering clamp applies regardless)."});
    v.Field(s.slip_angle_filter_Ts,
            {.key = "slip_angle_filter_Ts",
             .unit = "s",
             .lo = 1e-6,
             .hi = 10.0,
             .doc = "TIME CONSTANT (here really a time) of the low-pass on the load-weighted "
                    "axle slip angles (0.15 s ↔ pole 0.9355 at 100 Hz).",
             .scale = Scale::kLog,
             .resolution = 0.001});
    v.Field(s.enable_sideslip, {.key = "enable_sideslip",
                                .unit = "rad",
                                .lo = 0.0,
                                .hi = 0.5,
                                .doc = "Minimum |filtered rear axle slip angle| for a correction.",
                                .scale = Scale::kLinear,
                                .resolution = 0.0001});
    v.Field(s.steering_factor, {.key = "steering_factor",
                                .unit = "-",
                                .lo = 0.0,
                                .hi = 5.0,
                                .doc = "Gain k in δ_out = δ_req − k·(ᾱ_r − ᾱ_f).",
                                .scale = Scale::kLinear,
                                .resolution = 0.01});
  }
};

// ---- Optional keys the node also declares (§7.2): vehicle constants of the node's modules. ----

struct VelocityScaling {
  std::vector<double> velocity{20.0, 50.0, 80.0};
  std::vector<double> factor{1.0, 1.0065, 1.0205};
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.velocity, {.key = "velocity",
                         .unit = "m/s",
                         .lo = 0.0,
                         .hi = 200.0,
                         .doc = "Speed breakpoints of the dynamic tyre-radius growth.",
                         .optional = true,
                         .min_size = 2,
                         .ascending = true});
    v.Field(s.factor, {.key = "factor",
                       .unit = "-",
                       .lo = 0.5,
                       .hi = 1.5,
                       .doc = "Radius factor at each breakpoint (extrapolated).",
                       .optional = true,
                       .min_size = 2});
  }
  static void CrossCheck(const VelocityScaling& p, Problems& pr) {
    if (p.velocity.size() != p.factor.size())
      pr.Add("factor", "must have the same length as velocity");
  }
};

struct TireRadius {
  double radius_20mps = 0.293475;
  VelocityScaling velocity_scaling{};
  bool has_velocity_scaling = true;  // not a key: whether the node declares the scaling here

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.radius_20mps, {.key = "radius_20mps",
                             .unit = "m",
                             .lo = 0.1,
                             .hi = 1.0,
                             .doc = "Rolling radius at 20 m/s (force→pressure factors, slip).",
                             .optional = true});
    if (s.has_velocity_scaling) v.Nested("velocity_scaling", s.velocity_scaling, true);
  }
};

struct TireEntry {
  TireRadius radius{};
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Nested("radius", s.radius, true);
  }
};

struct TiresParams {
  TireEntry front_left{};
  TireEntry rear_left{TireRadius{.radius_20mps = 0.3074348, .has_velocity_scaling = false}};
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Nested("front_left", s.front_left, true);
    v.Nested("rear_left", s.rear_left, true);
  }
};

struct VehicleDimension {
  double trackwidth = 1.606;
  double wheelbase = 2.971;
  double distance_to_front_axle = 1.724;
  double track_width_front = 1.639;
  double track_width_rear = 1.524;
  double cog_height = 0.3;
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.trackwidth, {.key = "trackwidth",
                           .unit = "m",
                           .lo = 0.5,
                           .hi = 3.0,
                           .doc = "Track width used by ESC for yaw moment → force difference "
                                  "(a key of its own, not track_width_front).",
                           .optional = true});
    v.Field(s.wheelbase, {.key = "wheelbase",
                          .unit = "m",
                          .lo = 1.0,
                          .hi = 6.0,
                          .doc = "Wheelbase l (ESC reference model, slip calculation).",
                          .optional = true});
    v.Field(s.distance_to_front_axle, {.key = "distance_to_front_axle",
                                       .unit = "m",
                                       .lo = 0.1,
                                       .hi = 5.0,
                                       .doc = "CoG to front axle l_f (l_r = l − l_f).",
                                       .optional = true});
    v.Field(s.track_width_front, {.key = "track_width_front",
                                  .unit = "m",
                                  .lo = 0.5,
                                  .hi = 3.0,
                                  .doc = "Front track width (slip calculation).",
                                  .optional = true});
    v.Field(s.track_width_rear, {.key = "track_width_rear",
                                 .unit = "m",
                                 .lo = 0.5,
                                 .hi = 3.0,
                                 .doc = "Rear track width (slip calculation).",
                                 .optional = true});
    v.Field(s.cog_height, {.key = "cog_height",
                           .unit = "m",
                           .lo = 0.0,
                           .hi = 2.0,
                           .doc = "CoG height for the quasi-static vertical-load estimate.",
                           .optional = true,
                           .workspace_only = true});
  }
  static void CrossCheck(const VehicleDimension& p, Problems& pr) {
    if (!(p.distance_to_front_axle < p.wheelbase))
      pr.Add("distance_to_front_axle", "must be smaller than wheelbase");
  }
};

struct VehicleDrivetrain {
  double transmission_ratio = 3.0;
  std::vector<double> gear_ratios{0.0, 2.9167, 1.875, 1.3809, 1.1154, 0.96, 0.8889};
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.transmission_ratio, {.key = "transmission_ratio",
                                   .unit = "-",
                                   .lo = 0.0,
                                   .hi = 50.0,
                                   .doc = "Final-drive ratio i_fd (virtual slips).",
                                   .optional = true});
    v.Field(s.gear_ratios,
            {.key = "gear_ratios",
             .unit = "-",
             .lo = 0.0,
             .hi = 50.0,
             .doc = "Gear ratios indexed by gear − 1 (the node's code default has a leading 0.0, "
                    "off by one; the car's vehicle config has none).",
             .optional = true});
  }
};

struct BrakeFrictionMap {
  std::vector<double> temperature{0.0, 1000.0};
  std::vector<double> coefficient{0.35, 0.35};
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.temperature, {.key = "temperature",
                            .unit = "degC",
                            .lo = -50.0,
                            .hi = 2000.0,
                            .doc = "Brake temperature breakpoints of the friction map.",
                            .optional = true,
                            .min_size = 2,
                            .ascending = true});
    v.Field(s.coefficient, {.key = "coefficient",
                            .unit = "-",
                            .lo = 0.01,
                            .hi = 2.0,
                            .doc = "Pad friction coefficient at each temperature.",
                            .optional = true,
                            .min_size = 2});
  }
  static void CrossCheck(const BrakeFrictionMap& p, Problems& pr) {
    if (p.temperature.size() != p.coefficient.size())
      pr.Add("coefficient", "must have the same length as temperature");
  }
};

struct VehicleBrake {
  double pad_mean_radius = 0.134;
  double pad_number = 1.0;
  double piston_diameter = 0.0798;
  double friction_coeff = 0.35;
  BrakeFrictionMap friction{};
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.pad_mean_radius, {.key = "pad_mean_radius",
                                .unit = "m",
                                .lo = 0.01,
                                .hi = 1.0,
                                .doc = "Effective pad radius r_pad (force → pressure).",
                                .optional = true});
    v.Field(s.pad_number, {.key = "pad_number",
                           .unit = "-",
                           .lo = 0.1,
                           .hi = 20.0,
                           .doc = "Number of pads n_pad.",
                           .optional = true});
    v.Field(s.piston_diameter, {.key = "piston_diameter",
                                .unit = "m",
                                .lo = 0.005,
                                .hi = 1.0,
                                .doc = "Caliper piston diameter d (real cars ≈ 0.04–0.08 m).",
                                .optional = true});
    v.Field(s.friction_coeff, {.key = "friction_coeff",
                               .unit = "-",
                               .lo = 0.01,
                               .hi = 2.0,
                               .doc = "Pad friction μ used when no temperature map applies.",
                               .optional = true});
    v.Nested("friction", s.friction, true);
  }
};

struct VehicleAero {
  double air_density = 1.22;
  double cross_track_area = 1.0;
  double lift_coeff = -1.65;
  double front_downforce_share = 0.45;
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.air_density, {.key = "air_density",
                            .unit = "kg/m^3",
                            .lo = 0.5,
                            .hi = 2.0,
                            .doc = "Air density ρ (ABS target reduction, load estimate).",
                            .optional = true});
    v.Field(s.cross_track_area, {.key = "cross_track_area",
                                 .unit = "m^2",
                                 .lo = 0.0,
                                 .hi = 10.0,
                                 .doc = "Reference area A.",
                                 .optional = true});
    v.Field(s.lift_coeff, {.key = "lift_coeff",
                           .unit = "-",
                           .lo = -20.0,
                           .hi = 20.0,
                           .doc = "Lift coefficient c_L (negative = downforce).",
                           .optional = true});
    v.Field(s.front_downforce_share,
            {.key = "front_downforce_share",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Aero balance: front share of the downforce in the vertical-load estimate.",
             .optional = true,
             .workspace_only = true});
  }
};

struct VehicleSteering {
  double min_angle = -0.43;
  double max_angle = 0.43;
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.min_angle, {.key = "min_angle",
                          .unit = "rad",
                          .lo = -1.5,
                          .hi = 0.0,
                          .doc = "Lower steering (tyre) angle limit of the countersteer clamp.",
                          .optional = true});
    v.Field(s.max_angle, {.key = "max_angle",
                          .unit = "rad",
                          .lo = 0.0,
                          .hi = 1.5,
                          .doc = "Upper steering (tyre) angle limit of the countersteer clamp.",
                          .optional = true});
  }
};

struct VehicleMass {
  double total = 800.0;
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.total, {.key = "total",
                      .unit = "kg",
                      .lo = 50.0,
                      .hi = 5000.0,
                      .doc = "Vehicle mass m (ESC reference model, ABS target reduction).",
                      .optional = true});
  }
};

struct VehicleInertia {
  double yaw = 1000.0;
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.yaw, {.key = "yaw",
                    .unit = "kg*m^2",
                    .lo = 10.0,
                    .hi = 20000.0,
                    .doc = "Yaw inertia I_z (ESC: yaw moment = I_z · PID output).",
                    .optional = true});
  }
};

struct NodeVehicleParams {
  VehicleDimension dimension{};
  VehicleInertia inertia{};
  VehicleMass mass{};
  VehicleDrivetrain drivetrain{};
  VehicleBrake brake{};
  VehicleAero aero{};
  VehicleSteering steering{};
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Nested("dimension", s.dimension, true);
    v.Nested("inertia", s.inertia, true);
    v.Nested("mass", s.mass, true);
    v.Nested("drivetrain", s.drivetrain, true);
    v.Nested("brake", s.brake, true);
    v.Nested("aero", s.aero, true);
    v.Nested("steering", s.steering, true);
  }
  static void CrossCheck(const NodeVehicleParams& p, Problems& pr) {
    if (!(p.steering.min_angle < p.steering.max_angle))
      pr.Add("steering.min_angle", "must be below steering.max_angle");
  }
};

/// The whole parameter set of the car's stability node.
struct StabilityParams {
  double tS = 0.01;
  double P_VDC_MinVelSlipCalc_mps = 5.0;
  double P_VDC_brake_bias_front = 0.58;
  BrakeBiasShift brake_bias_shift{};
  SlipControlParams SlipControl{};
  EscParams ESC{};
  CountersteerParams countersteer_system{};
  double tire_stiffness_front = 100000.0;
  double tire_stiffness_rear = 200000.0;
  NodeVehicleParams vehicle{};
  TiresParams tires{};

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.tS, {.key = "tS",
                   .unit = "s",
                   .lo = 1e-4,
                   .hi = 0.1,
                   .doc = "Control period: node timer and every discrete filter/derivative."});
    v.Field(s.P_VDC_MinVelSlipCalc_mps,
            {.key = "P_VDC_MinVelSlipCalc_mps",
             .unit = "m/s",
             .lo = 2.0,
             .hi = 30.0,
             .doc = "v_min of the low-speed slip fade: slips are 0 below v_min − 2 and fully "
                    "weighted from v_min.",
             .scale = Scale::kLinear,
             .resolution = 0.1});
    v.Field(s.P_VDC_brake_bias_front,
            {.key = "P_VDC_brake_bias_front",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Assumed front share of the total brake force in the ABS/TC force → "
                    "pressure model; must match the longitudinal controller."});
    v.Nested("brake_bias_shift", s.brake_bias_shift);
    v.Nested("SlipControl", s.SlipControl);
    v.Nested("ESC", s.ESC);
    v.Nested("countersteer_system", s.countersteer_system);
    v.Field(s.tire_stiffness_front,
            {.key = "tire_stiffness_front",
             .unit = "N/rad",
             .lo = 1000.0,
             .hi = 5e6,
             .doc = "Front axle cornering stiffness of the ESC single-track reference model.",
             .scale = Scale::kLog,
             .resolution = 100.0,
             .optional = true});
    v.Field(s.tire_stiffness_rear,
            {.key = "tire_stiffness_rear",
             .unit = "N/rad",
             .lo = 1000.0,
             .hi = 5e6,
             .doc = "Rear axle cornering stiffness of the ESC single-track reference model.",
             .scale = Scale::kLog,
             .resolution = 100.0,
             .optional = true});
    v.Nested("vehicle", s.vehicle, true);
    v.Nested("tires", s.tires, true);
  }
};

}  // namespace scw::params
