// Powertrain parameters of the plant: engine torque map, gearbox with automatic shifting and torque
// interruption, final drive, rear differential (spool or limited slip).
// Source of the model: ../shared/spec/plant-and-track.md §3.1 (TUM sim_vehicle_dynamics powertrain)
// and §2.4 (Open Car Dynamics RWD_LSD). In-class defaults: EAV24/25-class car (A2RL, Dallara SF23
// based), public estimates of spec §4.5/§4.6/§7; each value says where it comes from.
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

/// Engine: torque map over (engine speed x throttle), rev limiter, launch-clutch speed, inertia.
struct EngineParams {
  std::vector<double> map_speed_rpm = {1000, 2000, 3000, 4000, 4500, 5500, 6500, 7250, 7500};
  std::vector<double> map_throttle = {0.0, 0.25, 0.5, 0.75, 1.0};
  // Row-major: one row per map_speed_rpm entry, one column per map_throttle entry.
  std::vector<double> map_torque = {
      -20.0,  22.5,   65.0,   107.5,  150.0,  //
      -26.15, 45.38,  116.92, 188.46, 260.0,  //
      -32.31, 75.77,  183.85, 291.92, 400.0,  //
      -38.46, 101.15, 240.77, 380.38, 520.0,  //
      -41.54, 103.85, 249.23, 394.62, 540.0,  //
      -47.69, 99.23,  246.15, 393.08, 540.0,  //
      -53.85, 94.62,  243.08, 391.54, 540.0,  //
      -58.46, 91.15,  240.77, 390.38, 540.0,  //
      -60.0,  85.0,   230.0,  375.0,  520.0,  //
  };
  double clutch_slip_rpm = 3500.0;
  double rev_limit_rpm = 7500.0;
  double rev_limiter_band_rpm = 100.0;
  double inertia = 0.15;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.map_speed_rpm,
            {.key = "map_speed_rpm",
             .unit = "rpm",
             .lo = 0.0,
             .hi = 20000.0,
             .doc = "Engine-speed breakpoints of the torque map (rows). Outside the range the "
                    "map is held at the end rows.",
             .min_size = 2,
             .ascending = true});
    v.Field(s.map_throttle,
            {.key = "map_throttle",
             .unit = "-",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Throttle breakpoints of the torque map (columns), 0 = closed, 1 = full.",
             .min_size = 2,
             .ascending = true});
    v.Field(s.map_torque,
            {.key = "map_torque",
             .unit = "N*m",
             .lo = -2000.0,
             .hi = 5000.0,
             .doc = "Crankshaft torque, row-major (speed rows x throttle columns), bilinear "
                    "interpolation. EAV24: 2.0 L turbo I4 of the SF23, 540 N*m flat from 4500 "
                    "to 7250 rpm = 410 kW (550 hp) peak power (spec §7); closed-throttle drag "
                    "-20 to -60 N*m and linear throttle blend are assumptions (no public map).",
             .min_size = 4});
    v.Field(s.clutch_slip_rpm,
            {.key = "clutch_slip_rpm",
             .unit = "rpm",
             .lo = 0.0,
             .hi = 10000.0,
             .doc = "Engine speed held while the launch clutch slips (below the road speed at "
                    "which the engaged gear reaches it); the map torque at this speed is "
                    "transmitted. No clutch dynamics are modelled (assumption)."});
    v.Field(s.rev_limit_rpm,
            {.key = "rev_limit_rpm",
             .unit = "rpm",
             .lo = 1000.0,
             .hi = 20000.0,
             .doc = "Rev limiter: positive torque fades linearly to 0 between this speed and "
                    "rev_limit + band. EAV24: 7500 rpm (A2RL upshift points 6800-7000 rpm, "
                    "spec §4.5)."});
    v.Field(s.rev_limiter_band_rpm,
            {.key = "rev_limiter_band_rpm",
             .unit = "rpm",
             .lo = 1.0,
             .hi = 2000.0,
             .doc = "Width of the rev-limiter torque fade (a smooth cut avoids chatter)."});
    v.Field(s.inertia,
            {.key = "inertia",
             .unit = "kg*m^2",
             .lo = 0.0,
             .hi = 5.0,
             .doc = "Engine + gearbox input inertia, reflected to the rear axle by (i_g i_f)^2 "
                    "while a gear is engaged and the clutch is closed. EAV24: 0.15 (assumption, "
                    "AV-21 engine 0.2, spec §4.1)."});
  }
  static void CrossCheck(const EngineParams& p, Problems& pr) {
    if (p.map_torque.size() != p.map_speed_rpm.size() * p.map_throttle.size())
      pr.Add("map_torque", "needs map_speed_rpm.size() x map_throttle.size() = " +
                               std::to_string(p.map_speed_rpm.size() * p.map_throttle.size()) +
                               " values (row-major), has " + std::to_string(p.map_torque.size()));
  }
};

/// Sequential gearbox with automatic up/down shifts by engine speed and a torque interruption.
struct GearboxParams {
  std::vector<double> ratios = {3.083, 2.286, 1.7647, 1.421, 1.19, 1.036};
  std::vector<double> efficiency = {0.95, 0.95, 0.95, 0.95, 0.95, 0.95};
  double final_drive_ratio = 2.818;
  double final_drive_efficiency = 0.97;
  std::vector<double> upshift_rpm = {7300, 7300, 7300, 7300, 7300};
  std::vector<double> downshift_rpm = {4800, 5000, 5300, 5600, 5800};
  double shift_time = 0.1;
  double min_time_in_gear = 0.3;
  int initial_gear = 1;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.ratios, {.key = "ratios",
                       .lo = 0.3,
                       .hi = 6.0,
                       .doc = "Gear ratios i_g (engine speed / gearbox output speed), first to "
                              "top. EAV24: SF23 six-speed [3.083 ... 1.036] (A2RL team config, "
                              "spec §4.5)."});
    v.Field(s.efficiency, {.key = "efficiency",
                           .lo = 0.5,
                           .hi = 1.0,
                           .doc = "Mechanical efficiency of each gear (applied to drive and "
                                  "engine-braking torque alike). EAV24: 0.95 (assumption)."});
    v.Field(s.final_drive_ratio,
            {.key = "final_drive_ratio",
             .lo = 0.5,
             .hi = 10.0,
             .doc = "Final drive ratio i_f. EAV24: 2.818 (A2RL team config, spec §4.5); with "
                    "the 6th gear and 7500 rpm this gives 82 m/s."});
    v.Field(s.final_drive_efficiency,
            {.key = "final_drive_efficiency",
             .lo = 0.5,
             .hi = 1.0,
             .doc = "Efficiency of final drive and differential. EAV24: 0.97 (AV-21: "
                    "0.98 x 0.99)."});
    v.Field(s.upshift_rpm,
            {.key = "upshift_rpm",
             .unit = "rpm",
             .lo = 500.0,
             .hi = 20000.0,
             .doc = "Upshift engine speed of gear 1 .. N-1 (N-1 values): the shift is requested "
                    "when the engine reaches it. EAV24: 7300 rpm (assumption, just below the "
                    "limiter)."});
    v.Field(s.downshift_rpm,
            {.key = "downshift_rpm",
             .unit = "rpm",
             .lo = 0.0,
             .hi = 20000.0,
             .doc = "Downshift engine speed of gear 2 .. N (N-1 values): gear k+1 shifts down "
                    "when the engine falls below downshift_rpm[k-1]. EAV24: 4800-5800 rpm "
                    "(assumption; keeps the engine in its 540 N*m band)."});
    v.Field(s.shift_time,
            {.key = "shift_time",
             .unit = "s",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Torque interruption per shift: from the shift decision (gear request "
                    "changes) until the new gear is engaged, the engine transmits no torque. "
                    "0.1 s as the AV-21 throttle shift break (spec §3.1, §9)."});
    v.Field(s.min_time_in_gear,
            {.key = "min_time_in_gear",
             .unit = "s",
             .lo = 0.0,
             .hi = 5.0,
             .doc = "Minimum time after an engagement before the next shift may be requested "
                    "(prevents hunting)."});
    v.Field(s.initial_gear, {.key = "initial_gear",
                             .lo = 1,
                             .hi = 10,
                             .doc = "Gear engaged at rest; a rolling start selects the gear "
                                    "from speed."});
  }
  static void CrossCheck(const GearboxParams& p, Problems& pr) {
    const std::size_t n = p.ratios.size();
    if (p.efficiency.size() != n) pr.Add("efficiency", "needs one value per gear ratio");
    if (n >= 1 && p.upshift_rpm.size() != n - 1)
      pr.Add("upshift_rpm", "needs (number of gears - 1) values");
    if (n >= 1 && p.downshift_rpm.size() != n - 1)
      pr.Add("downshift_rpm", "needs (number of gears - 1) values");
    for (std::size_t k = 1; k < n; ++k)
      if (!(p.ratios[k] < p.ratios[k - 1])) {
        pr.Add("ratios", "must decrease from first to top gear");
        break;
      }
    if (p.initial_gear > static_cast<int>(n))
      pr.Add("initial_gear", "is above the number of gears");
    // Hysteresis: after a downshift the engine must land below the upshift speed of the new gear.
    if (p.upshift_rpm.size() == n - 1 && p.downshift_rpm.size() == n - 1)
      for (std::size_t k = 0; k + 1 < n; ++k)
        if (p.downshift_rpm[k] * p.ratios[k] / p.ratios[k + 1] >= p.upshift_rpm[k])
          pr.Add("downshift_rpm", "gear " + std::to_string(k + 2) +
                                      ": a downshift would land above the upshift speed of gear " +
                                      std::to_string(k + 1) + " (shift hunting)");
  }
};

/// Rear differential: a locked spool or a limited-slip differential.
struct DifferentialParams {
  std::string type = "lsd";
  double lsd_preload = 50.0;
  double lsd_lock_drive = 0.3;
  double lsd_lock_coast = 0.15;
  double lsd_speed_scale = 1.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.type, {.key = "type",
                     .doc = "'spool': both rear wheels turn at the same speed (locked; the TUM "
                            "AV-21 simulation model). 'lsd': open differential plus a locking "
                            "torque (below). EAV24: lsd, the SF23-based car's limited-slip "
                            "differential (plant spec §4.6/§7, TUM A2RL stack summary); preload "
                            "and locking ratios below are assumptions.",
                     .choices = "spool|lsd"});
    v.Field(s.lsd_preload, {.key = "lsd_preload",
                            .unit = "N*m",
                            .lo = 0.0,
                            .hi = 5000.0,
                            .doc = "LSD preload: minimum locking torque."});
    v.Field(s.lsd_lock_drive, {.key = "lsd_lock_drive",
                               .lo = 0.0,
                               .hi = 1.0,
                               .doc = "LSD locking torque per unit input torque under drive: "
                                      "M_lock = max(preload, k |T_in|) (ramp-type plate LSD)."});
    v.Field(s.lsd_lock_coast, {.key = "lsd_lock_coast",
                               .lo = 0.0,
                               .hi = 1.0,
                               .doc = "LSD locking torque per unit input torque on overrun."});
    v.Field(s.lsd_speed_scale,
            {.key = "lsd_speed_scale",
             .unit = "rad/s",
             .lo = 0.01,
             .hi = 100.0,
             .doc = "Wheel-speed difference over which the locking torque builds up "
                    "(M = M_lock tanh(dw/scale)); smooths the stick-slip of the clutch pack."});
  }
};

}  // namespace scw::params
