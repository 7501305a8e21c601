// What `scw maneuver` prints and writes about a maneuver (tuning/maneuver/maneuver.h): the text
// table and the JSON document the plot script and experiments/maneuvers.py read.
#pragma once

#include <string>

#include "tuning/maneuver/maneuver.h"

namespace scw::tuning {

/// The result as text: the standard, the scaling to this car (setup), one table row per run (its
/// values, the ESC/CS/ABS/TC activations, the verdict: `pass`, `fail: KEY ...` or `-` when the
/// run has no criterion) and a last line with the criteria checked and failed.
std::string FormatManeuver(const ManeuverResult& r);

/// The result as one JSON object:
///   {"maneuver", "standard", "series", "setup": {key: value},
///    "criteria_checked", "criteria_failed",
///    "runs": [{"label", "level", "status", "values": {key: value},
///              "criteria": [{"key", "value", "limit", "bound": "max"|"min", "source", "passed"}],
///              "metrics": {the run summary's numbers, RunMetrics keys},
///              "signals": {"t_s", "steer_deg", "yaw_rate_degps", "ay_mps2", "beta_deg",
///                          "speed_mps", "heading_deg", "x_m", "y_m": [...]}}]}
/// Numbers in shortest round-trip form, NaN as null. Signals are every `signal_every`-th control
/// tick (≥ 1).
std::string ManeuverJson(const ManeuverResult& r, int signal_every = 2);

}  // namespace scw::tuning
