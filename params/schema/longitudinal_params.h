// Parameters of the longitudinal controller (a_x request → total force request long_fx → throttle
// and per-wheel brake pressures), after the paper's stack (stability-control spec §6.2, §6.3).
// Its knowledge of the car (mass, aero, engine map, ratios, brake gains) is taken from the vehicle
// file of the scenario, as the car's controller takes it from its vehicle config.
#pragma once

#include "params/schema/field.h"

namespace scw::params {

struct LongitudinalParams {
  double kp = 100.0;
  double kd = 0.5;
  double feedback_limit = 1000.0;
  double feedback_time_constant = 0.07;
  double derivative_time_constant = 0.02;
  double max_force_rate = 200000.0;
  double force_max = 10000.0;
  double force_min = -50000.0;
  double rotational_inertia_factor = 1.0;
  double brake_bias_front = 0.58;
  bool hold_during_esc = false;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.kp, {.key = "kp",
                   .unit = "N/(m/s^2)",
                   .lo = 0.0,
                   .hi = 1e5,
                   .doc = "Feedback gain on the a_x error (P_VDC_LongAccKp)."});
    v.Field(s.kd, {.key = "kd",
                   .unit = "N*s/(m/s^2)",
                   .lo = 0.0,
                   .hi = 1e4,
                   .doc = "Derivative gain on the a_x error (P_VDC_LongAccKd)."});
    v.Field(s.feedback_limit, {.key = "feedback_limit",
                               .unit = "N",
                               .lo = 0.0,
                               .hi = 1e6,
                               .doc = "Saturation of the P term (P_VDC_LongAcc_LimFb_N)."});
    v.Field(s.feedback_time_constant,
            {.key = "feedback_time_constant",
             .unit = "s",
             .lo = 1e-6,
             .hi = 10.0,
             .doc = "Low-pass time constant of the feedback force (P_VDC_LongAccFB_Ts)."});
    v.Field(s.derivative_time_constant,
            {.key = "derivative_time_constant",
             .unit = "s",
             .lo = 1e-6,
             .hi = 10.0,
             .doc = "Low-pass time constant of the derivative term (P_VDC_LongAccFB_d_Ts)."});
    v.Field(s.max_force_rate, {.key = "max_force_rate",
                               .unit = "N/s",
                               .lo = 1.0,
                               .hi = 1e8,
                               .doc = "Rate limit of the force request (P_VDC_FxMaxSlope_Nps)."});
    v.Field(s.force_max, {.key = "force_max",
                          .unit = "N",
                          .lo = 0.0,
                          .hi = 1e6,
                          .doc = "Largest drive force requested (DriveForceMax_N)."});
    v.Field(s.force_min, {.key = "force_min",
                          .unit = "N",
                          .lo = -1e6,
                          .hi = 0.0,
                          .doc = "Largest braking force requested, negative (DriveForceMin_N)."});
    v.Field(s.rotational_inertia_factor,
            {.key = "rotational_inertia_factor",
             .unit = "-",
             .lo = 0.5,
             .hi = 2.0,
             .doc = "Mass factor for rotating parts in the feed-forward."});
    v.Field(s.brake_bias_front,
            {.key = "brake_bias_front",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Front share of the braking force (the car's P_VDC_brake_bias_front; the "
                    "stability controller's ABS model assumes the same value)."});
    v.Field(s.hold_during_esc,
            {.key = "hold_during_esc",
             .doc = "Declared interplay option, not the car's behaviour (closed-loop fidelity "
                    "spec §8 item 14): while ESC was active at the previous step, the feedback "
                    "is left out (as while ABS/TC act) and the force request may not rise, so "
                    "the throttle does not climb against ESC's braking. false = the car."});
  }
  static void CrossCheck(const LongitudinalParams& p, Problems& pr) {
    if (!(p.force_min < p.force_max)) pr.Add("force_min", "must be below force_max");
  }
};

}  // namespace scw::params
