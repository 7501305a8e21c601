// Outcome of one closed-loop run: how it ended and the quantities the cost and the reports use.
#pragma once

#include <string>
#include <vector>

namespace scw::tuning {

/// How a run ended. Everything but kCompleted is an abort.
enum class RunStatus {
  kCompleted,      ///< all laps driven
  kSideslip,       ///< |β| above the abort threshold
  kLateralError,   ///< lateral error above the abort threshold
  kWheelLock,      ///< a wheel's slip below −threshold for longer than the allowed time
  kWheelSpin,      ///< a wheel's slip above +threshold for longer than the allowed time
  kOffTrack,       ///< the car left the track bounds
  kNonFinite,      ///< NaN/inf in the plant or controller
  kTimeout,        ///< simulated time limit reached before the laps were done
  kInvalidParams,  ///< the parameter set was rejected before the run (schema rule violated)
};

const char* RunStatusName(RunStatus s);

struct RunMetrics {
  RunStatus status = RunStatus::kCompleted;
  std::vector<double> lap_times;  ///< [s] completed laps (lap 1 starts at the flying start)
  int laps_planned = 0;
  double time = 0.0;                      ///< [s] simulated time at the end
  double distance = 0.0;                  ///< [m] along the track at the end
  double distance_planned = 0.0;          ///< [m] laps × track length
  double end_s = 0.0;                     ///< [m] track position where the run ended
  int end_lap = 0;                        ///< lap index (0-based) where the run ended
  double max_abs_sideslip = 0.0;          ///< [rad]
  double max_abs_lateral_error = 0.0;     ///< [m]
  double max_abs_heading_error = 0.0;     ///< [rad]
  double max_slip_front = 0.0;            ///< [%] largest |longitudinal slip| of the front wheels
  double max_slip_rear = 0.0;             ///< [%] largest |longitudinal slip| of the rear wheels
  double sideslip_excess_integral = 0.0;  ///< [deg·s] ∫ max(0, |β| − β_allowed) dt
  double esc_time = 0.0, cs_time = 0.0, abs_time = 0.0, tc_time = 0.0;  ///< [s] active time
  int esc_count = 0, cs_count = 0, abs_count = 0, tc_count = 0;  ///< activations (rising edges)
  double esc_brake_energy = 0.0;  ///< [J] brake energy caused by ESC pressure changes
  /// [bar·s] ∫ Σ max(0, requested − applied pressure) dt over the wheels ABS acts on
  double abs_pressure_released = 0.0;
  /// [s] ∫ max(0, requested − applied throttle) dt while TC acts (throttle 0..1)
  double tc_throttle_cut = 0.0;
  double max_speed = 0.0;  ///< [m/s]

  bool aborted() const { return status != RunStatus::kCompleted; }
  /// Mean of the completed laps [s], or NaN if none.
  double MeanLapTime() const;
  /// Fraction of the planned distance driven, in [0, 1].
  double Progress() const;
};

/// Every field as text on one line, doubles as hexadecimal floats (printf %a), so that
/// DecodeRunMetrics reads back the same values bit for bit: results between processes (sweep
/// worker processes, MPI ranks). Update both when RunMetrics grows.
std::string EncodeRunMetrics(const RunMetrics& m);
/// Reads what EncodeRunMetrics wrote at the start of `text`; returns the position after it, or
/// nullptr when it is not readable.
const char* DecodeRunMetrics(const char* text, RunMetrics* m);

}  // namespace scw::tuning
