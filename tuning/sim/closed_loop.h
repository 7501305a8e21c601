// One closed-loop run: plant at its own step (1 kHz), motion and stability controllers at their
// sample time (100 Hz), a flying start on the reference line at the reference speed, N laps.
//
// Per control tick, in this order: measurement (with seeded noise if enabled) → motion controller
// (steering, a_x and ESC a_y requests) → longitudinal controller (long_fx, throttle, pressures;
// feedback frozen while slip control was active on the previous tick) → stability controller →
// actuator commands held until the next tick. The run ends when all laps are driven or at the
// first abort condition (|β|, lateral error to the reference, wheel lock or spin held for a time,
// leaving the track, non-finite values, timeout); it reports which and where (s, lap, time).
// Metrics follow tuning/sim/metrics.h. A run is a pure function of its inputs (scenario, stability
// set, seed): deterministic and thread-safe, so many runs may execute in parallel.
//
// The ticks run in the shared control loop (tuning/sim/control_loop.h), the one step loop that
// the standard maneuvers drive too: this file supplies its input (lap progress, events, motion
// control, request path), its observers and the road and air under the car.
//
// Each tick is handed as a TickRecord (tuning/sim/tick_record.h) to the run's observers: the lap
// counter, the metrics and the abort rules (tuning/sim/run_observers.h, which states the rules and
// their order) and the trace (tuning/sim/trace_schema.h, the one table of its columns).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "controller/stability/stability_controller.h"
#include "params/schema/stability_params.h"
#include "tuning/sim/metrics.h"
#include "tuning/sim/scenario.h"

namespace scw::io {
class CsvWriter;
}  // namespace scw::io

namespace scw::tuning {

struct RunOptions {
  /// Trace at the scenario's log rate (one column per signal, units in the header) or nullptr.
  io::CsvWriter* trace = nullptr;
  /// Called with every controller input (for the replay log), or nullptr.
  std::function<void(const controller::StabilityInput&)> on_controller_input;
  /// Called with every controller output, or nullptr.
  std::function<void(const controller::StabilityOutput&)> on_controller_output;
  /// |β| above this counts into RunMetrics::sideslip_excess_integral [deg].
  double sideslip_allowed_deg = 5.0;
};

/// Header of the trace CSV: the names (with units) of kTraceColumns (tuning/sim/trace_schema.h),
/// in file order.
std::vector<std::string> TraceHeader();

/// Runs the scenario with `stability` (before vehicle injection and subsystem switches; see
/// PrepareStability). Never throws for a run that fails: the failure is the status. Throws
/// ConfigError only if `stability` itself is invalid.
RunMetrics RunClosedLoop(const ResolvedScenario& sc, const params::StabilityParams& stability,
                         const RunOptions& options = {});

}  // namespace scw::tuning
