// Parameters of the pure-pursuit tracking controller, laid out like the ROS 2 params file of the
// car's node `/core/control/TrackingController` (stability-control spec §6.1, §7.3). The 10 keys of
// the shipped file are required; the keys the node declares in addition are optional.
#pragma once

#include "params/schema/field.h"

namespace scw::params {

inline constexpr char kTrackingNodeKey[] = "/core/control/TrackingController";

struct TrackingVehicleParams {
  double wheelbase_m = 2.971;
  double min_angle = -0.43;
  double max_angle = 0.43;
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.wheelbase_m, {.key = "dimension.wheelbase_m",
                            .unit = "m",
                            .lo = 1.0,
                            .hi = 6.0,
                            .doc = "Wheelbase of the pure-pursuit steering law (a key of its "
                                   "own: the vehicle handler does not provide it).",
                            .optional = true});
    v.Field(s.min_angle, {.key = "steering.min_angle",
                          .unit = "rad",
                          .lo = -1.5,
                          .hi = 0.0,
                          .doc = "Lower steering angle limit.",
                          .optional = true});
    v.Field(s.max_angle, {.key = "steering.max_angle",
                          .unit = "rad",
                          .lo = 0.0,
                          .hi = 1.5,
                          .doc = "Upper steering angle limit.",
                          .optional = true});
  }
};

struct TrackingParams {
  double tS = 0.01;
  double lookahead_time_long_ff_s = 0.08;
  double velocity_p_gain = 2.0;
  double vel_error_filter_time_constant = 0.5;
  double lookahead_time_lat_ff_s = 0.0;
  double lookahead_time_lat_s = 0.45;
  double min_lookahead_distance_lat_m = 0.1;
  double curvature_lookahead_gain = 0.00004;
  double curvature_filter_Ts = 0.005;
  double enable_lat_feedforward_perc = 0.5;
  double P_VDC_SteeringOvalComp_rad = 0.0;
  TrackingVehicleParams vehicle{};

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.tS, {.key = "tS",
                   .unit = "s",
                   .lo = 1e-4,
                   .hi = 0.1,
                   .doc = "Control period of the tracking controller."});
    v.Field(s.lookahead_time_long_ff_s,
            {.key = "lookahead_time_long_ff_s",
             .unit = "s",
             .lo = 0.0,
             .hi = 2.0,
             .doc = "Preview time of the longitudinal matching point (target speed and a_x).",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.velocity_p_gain, {.key = "velocity_p_gain",
                                .unit = "1/s",
                                .lo = 0.0,
                                .hi = 50.0,
                                .doc = "a_x correction per m/s of filtered speed error.",
                                .scale = Scale::kLinear,
                                .resolution = 0.01});
    v.Field(s.vel_error_filter_time_constant,
            {.key = "vel_error_filter_time_constant",
             .unit = "s",
             .lo = 1e-6,
             .hi = 10.0,
             .doc = "Time constant of the Tustin first-order lag on the speed error.",
             .scale = Scale::kLog,
             .resolution = 0.001});
    v.Field(s.lookahead_time_lat_ff_s, {.key = "lookahead_time_lat_ff_s",
                                        .unit = "s",
                                        .lo = 0.0,
                                        .hi = 2.0,
                                        .doc = "Preview time of the curvature feed-forward.",
                                        .scale = Scale::kLinear,
                                        .resolution = 0.01});
    v.Field(s.lookahead_time_lat_s,
            {.key = "lookahead_time_lat_s",
             .unit = "s",
             .lo = 0.0,
             .hi = 5.0,
             .doc = "Speed-proportional part of the pure-pursuit lookahead distance.",
             .scale = Scale::kLinear,
             .resolution = 0.01});
    v.Field(s.min_lookahead_distance_lat_m, {.key = "min_lookahead_distance_lat_m",
                                             .unit = "m",
                                             .lo = 0.0,
                                             .hi = 100.0,
                                             .doc = "Constant part of the lookahead distance.",
                                             .scale = Scale::kLinear,
                                             .resolution = 0.01});
    v.Field(s.curvature_lookahead_gain,
            {.key = "curvature_lookahead_gain",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Extra lookahead = gain × turn radius (grows without bound on straights on "
                    "the car; the workspace caps it, see the motion-controller options).",
             .scale = Scale::kLinear,
             .resolution = 0.000001});
    v.Field(s.curvature_filter_Ts,
            {.key = "curvature_filter_Ts",
             .unit = "s",
             .lo = 1e-6,
             .hi = 10.0,
             .doc = "TIME CONSTANT of the low-pass on the pure-pursuit curvature (0.005 s ↔ "
                    "pole 0.135 at 100 Hz).",
             .scale = Scale::kLog,
             .resolution = 0.001});
    v.Field(s.enable_lat_feedforward_perc, {.key = "enable_lat_feedforward_perc",
                                            .unit = "-",
                                            .lo = 0.0,
                                            .hi = 1.0,
                                            .doc = "Weight of the curvature feed-forward steering.",
                                            .scale = Scale::kLinear,
                                            .resolution = 0.01});
    v.Field(s.P_VDC_SteeringOvalComp_rad, {.key = "P_VDC_SteeringOvalComp_rad",
                                           .unit = "rad",
                                           .lo = -0.2,
                                           .hi = 0.2,
                                           .doc = "Static steering offset added to the command.",
                                           .optional = true});
    v.Nested("vehicle", s.vehicle, true);
  }
  static void CrossCheck(const TrackingParams& p, Problems& pr) {
    if (!(p.vehicle.min_angle < p.vehicle.max_angle))
      pr.Add("vehicle.steering.min_angle", "must be below vehicle.steering.max_angle");
  }
};

}  // namespace scw::params
