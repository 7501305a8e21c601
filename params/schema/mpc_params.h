// Settings of the two MPC motion controllers, described once (scenario keys motion.pmpc.* and
// motion.nmpc.*; docs/parameters-scenario.md, docs/motion_controllers.md). The controllers
// (controller/motion/pmpc.h, nmpc.h) take these plus what the scenario's vehicle and tracking
// parameters fix (sample time of pure pursuit's loop, wheelbase, steering limit, understeer
// gradient), which are therefore not keys here. Defaults are the values every study so far used.
#pragma once

#include <string>

#include "params/schema/field.h"

namespace scw::params {

namespace detail {
/// The settings both MPCs share: same meaning, unit, bounds and doc (their defaults differ).
template <class Self, class V>
void VisitMpcCommon(Self& s, V& v) {
  v.Field(s.q_n, {.key = "q_n",
                  .unit = "1/m^2",
                  .lo = 0.0,
                  .hi = 1e6,
                  .doc = "Weight of the lateral offset from the reference line.",
                  .optional = true});
  v.Field(s.q_v, {.key = "q_v",
                  .unit = "s^2/m^2",
                  .lo = 0.0,
                  .hi = 1e6,
                  .doc = "Weight of the speed error to the reference speed.",
                  .optional = true});
  v.Field(s.terminal_factor, {.key = "terminal_factor",
                              .lo = 0.0,
                              .hi = 1e3,
                              .doc = "Factor on the state weights of the last node.",
                              .optional = true});
  v.Field(s.slack_l1, {.key = "slack_l1",
                       .lo = 0.0,
                       .hi = 1e9,
                       .doc = "Linear penalty of the track-bound slack.",
                       .optional = true});
  v.Field(s.slack_l2, {.key = "slack_l2",
                       .lo = 0.0,
                       .hi = 1e9,
                       .doc = "Quadratic penalty of the track-bound slack.",
                       .optional = true});
  v.Field(s.min_speed, {.key = "min_speed",
                        .unit = "m/s",
                        .lo = 0.0,
                        .hi = 50.0,
                        .doc = "Lower bound of the planned speed.",
                        .optional = true});
  v.Field(s.projection_window, {.key = "projection_window",
                                .unit = "m",
                                .lo = 1.0,
                                .hi = 10000.0,
                                .doc = "Local search window of the path matching.",
                                .optional = true});
  v.Field(s.max_iter, {.key = "max_iter",
                       .lo = 1,
                       .hi = 10000,
                       .doc = "Iteration limit of each solve (Ipopt).",
                       .optional = true});
  v.Field(s.tol, {.key = "tol",
                  .lo = 1e-12,
                  .hi = 1.0,
                  .doc = "Convergence tolerance of each solve (Ipopt).",
                  .optional = true});
}
}  // namespace detail

/// Point-mass tube MPC (QP in the curvilinear frame, ancillary feedback each sample).
struct PmpcParams {
  int horizon_steps = 20;     ///< N
  double step = 0.125;        ///< dt of the plan [s]
  double solve_period = 0.1;  ///< QP re-solve period [s]
  double q_n = 1.0;           ///< [1/m²]
  double q_w = 0.5;           ///< [s²/m²]
  double q_v = 4.0;           ///< [s²/m²]
  double r_at = 0.01;         ///< [s⁴/m²]
  double r_an = 0.01;         ///< [s⁴/m²]
  double r_dat = 0.05;        ///< [s⁴/m²]
  double r_dan = 0.2;         ///< [s⁴/m²]
  double terminal_factor = 5.0;
  double slack_l1 = 1e3;
  double slack_l2 = 1e3;
  double tube_lateral = 0.3;        ///< [m]
  double nominal_fraction = 1.15;   ///< [-]
  double headroom = 1.3;            ///< [-]
  double min_speed = 1.0;           ///< [m/s]
  double lookahead_time = 0.6;      ///< [s]
  double min_lookahead = 10.0;      ///< [m]
  double speed_gain = 0.5;          ///< [1/s]
  double yaw_rate_gain = 0.0;       ///< [s]
  double lat_accel_gain = 0.0;      ///< [m]
  double projection_window = 60.0;  ///< [m]
  int max_iter = 60;
  double tol = 1e-6;
  std::string esc_target = "plan";  ///< plan | commanded | steering
  std::string limits = "scaled";    ///< scaled | provided
  double target_fraction = 0.85;    ///< [-] provided: the plan's speed profile × the limits

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.horizon_steps, {.key = "horizon_steps",
                              .lo = 2,
                              .hi = 200,
                              .doc = "Nodes of the plan N.",
                              .optional = true});
    v.Field(s.step, {.key = "step",
                     .unit = "s",
                     .lo = 0.005,
                     .hi = 1.0,
                     .doc = "Interval of the plan.",
                     .optional = true});
    v.Field(s.solve_period,
            {.key = "solve_period",
             .unit = "s",
             .lo = 0.001,
             .hi = 1.0,
             .doc = "Time between QP solves (at least the tracking sample time; the ancillary "
                    "feedback runs every sample in between).",
             .optional = true});
    v.Field(s.q_w, {.key = "q_w",
                    .unit = "s^2/m^2",
                    .lo = 0.0,
                    .hi = 1e6,
                    .doc = "Weight of the lateral speed.",
                    .optional = true});
    v.Field(s.r_at, {.key = "r_at",
                     .unit = "s^4/m^2",
                     .lo = 0.0,
                     .hi = 1e6,
                     .doc = "Weight of the tangential acceleration.",
                     .optional = true});
    v.Field(s.r_an, {.key = "r_an",
                     .unit = "s^4/m^2",
                     .lo = 0.0,
                     .hi = 1e6,
                     .doc = "Weight of the normal acceleration.",
                     .optional = true});
    v.Field(s.r_dat, {.key = "r_dat",
                      .unit = "s^4/m^2",
                      .lo = 0.0,
                      .hi = 1e6,
                      .doc = "Weight of the change of tangential acceleration between steps.",
                      .optional = true});
    v.Field(s.r_dan, {.key = "r_dan",
                      .unit = "s^4/m^2",
                      .lo = 0.0,
                      .hi = 1e6,
                      .doc = "Weight of the change of normal acceleration between steps.",
                      .optional = true});
    v.Field(s.tube_lateral, {.key = "tube_lateral",
                             .unit = "m",
                             .lo = 0.0,
                             .hi = 5.0,
                             .doc = "Track bounds tightened for the nominal plan.",
                             .optional = true});
    v.Field(s.nominal_fraction,
            {.key = "nominal_fraction",
             .lo = 0.05,
             .hi = 3.0,
             .doc = "Share of the planner's g-g limits the nominal plan may use.",
             .optional = true});
    v.Field(s.headroom, {.key = "headroom",
                         .lo = 0.05,
                         .hi = 3.0,
                         .doc = "Share of the g-g limits the ancillary feedback may reach (at "
                                "least nominal_fraction).",
                         .optional = true});
    v.Field(s.lookahead_time, {.key = "lookahead_time",
                               .unit = "s",
                               .lo = 0.0,
                               .hi = 5.0,
                               .doc = "Lookahead time of the steering law on the plan.",
                               .optional = true});
    v.Field(s.min_lookahead, {.key = "min_lookahead",
                              .unit = "m",
                              .lo = 0.1,
                              .hi = 500.0,
                              .doc = "Minimum lookahead distance of the steering law.",
                              .optional = true});
    v.Field(s.yaw_rate_gain,
            {.key = "yaw_rate_gain",
             .unit = "s",
             .lo = 0.0,
             .hi = 2.0,
             .doc = "Yaw-rate feedback of the steering law: the steering request is reduced by "
                    "this gain times (measured yaw rate - a_n,cmd / v), so the car is steered out "
                    "when it yaws faster than its commanded path. 0 = none (the default; not in "
                    "the published PMPC description, a claims-map candidate for claim (d)).",
             .optional = true});
    v.Field(s.lat_accel_gain,
            {.key = "lat_accel_gain",
             .unit = "m",
             .lo = 0.0,
             .hi = 20.0,
             .doc = "Lateral-acceleration feedback of the steering law, the lower-level lateral "
                    "controller of the TUM tube MPC: the steering request is increased by this "
                    "gain times (a_n,cmd - measured a_y) / v^2, so a car that falls short of its "
                    "commanded lateral acceleration is steered in. 0 = none (the default); the "
                    "TUM stack's loop analysis uses 3 m. A claims-map candidate for claim (d).",
             .optional = true});
    v.Field(s.speed_gain, {.key = "speed_gain",
                           .unit = "1/s",
                           .lo = 0.0,
                           .hi = 20.0,
                           .doc = "Gain of the ancillary speed feedback.",
                           .optional = true});
    v.Field(s.esc_target,
            {.key = "esc_target",
             .doc = "Lateral-acceleration request published as the ESC's yaw reference: plan = "
                    "the nominal plan's normal acceleration now; commanded = the one the "
                    "steering is computed from (the plan plus the ancillary feedback that "
                    "returns the car to it); steering = none, so the ESC takes its curvature "
                    "from the steering request through its single-track model "
                    "(tire_stiffness_front/rear), the paper's other reference. Which one the "
                    "paper's PMPC gave in studies 1-2 is not public (it names a_y only for "
                    "study 3).",
             .optional = true,
             .choices = "plan|commanded|steering"});
    v.Field(s.limits,
            {.key = "limits",
             .doc = "scaled = the plan within nominal_fraction and the feedback within headroom "
                    "times the planner's limits, on the planner's speed profile; provided = "
                    "nothing above the planner's limits (plan and feedback at 1.0, the "
                    "feedback's a_x inside the g-g law at its a_n; nominal_fraction and headroom "
                    "unused) on a speed profile planned at target_fraction of them.",
             .optional = true,
             .choices = "scaled|provided"});
    v.Field(s.target_fraction,
            {.key = "target_fraction",
             .lo = 0.3,
             .hi = 1.0,
             .doc = "limits=provided: the share of the planner's limits the speed profile the "
                    "plan follows is planned with (fixed by "
                    "experiments/pmpc_provided_criterion.md).",
             .optional = true});
    detail::VisitMpcCommon(s, v);
  }
  static void CrossCheck(const PmpcParams& p, Problems& pr) {
    if (!(p.headroom >= p.nominal_fraction))
      pr.Add("headroom", "must be at least nominal_fraction (" + FormatNumber(p.nominal_fraction) +
                             "), is " + FormatNumber(p.headroom));
  }
};

/// Single-track nonlinear MPC (multiple shooting, RK4, Ipopt).
struct NmpcParams {
  int horizon_steps = 20;     ///< N
  double step = 0.1;          ///< dt [s]
  int substeps = 2;           ///< RK4 steps per interval
  double sample_time = 0.05;  ///< one solve per call [s]
  double q_n = 1.0;           ///< [1/m²]
  double q_mu = 10.0;         ///< [1/rad²]
  double q_v = 4.0;           ///< [s²/m²]
  double r_ddelta = 200.0;    ///< [1/rad²]
  double r_da = 0.1;          ///< [s⁴/m²]
  double r_a = 0.01;          ///< [s⁴/m²]
  double terminal_factor = 5.0;
  double slack_l1 = 1e3, slack_l2 = 1e3;
  double margin = 0.3;                   ///< [m]
  double accel_fraction = 1.15;          ///< [-]
  double max_steering_rate = 1.0;        ///< [rad/s]
  double min_speed = 2.0;                ///< [m/s]
  double projection_window = 60.0;       ///< [m]
  double fallback_lookahead_time = 0.6;  ///< [s]
  double fallback_min_lookahead = 10.0;  ///< [m]
  int max_iter = 30;
  double tol = 1e-5;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.horizon_steps, {.key = "horizon_steps",
                              .lo = 2,
                              .hi = 200,
                              .doc = "Shooting intervals N.",
                              .optional = true});
    v.Field(s.step, {.key = "step",
                     .unit = "s",
                     .lo = 0.005,
                     .hi = 1.0,
                     .doc = "Interval of the plan.",
                     .optional = true});
    v.Field(
        s.substeps,
        {.key = "substeps", .lo = 1, .hi = 20, .doc = "RK4 steps per interval.", .optional = true});
    v.Field(s.sample_time, {.key = "sample_time",
                            .unit = "s",
                            .lo = 0.005,
                            .hi = 1.0,
                            .doc = "Time between solves (the plan is held in between).",
                            .optional = true});
    v.Field(s.q_mu, {.key = "q_mu",
                     .unit = "1/rad^2",
                     .lo = 0.0,
                     .hi = 1e6,
                     .doc = "Weight of the heading error to the reference line.",
                     .optional = true});
    v.Field(s.r_ddelta, {.key = "r_ddelta",
                         .unit = "1/rad^2",
                         .lo = 0.0,
                         .hi = 1e9,
                         .doc = "Weight of the steering change between intervals.",
                         .optional = true});
    v.Field(s.r_da, {.key = "r_da",
                     .unit = "s^4/m^2",
                     .lo = 0.0,
                     .hi = 1e6,
                     .doc = "Weight of the acceleration change between intervals.",
                     .optional = true});
    v.Field(s.r_a, {.key = "r_a",
                    .unit = "s^4/m^2",
                    .lo = 0.0,
                    .hi = 1e6,
                    .doc = "Weight of the acceleration's deviation from the reference's.",
                    .optional = true});
    v.Field(s.margin, {.key = "margin",
                       .unit = "m",
                       .lo = 0.0,
                       .hi = 5.0,
                       .doc = "Track bounds tightened for the plan.",
                       .optional = true});
    v.Field(s.accel_fraction, {.key = "accel_fraction",
                               .lo = 0.05,
                               .hi = 3.0,
                               .doc = "Share of the planner's g-g limits the plan may use.",
                               .optional = true});
    v.Field(s.max_steering_rate, {.key = "max_steering_rate",
                                  .unit = "rad/s",
                                  .lo = 0.01,
                                  .hi = 20.0,
                                  .doc = "Steering rate bound of the plan.",
                                  .optional = true});
    v.Field(s.fallback_lookahead_time,
            {.key = "fallback_lookahead_time",
             .unit = "s",
             .lo = 0.0,
             .hi = 5.0,
             .doc = "Lookahead time of the fallback steering law (no valid plan).",
             .optional = true});
    v.Field(s.fallback_min_lookahead,
            {.key = "fallback_min_lookahead",
             .unit = "m",
             .lo = 0.1,
             .hi = 500.0,
             .doc = "Minimum lookahead distance of the fallback steering law.",
             .optional = true});
    detail::VisitMpcCommon(s, v);
  }
};

}  // namespace scw::params
