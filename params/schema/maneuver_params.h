// A standard open-loop maneuver (tuning/maneuver/maneuver.h): section `maneuver:` of a scenario
// whose `kind` is `maneuver`, and the options of `scw maneuver NAME`. The car, the stability set,
// the grip factors, the subsystem switches, the plant step and the abort limits come from the
// scenario as for a closed-loop run; this section says which test is driven and how it is scaled
// to this car. Every key is optional and written only when it differs from its default, so a
// scenario that is not a maneuver prints no `maneuver:` section.
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

struct ManeuverParams {
  std::string name = "sine_with_dwell";
  double speed = 0.0;
  double steering_ratio = 12.0;
  std::string direction = "left";
  std::vector<double> amplitude_factors = {1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 6.5};
  bool extend_to_270deg = true;
  double frequency = 0.7;
  double dwell = 0.5;
  double lateral_acceleration = 4.0;
  std::vector<double> decelerations = {2.0, 4.0, 6.0, 8.0};
  double steer_rise_time = 0.1;
  double mu_low = 0.3;
  double mu_high = 1.0;
  double heading_gain = 1.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    const auto opt = [](Meta m) {
      m.optional = true;
      m.omit_default = true;
      return m;
    };
    v.Field(s.name,
            opt({.key = "name",
                 .doc = "The test: sine_with_dwell (FMVSS 126 / UN R140), step_steer (ISO 7401), "
                        "steady_state_circular (ISO 4138, constant speed), braking_in_turn (ISO "
                        "7975), power_off_in_turn and power_on_in_turn (ISO 9816), "
                        "split_mu_braking (ISO 14512), split_mu_acceleration, mu_jump_acceleration "
                        "(docs/maneuvers.md).",
                 .choices = "sine_with_dwell|step_steer|steady_state_circular|braking_in_turn|"
                            "power_off_in_turn|power_on_in_turn|split_mu_braking|"
                            "split_mu_acceleration|mu_jump_acceleration"}));
    v.Field(s.speed, opt({.key = "speed",
                          .unit = "m/s",
                          .lo = 0.0,
                          .hi = 90.0,
                          .doc = "Test speed; 0 = the standard's (80 km/h = 22.22 m/s for sine "
                                 "with dwell, step steer, steady-state circular and the in-turn "
                                 "tests, 100 km/h for split-mu braking, 10 m/s at the start of "
                                 "the acceleration tests)."}));
    v.Field(s.steering_ratio,
            opt({.key = "steering_ratio",
                 .unit = "-",
                 .lo = 1.0,
                 .hi = 40.0,
                 .doc = "Handwheel angle per road-wheel angle. The programs act at the road wheel; "
                        "the ratio converts the standards' handwheel figures (the 5 deg "
                        "beginning-of-steer threshold, 13.5 deg/s of the slowly increasing steer, "
                        "the 270 deg and 300 deg amplitude caps) and reports handwheel angles."}));
    v.Field(s.direction, opt({.key = "direction",
                              .doc = "Direction of the first steer (sine with dwell, step steer, "
                                     "the in-turn tests): left or right.",
                              .choices = "left|right"}));
    v.Field(s.amplitude_factors,
            opt({.key = "amplitude_factors",
                 .unit = "-",
                 .lo = 0.1,
                 .hi = 20.0,
                 .doc = "Sine with dwell: steering amplitudes as multiples of A, the angle that "
                        "gives 0.3 g in the slowly increasing steer at the test speed (the "
                        "standard: 1.5 to 6.5 in steps of 0.5).",
                 .ascending = true}));
    v.Field(s.extend_to_270deg,
            opt({.key = "extend_to_270deg",
                 .doc = "Sine with dwell: when 6.5 A is below 270 deg at the handwheel, continue "
                        "the series in steps of 0.5 A up to 270 deg (never beyond 300 deg), as "
                        "the standard does."}));
    v.Field(s.frequency, opt({.key = "frequency",
                              .unit = "Hz",
                              .lo = 0.1,
                              .hi = 5.0,
                              .doc = "Sine with dwell: frequency of the sine (the standard: "
                                     "0.7 Hz)."}));
    v.Field(s.dwell, opt({.key = "dwell",
                          .unit = "s",
                          .lo = 0.0,
                          .hi = 5.0,
                          .doc = "Sine with dwell: hold at the second peak (the standard: "
                                 "0.5 s)."}));
    v.Field(s.lateral_acceleration,
            opt({.key = "lateral_acceleration",
                 .unit = "m/s^2",
                 .lo = 0.5,
                 .hi = 40.0,
                 .doc = "Step steer: the steady-state lateral acceleration the step aims at "
                        "(ISO 7401: 4 m/s^2); the in-turn tests: the steady circle the test "
                        "starts from (ISO 7975 and ISO 9816: 4 m/s^2)."}));
    v.Field(s.decelerations, opt({.key = "decelerations",
                                  .unit = "m/s^2",
                                  .lo = 0.5,
                                  .hi = 40.0,
                                  .doc = "Braking in a turn: the deceleration levels, one run "
                                         "each (brake pressures from the car's brake gains and "
                                         "the front share 0.58).",
                                  .ascending = true}));
    v.Field(s.steer_rise_time,
            opt({.key = "steer_rise_time",
                 .unit = "s",
                 .lo = 0.01,
                 .hi = 1.0,
                 .doc = "Step steer: time of the steering ramp from 0 to the step's angle "
                        "(ISO 7401 asks for as fast as possible; 0.1 s is a robot's)."}));
    v.Field(s.mu_low, opt({.key = "mu_low",
                           .unit = "-",
                           .lo = 0.05,
                           .hi = 2.0,
                           .doc = "Split-mu and mu-jump tests: friction factor of the slippery "
                                  "surface (the left wheels on split mu; all wheels after the "
                                  "jump)."}));
    v.Field(s.mu_high,
            opt({.key = "mu_high",
                 .unit = "-",
                 .lo = 0.05,
                 .hi = 2.0,
                 .doc = "Split-mu and mu-jump tests: friction factor of the grippy surface."}));
    v.Field(s.heading_gain,
            opt({.key = "heading_gain",
                 .unit = "rad/rad",
                 .lo = 0.0,
                 .hi = 20.0,
                 .doc = "Split-mu and mu-jump tests: the steering robot's road-wheel angle per "
                        "heading deviation (0 = steering held straight); the largest correction "
                        "it needs is reported."}));
  }
};

}  // namespace scw::params
