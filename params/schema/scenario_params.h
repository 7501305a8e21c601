// A closed-loop scenario: what is driven (track, car, controllers, parameter files), under which
// conditions (acceleration scaling GG, grip), for how long, and when a run counts as failed.
// Plain YAML (params/scenarios/*.yaml); every key can be overridden with `--set key=value`.
// Empty file references mean the workspace's built-in defaults: Yas Marina North, the EAV24-class
// car, the car's stability parameters and the shipped pure-pursuit parameters.
#pragma once

#include <string>

#include "params/schema/event_params.h"
#include "params/schema/field.h"
#include "params/schema/friction_patch_params.h"
#include "params/schema/longitudinal_params.h"
#include "params/schema/maneuver_params.h"
#include "params/schema/mpc_params.h"
#include "params/schema/plant_variation_params.h"
#include "params/schema/tire_params.h"

namespace scw::params {

struct MotionScenario {
  std::string controller = "pure_pursuit";
  std::string params;  ///< "" = built-in
  double max_curvature_lookahead = 20.0;
  std::string esc_target = "feedback";
  std::string raceline = "optimal";
  double raceline_margin = 2.0;
  LongitudinalParams longitudinal{};
  PmpcParams pmpc{};  ///< used when controller = pmpc
  NmpcParams nmpc{};  ///< used when controller = nmpc
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.controller, {.key = "controller",
                           .doc = "Motion controller: pure_pursuit, pmpc (point-mass tube "
                                  "MPC) or nmpc (single-track nonlinear MPC); see "
                                  "docs/motion_controllers.md.",
                           .choices = "pure_pursuit|pmpc|nmpc"});
    v.Field(s.params, {.key = "params",
                       .doc = "Tracking-controller params file (ROS 2 layout of "
                              "/core/control/TrackingController); empty = built-in.",
                       .optional = true});
    v.Field(s.max_curvature_lookahead,
            {.key = "max_curvature_lookahead",
             .unit = "m",
             .lo = 0.0,
             .hi = 10000.0,
             .doc = "Cap of the pure-pursuit curvature lookahead term (the car has none: 4000 m "
                    "on straights).",
             .optional = true});
    v.Field(s.esc_target,
            {.key = "esc_target",
             .doc = "Lateral-acceleration request pure pursuit publishes (the ESC's yaw "
                    "reference): feedback = the car's node, feedback curvature x v^2 only (about "
                    "half the real a_y in corners, so ESC's yaw-rate condition holds nearly all "
                    "the time); total = the total commanded curvature tan(delta_ff + delta_fb)/l "
                    "x v^2. The MPCs always publish their planned a_y.",
             .optional = true,
             .choices = "feedback|total"});
    v.Field(s.raceline,
            {.key = "raceline",
             .doc = "Reference line: optimal (minimum curvature within the track bounds), "
                    "centerline, or a raceline CSV file (x_m,y_m).",
             .optional = true});
    v.Field(s.raceline_margin, {.key = "raceline_margin",
                                .unit = "m",
                                .lo = 0.0,
                                .hi = 20.0,
                                .doc = "Distance the optimal line keeps from each track edge.",
                                .optional = true});
    v.Nested("longitudinal", s.longitudinal, true);
    v.Nested("pmpc", s.pmpc, true);
    v.Nested("nmpc", s.nmpc, true);
  }
};

struct AbortParams {
  double max_sideslip_deg = 20.0;
  double max_lateral_error = 3.0;
  double lock_slip_pct = 95.0;
  double spin_slip_pct = 50.0;
  double slip_time = 0.5;
  bool off_track = true;
  double timeout_factor = 3.0;
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.max_sideslip_deg, {.key = "max_sideslip_deg",
                                 .unit = "deg",
                                 .lo = 0.1,
                                 .hi = 180.0,
                                 .doc = "Abort when |β| exceeds this (the paper: 20°)."});
    v.Field(
        s.max_lateral_error,
        {.key = "max_lateral_error",
         .unit = "m",
         .lo = 0.01,
         .hi = 100.0,
         .doc = "Abort when the distance to the reference line exceeds this (the paper: 3 m)."});
    v.Field(s.lock_slip_pct,
            {.key = "lock_slip_pct",
             .unit = "%",
             .lo = 1.0,
             .hi = 100.0,
             .doc = "Wheel lock: slip below −this for longer than slip_time aborts the run."});
    v.Field(s.spin_slip_pct,
            {.key = "spin_slip_pct",
             .unit = "%",
             .lo = 1.0,
             .hi = 1000.0,
             .doc = "Wheel spin: slip above this for longer than slip_time aborts the run."});
    v.Field(s.slip_time, {.key = "slip_time",
                          .unit = "s",
                          .lo = 0.0,
                          .hi = 10.0,
                          .doc = "How long lock or spin must last to abort."});
    v.Field(s.off_track,
            {.key = "off_track", .doc = "Abort when the CoG leaves the track bounds."});
    v.Field(s.timeout_factor,
            {.key = "timeout_factor",
             .unit = "-",
             .lo = 1.1,
             .hi = 100.0,
             .doc = "Abort when the simulated time exceeds this × laps × ideal lap time."});
  }
};

struct SubsystemSwitches {
  bool esc = true;
  bool cs = true;
  bool abs = true;
  bool tc = true;
  bool release_compat = false;
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.esc, {.key = "esc", .doc = "Run ESC (and only if ESC.enabled in the params file)."});
    v.Field(s.cs, {.key = "cs", .doc = "Run countersteer (and countersteer_system.enabled)."});
    v.Field(s.abs, {.key = "abs", .doc = "Run ABS (and SlipControl.ABS.enabled)."});
    v.Field(s.tc, {.key = "tc", .doc = "Run TC (and SlipControl.TC.enabled)."});
    v.Field(s.release_compat,
            {.key = "release_compat",
             .doc = "Reproduce the released node: long_fx ≡ 0 (TC cannot activate, ABS only via "
                    "ESC)."});
  }
};

struct ScenarioParams {
  std::string name = "default";
  std::string kind = "clean";
  std::string track;
  std::string vehicle;
  std::string stability;
  MotionScenario motion{};
  double gg_scale = 1.0;
  double limit_fraction = 0.7;
  bool plan_with_nominal_grip = false;
  GripParams grip{};
  FrictionPatches friction_patches{};
  ScenarioEvents events{};
  int laps = 3;
  AbortParams abort{};
  SubsystemSwitches subsystems{};
  PlantVariationParams plant{};  ///< the simulated car's variation (plant_variation_params.h)
  int seed = 1;
  bool sensor_noise = false;
  double log_rate = 100.0;
  double plant_step = 0.0;
  ManeuverParams maneuver{};  ///< used when kind = maneuver

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name", .doc = "Scenario name (reports, file names)."});
    v.Field(s.kind,
            {.key = "kind",
             .doc = "What the scenario tests, which selects its cost terms (tuning/optim/cost.h): "
                    "clean = a lap that should need no intervention (lap time and the cost of "
                    "every intervention count); critical = a situation the stability control "
                    "must save (survival, sideslip above the allowed angle and distance lost "
                    "count; interventions are free); maneuver = a standard open-loop test "
                    "(section maneuver, docs/maneuvers.md: no track, no motion controller; its "
                    "failed pass/fail criteria count).",
             .optional = true,
             .choices = "clean|critical|maneuver"});
    v.Field(s.track, {.key = "track",
                      .doc = "Track: a built-in name (yas_north = Yas Marina North, monza = "
                             "Autodromo Nazionale Monza, 5.793 km GP layout, clockwise) or a file "
                             "(.csv centre line with widths, or a piecewise .yaml); empty = "
                             "built-in Yas Marina North.",
                      .optional = true});
    v.Field(s.vehicle, {.key = "vehicle",
                        .doc = "Vehicle parameter file (params/vehicles/*.yaml); empty = built-in "
                               "EAV24-class car.",
                        .optional = true});
    v.Field(s.stability, {.key = "stability",
                          .doc = "Stability params file (the car's ROS 2 layout); empty = "
                                 "built-in (the car's values).",
                          .optional = true});
    v.Nested("motion", s.motion, true);
    v.Field(s.gg_scale, {.key = "gg_scale",
                         .unit = "-",
                         .lo = 0.1,
                         .hi = 3.0,
                         .doc = "Acceleration scaling GG of the paper: multiplies the g-g-v "
                                "limits of the reference velocity profile."});
    v.Field(s.limit_fraction,
            {.key = "limit_fraction",
             .unit = "-",
             .lo = 0.1,
             .hi = 1.5,
             .doc = "Fraction of the plant's combined g-g-v envelope (`scw vehicle envelope`) "
                    "the velocity planner uses at GG = 1: the paper starts from conservative "
                    "targets and scales them up by GG until an abort. With 0.7 (a mapping fixed "
                    "before the studies were run) GG 1.0 is 70 % of the car's real limits and "
                    "GG 1.43 is 100 %, so the studied range GG 1.0-1.8 crosses the limits.",
             .optional = true});
    v.Field(s.plan_with_nominal_grip,
            {.key = "plan_with_nominal_grip",
             .doc = "Plan the velocity profile for the vehicle file's grip, ignoring this "
                    "scenario's grip factors (the planner does not know the track is slippery).",
             .optional = true});
    v.Nested("grip", s.grip, true);
    // Patches of other grip on the road (params/schema/friction_patch_params.h), added to the
    // track file's. Only the simulated car feels them: the planner knows the track's
    // friction_scale, not a patch (a wet or oily patch is an event the motion controller meets).
    v.Nested("friction_patches", s.friction_patches, true);
    // Faults, grip events and gusts at a place on the track (params/schema/event_params.h).
    v.Nested("events", s.events, true);
    v.Field(
        s.laps,
        {.key = "laps", .unit = "-", .lo = 1, .hi = 100, .doc = "Laps after the flying start."});
    v.Nested("abort", s.abort, true);
    v.Nested("subsystems", s.subsystems, true);
    v.Nested("plant", s.plant, true);
    v.Field(s.seed, {.key = "seed",
                     .unit = "-",
                     .lo = 0,
                     .hi = 2147483647,
                     .doc = "Seed of the sensor noise.",
                     .optional = true});
    v.Field(s.sensor_noise, {.key = "sensor_noise",
                             .doc = "Add the vehicle file's sensor noise to the measurements.",
                             .optional = true});
    v.Field(s.log_rate, {.key = "log_rate",
                         .unit = "Hz",
                         .lo = 1.0,
                         .hi = 1000.0,
                         .doc = "Trace logging rate.",
                         .optional = true});
    v.Field(s.plant_step,
            {.key = "plant_step",
             .unit = "s",
             .lo = 0.0,
             .hi = 0.005,
             .doc = "Plant step h of this scenario; 0 = the vehicle file's "
                    "simulation.time_step. Must divide the controller period tS. `scw tune` "
                    "searches with a coarser step (--search-plant-step, 2 ms by default) once a "
                    "check on the training scenarios shows it gives the same outcomes as the "
                    "vehicle's own step (docs/plant-step.md); everything it reports runs at the "
                    "vehicle's step.",
             .optional = true});
    // A standard open-loop test (params/schema/maneuver_params.h); every key optional and
    // written only when changed.
    v.Nested("maneuver", s.maneuver, true);
  }
};

}  // namespace scw::params
