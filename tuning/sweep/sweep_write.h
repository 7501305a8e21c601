// Write: a SweepResult as the results CSV and as the console table, the traced runs' file names
// and selection. Nothing here runs a simulation.
#pragma once

#include <string>
#include <vector>

#include "tuning/sweep/sweep_run.h"
#include "tuning/sweep/sweep_spec.h"

namespace scw::tuning::sweep {

/// Whether a run matches parsed trace conditions (ParseTraceConditions): conditions on different
/// keys must all hold, on the same key any one value (SameSweepValue); none = every run.
bool SelectedForTrace(const SweepResult& r, const SweepRun& run,
                      const std::vector<TraceCondition>& conditions);

/// The same for `--trace-at` texts (throws ConfigError for a malformed condition or a key that is
/// neither `config` nor varied).
bool MatchesTraceConditions(const SweepResult& r, const SweepRun& run,
                            const std::vector<std::string>& at);

/// "<config>__<key>-<value>[__...].csv", characters outside [A-Za-z0-9_.+-] replaced by '_'.
std::string TraceFileName(const SweepResult& r, const SweepRun& run);

/// Writes the reported runs as CSV (atomic; shortest round-trip numbers; NaN as "nan"):
/// config, the varied keys, status, progress, laps_completed, lap_1_s..lap_N_s, mean_lap_time_s,
/// max_abs_sideslip_deg, max_slip_front_pct, max_slip_rear_pct, max_abs_lateral_error_m,
/// max_abs_heading_error_deg, max_speed_mps, {esc,cs,abs,tc}_count, {esc,cs,abs,tc}_time_s,
/// esc_brake_energy_J, max_esc_margin, max_esc_{beta,beta_error,yaw_rate_error}_ratio,
/// steer_hf_rms_deg, end_lap, end_s_m, ideal_lap_time_s. The metric columns are
/// those of RunMetrics::Visit (names, units and conversions: RenderedMetric).
void WriteSweepCsv(const std::string& path, const SweepResult& r);

/// The console table of the reported runs, one line each: configuration, varied values and status
/// (text columns as wide as their longest entry), mean lap time [s], max |sideslip| [deg], max
/// slip front/rear [%] ("-" for NaN).
std::string SweepTable(const SweepResult& r);

}  // namespace scw::tuning::sweep
