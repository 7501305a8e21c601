// Standard open-loop maneuvers: a prescribed input program drives the plant with the stability
// controller in the loop and no motion controller, as a driving robot does on a proving ground,
// and the standard's metrics and pass/fail criteria are computed from the run
// (docs/maneuvers.md).
//
// The car is a scenario's (Resolve of a scenario with `kind: maneuver`, tuning/sim/scenario.h):
// its vehicle with the grip factors and plant step, the stability set with the vehicle constants
// injected and the subsystem switches applied, exactly as the closed loop gets them. The section
// `maneuver:` (params/schema/maneuver_params.h) picks the test and its scaling to this car.
//
// One tick, per controller period tS (the plant steps tS/h times in between), in the closed
// loop's own control loop (tuning/sim/control_loop.h; this file drives it and has no step loop):
// measurement → the robot's command (input program; speed hold by throttle where the program asks
// for it; heading hold by steering in the split-mu and mu-jump tests) → the stability controller's
// input (steering, throttle and brake requests; long_fx from the engine map at the requested
// throttle, or −Σ k_b p / r of the requested pressures; no ESC targets, so ESC uses its own
// single-track reference) → the stability controller → the plant. The road under each wheel (split
// mu, mu jump) reaches the plant as its Environment.
//
// Runs: each maneuver is a series of runs (sine with dwell: one slowly increasing steer for A, then
// one run per amplitude; braking in a turn: one per deceleration; the others one run). Every run
// starts at rest in yaw, straight at the test speed (MakeState), settles (speed hold; on the circle
// for the in-turn tests), and its program starts at t = 0 (the settling phase has t < 0).
//
// A run is a pure function of its inputs: deterministic and thread-safe. A maneuver never aborts on
// the closed loop's rules (a spin is a result, not an error): only a non-finite state ends a run
// early (status kNonFinite).
#pragma once

#include <string>
#include <vector>

#include "params/schema/stability_params.h"
#include "tuning/sim/metrics.h"
#include "tuning/sim/scenario.h"

namespace scw::io {
class CsvWriter;
}  // namespace scw::io

namespace scw::tuning {

/// One number a maneuver reports.
struct ManeuverValue {
  std::string key;   ///< snake_case name with the unit suffix (`ratio_1_00_pct`)
  double value = 0;  ///< NaN when it could not be computed
  std::string doc;   ///< what it is, in a few words
};

/// One pass/fail criterion: `value` must be ≤ `limit` (`upper`) or ≥ `limit`.
struct ManeuverCriterion {
  std::string key;     ///< the value's key
  double value = 0.0;  ///< NaN fails
  double limit = 0.0;
  bool upper = true;
  std::string source;  ///< "FMVSS 126 S5.2.1", or "workspace" for the workspace's own limits
  bool passed() const;
  /// min(1, |value − limit| / |limit|) when failed (1 for NaN or a zero limit), else 0.
  double miss() const;
};

/// The signals of one run, per control tick (for the metrics and the plots).
struct ManeuverSignals {
  std::vector<double> t;              ///< [s] since the program began (< 0 while settling)
  std::vector<double> steer;          ///< [rad] the robot's road-wheel angle request
  std::vector<double> yaw_rate;       ///< [rad/s] measured
  std::vector<double> a_x;            ///< [m/s²] measured
  std::vector<double> a_y;            ///< [m/s²] measured
  std::vector<double> beta;           ///< [rad] sideslip (as the closed loop computes it)
  std::vector<double> speed;          ///< [m/s]
  std::vector<double> heading;        ///< [rad] ψ − ψ at t = 0
  std::vector<double> x, y;           ///< [m] position in the frame of the car at t = 0
  std::vector<double> max_slip_rear;  ///< [%] rear wheel of larger |slip|, signed (< 0 brakes)
};

struct ManeuverRun {
  std::string label;   ///< "3.5 A", "4 m/s^2" …
  double level = 0.0;  ///< the series variable (amplitude factor, deceleration …)
  std::vector<ManeuverValue> values;
  std::vector<ManeuverCriterion> criteria;
  RunMetrics metrics;  ///< sideslip, interventions, slips of the run (no laps)
  ManeuverSignals signals;
};

struct ManeuverResult {
  std::string name;      ///< params::ManeuverParams::name
  std::string standard;  ///< "FMVSS 126 / UN R140 sine with dwell" …
  std::string series;    ///< what `level` of the runs is ("amplitude factor [A]") or ""
  /// The scaling to this car, stated: test speed, steering ratio, A, the circle's steer …
  std::vector<ManeuverValue> setup;
  std::vector<ManeuverRun> runs;

  /// Every run's metrics folded into one: the worst status, the largest extremes, summed
  /// integrals, interventions and criteria (criteria_checked, criteria_failed, criteria_miss).
  RunMetrics Summary() const;
};

struct ManeuverOptions {
  /// Trace of every run (TraceHeader() columns, tuning/sim/trace_schema.h) or nullptr; see
  /// docs/maneuvers.md for what the track columns hold in a maneuver.
  io::CsvWriter* trace = nullptr;
  /// |β| above this counts into RunMetrics::sideslip_excess_integral [deg].
  double sideslip_allowed_deg = 5.0;
};

/// Runs the maneuver of `sc.spec.maneuver` with `stability` (before vehicle injection and
/// subsystem switches, as RunClosedLoop). Throws ConfigError only for an invalid `stability` or a
/// maneuver the car cannot drive (e.g. a steady circle beyond its limits).
ManeuverResult RunManeuver(const ResolvedScenario& sc, const params::StabilityParams& stability,
                           const ManeuverOptions& options = {});

/// The names RunManeuver knows (params::ManeuverParams::name's choices), in the suite's order.
const std::vector<std::string>& ManeuverNames();

}  // namespace scw::tuning
