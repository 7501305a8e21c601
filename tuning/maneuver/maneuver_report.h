// What `scw maneuver` prints and writes about a maneuver (tuning/maneuver/maneuver.h): the text
// table and the JSON document the plot script and experiments/maneuvers.py read.
#pragma once

#include <string>

#include "tuning/maneuver/maneuver.h"

namespace scw::tuning {

/// How a maneuver was run besides its setup (the caller knows it: RunManeuver's scenario):
/// the files and the subsystems that ran.
struct ManeuverConditions {
  std::string vehicle = "built-in";    ///< vehicle file, or "built-in"
  std::string stability = "built-in";  ///< stability params file, or "built-in"
  params::SubsystemSwitches subsystems;
};

/// "ESC CS ABS TC", "none" …: the subsystems that ran.
std::string SubsystemsText(const params::SubsystemSwitches& sw);

/// One pass/fail limit of the maneuver as the standard (or the workspace) sets it, with the runs
/// it applies to: the union of the runs' criteria, in first-seen order.
struct ManeuverLimit {
  std::string key;
  double limit = 0.0;
  bool upper = true;
  std::string source;
  std::string runs;  ///< "every run", or "runs 5.00 A to 13.00 A" / "run 4 m/s^2"
};
std::vector<ManeuverLimit> ManeuverLimits(const ManeuverResult& r);

/// Notes on what the maneuver did not test: a subsystem that ran but never acted (e.g. ESC in a
/// sine with dwell at 80 km/h, where the car stays below its thresholds), so that a pass with
/// stability control on is not read as ESC's.
std::vector<std::string> ManeuverNotes(const ManeuverResult& r, const ManeuverConditions& c);

/// The result as text: the standard, the conditions (files, subsystems), the scaling to this car
/// (setup), the pass limits, what each column is, one table row per run (its values, the
/// ESC/CS/ABS/TC activations, the verdict: `pass`, `fail: KEY ...` or `-` when the run has no
/// criterion), a line with the criteria checked and failed, and the notes (ManeuverNotes).
std::string FormatManeuver(const ManeuverResult& r, const ManeuverConditions& conditions = {});

/// The result as one JSON object:
///   {"maneuver", "standard", "series", "setup": {key: value},
///    "conditions": {"vehicle", "stability", "subsystems", "stability_control": "on"|"off"|
///                   "partial"},
///    "limits": [{"key", "limit", "bound", "source", "runs"}], "notes": [text],
///    "criteria_checked", "criteria_failed",
///    "runs": [{"label", "level", "status", "values": {key: value},
///              "criteria": [{"key", "value", "limit", "bound": "max"|"min", "source", "passed"}],
///              "metrics": {the run summary's numbers, RunMetrics keys},
///              "signals": {"t_s", "steer_deg", "yaw_rate_degps", "ay_mps2", "beta_deg",
///                          "speed_mps", "heading_deg", "x_m", "y_m",
///                          "slip_rear_pct" (the rear wheel of larger |slip|, < 0 braking):
///                          [...]}}]}
/// Numbers in shortest round-trip form, NaN as null. Signals are every `signal_every`-th control
/// tick (≥ 1).
std::string ManeuverJson(const ManeuverResult& r, int signal_every = 2,
                         const ManeuverConditions& conditions = {});

}  // namespace scw::tuning
