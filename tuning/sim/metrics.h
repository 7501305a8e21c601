// Outcome of one closed-loop run: how it ended and the quantities the cost and the reports use.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "params/schema/field.h"

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

/// Every member is described once, in Visit (name with unit, doc): the run summaries (text, YAML),
/// the comparison and sweep CSV columns and the exact encoding between processes derive from it.
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
  /// Largest ESC activation margin (controller::EscActivationMargin; > 1: ESC's activation
  /// condition held at least once, whether or not ESC was enabled). Sweep CSV only.
  double max_esc_margin = 0.0;
  /// Largest value of each term of that condition (controller::EscActivationRatios, each taken
  /// on its own while the oversteer signs hold): a term below 1 kept ESC off. Sweep CSV only.
  double max_esc_beta_ratio = 0.0;
  double max_esc_beta_error_ratio = 0.0;
  double max_esc_yaw_rate_error_ratio = 0.0;
  /// [rad] RMS over the run of the steering request's content above ~1.6 Hz (its second-order
  /// high-pass, MetricsAccumulator): a motion controller limit-cycling at a few Hz shows here;
  /// a racing line's own steering hardly does.
  /// A diagnostic of the motion controller, not of the stability parameters: sweep CSV only.
  double steer_hf_rms = 0.0;
  /// Maneuver runs (tuning/maneuver/maneuver.h) only: the standard's pass/fail criteria checked
  /// and failed, and Σ over the failed ones of min(1, |value − limit| / |limit|).
  int criteria_checked = 0;
  int criteria_failed = 0;
  double criteria_miss = 0.0;

  bool aborted() const { return status != RunStatus::kCompleted; }
  /// Mean of the completed laps [s], or NaN if none.
  double MeanLapTime() const;
  /// Fraction of the planned distance driven, in [0, 1].
  double Progress() const;

  /// Every member, in the order of the YAML summary. `v.Output(member, meta)` with member one of
  /// RunStatus, std::vector<double>, int, double.
  template <class Self, class V>
  static void Visit(Self& m, V& v) {
    using params::OutputMeta;
    v.Output(m.status, OutputMeta{.key = "status", .doc = "how the run ended"});
    v.Output(m.lap_times, OutputMeta{.key = "lap_times_s",
                                     .unit = "s",
                                     .doc = "completed laps (lap 1 starts at the flying start)"});
    v.Output(
        m.laps_planned,
        OutputMeta{.key = "laps_planned", .doc = "laps the scenario asks for", .summary = false});
    v.Output(m.time, OutputMeta{.key = "time_s", .unit = "s", .doc = "simulated time at the end"});
    v.Output(m.distance,
             OutputMeta{.key = "distance_m", .unit = "m", .doc = "along the track at the end"});
    v.Output(m.distance_planned, OutputMeta{.key = "distance_planned_m",
                                            .unit = "m",
                                            .doc = "laps × track length",
                                            .summary = false});
    v.Output(
        m.end_s,
        OutputMeta{.key = "end_s_m", .unit = "m", .doc = "track position where the run ended"});
    v.Output(m.end_lap,
             OutputMeta{.key = "end_lap", .doc = "lap index (0-based) where the run ended"});
    v.Output(m.max_abs_sideslip, OutputMeta{.key = "max_abs_sideslip_deg",
                                            .unit = "deg",
                                            .doc = "largest |sideslip angle β|",
                                            .rad_to_deg = true});
    v.Output(m.max_abs_lateral_error,
             OutputMeta{.key = "max_abs_lateral_error_m",
                        .unit = "m",
                        .doc = "largest |lateral error| to the reference line"});
    v.Output(m.max_abs_heading_error, OutputMeta{.key = "max_abs_heading_error_deg",
                                                 .unit = "deg",
                                                 .doc = "largest |heading error| to the reference",
                                                 .rad_to_deg = true});
    v.Output(m.max_slip_front,
             OutputMeta{.key = "max_slip_front_pct",
                        .unit = "%",
                        .doc = "largest |longitudinal slip| of the front wheels"});
    v.Output(m.max_slip_rear, OutputMeta{.key = "max_slip_rear_pct",
                                         .unit = "%",
                                         .doc = "largest |longitudinal slip| of the rear wheels"});
    v.Output(m.sideslip_excess_integral, OutputMeta{.key = "sideslip_excess_deg_s",
                                                    .unit = "deg·s",
                                                    .doc = "∫ max(0, |β| − β_allowed) dt"});
    v.Output(m.max_speed,
             OutputMeta{.key = "max_speed_mps", .unit = "m/s", .doc = "largest speed"});
    v.Output(m.max_esc_margin,
             OutputMeta{.key = "max_esc_margin",
                        .doc = "closest approach to ESC's activation condition (> 1: it held; "
                               "computed with ESC off too)",
                        // A diagnostic of the thresholds, not of the car: it moves with every
                        // ESC threshold even where ESC never acts, so it stays out of the run
                        // summaries and hence out of what counts as exercised
                        // (tuning/optim/sensitivity.h); the sweep CSV has it.
                        .summary = false});
    // The margin's three terms: the same kind of diagnostic, out of the summaries likewise.
    v.Output(m.max_esc_beta_ratio,
             OutputMeta{.key = "max_esc_beta_ratio",
                        .doc = "largest |β|/B_a while ESC's oversteer signs held",
                        .summary = false});
    v.Output(m.max_esc_beta_error_ratio,
             OutputMeta{.key = "max_esc_beta_error_ratio",
                        .doc = "largest |e_β,f|/Eβ_a while ESC's oversteer signs held",
                        .summary = false});
    v.Output(m.max_esc_yaw_rate_error_ratio,
             OutputMeta{.key = "max_esc_yaw_rate_error_ratio",
                        .doc = "largest |e_ψ,f|/Eψ_a while ESC's oversteer signs held",
                        .summary = false});
    v.Output(m.steer_hf_rms,
             OutputMeta{.key = "steer_hf_rms_deg",
                        .unit = "deg",
                        .doc = "RMS of the steering request's content above ~1.6 Hz (a "
                               "limit-cycling motion controller)",
                        .rad_to_deg = true,
                        .summary = false});
    v.Output(m.esc_count, OutputMeta{.key = "esc_count", .doc = "ESC activations (rising edges)"});
    v.Output(m.esc_time,
             OutputMeta{.key = "esc_time_s", .unit = "s", .doc = "time ESC was active"});
    v.Output(m.cs_count,
             OutputMeta{.key = "cs_count", .doc = "countersteer activations (rising edges)"});
    v.Output(m.cs_time,
             OutputMeta{.key = "cs_time_s", .unit = "s", .doc = "time countersteer was active"});
    v.Output(m.abs_count, OutputMeta{.key = "abs_count", .doc = "ABS activations (rising edges)"});
    v.Output(m.abs_time,
             OutputMeta{.key = "abs_time_s", .unit = "s", .doc = "time ABS was active"});
    v.Output(m.tc_count, OutputMeta{.key = "tc_count", .doc = "TC activations (rising edges)"});
    v.Output(m.tc_time, OutputMeta{.key = "tc_time_s", .unit = "s", .doc = "time TC was active"});
    v.Output(m.esc_brake_energy, OutputMeta{.key = "esc_brake_energy_J",
                                            .unit = "J",
                                            .doc = "brake energy caused by ESC pressure changes"});
    v.Output(m.abs_pressure_released,
             OutputMeta{.key = "abs_pressure_released_bar_s",
                        .unit = "bar·s",
                        .doc = "∫ Σ max(0, requested − applied pressure) dt where ABS acts"});
    v.Output(m.tc_throttle_cut,
             OutputMeta{.key = "tc_throttle_cut_s",
                        .unit = "s",
                        .doc = "∫ max(0, requested − applied throttle) dt while TC acts"});
    v.Output(m.criteria_checked, OutputMeta{.key = "criteria_checked",
                                            .doc = "maneuver pass/fail criteria checked",
                                            .summary = false});
    v.Output(m.criteria_failed, OutputMeta{.key = "criteria_failed",
                                           .doc = "maneuver pass/fail criteria failed",
                                           .summary = false});
    v.Output(m.criteria_miss,
             OutputMeta{.key = "criteria_miss",
                        .doc = "Σ over the failed criteria of min(1, relative miss)",
                        .summary = false});
  }
};

/// Derived outputs, rendered beside the members: `mean_lap_time_s` (MeanLapTime) and `progress`
/// (Progress, 0..1).
inline constexpr std::string_view kMeanLapTimeKey = "mean_lap_time_s";
inline constexpr std::string_view kProgressKey = "progress";

/// One rendered number of RunMetrics: an integer member renders as an integer.
struct MetricValue {
  bool is_integer = false;
  long integer = 0;
  double real = 0.0;
};

/// The rendered value of the member or derived output named `key` (degrees for radian members).
/// `status` and `lap_times_s` are not numbers: use RunStatusName and the laps directly. Throws
/// std::logic_error for an unknown key (a bug in the caller).
MetricValue RenderedMetric(const RunMetrics& m, std::string_view key);

/// The keys of the summary numbers in Visit order (status and lap_times_s left out), after
/// `mean_lap_time_s`.
std::vector<std::string_view> SummaryMetricKeys();

/// Every member (RunMetrics::Visit) as text on one line, doubles as hexadecimal floats (printf %a),
/// so that DecodeRunMetrics reads back the same values bit for bit: results between processes
/// (sweep worker processes, MPI ranks).
std::string EncodeRunMetrics(const RunMetrics& m);
/// Reads what EncodeRunMetrics wrote at the start of `text`; returns the position after it, or
/// nullptr when it is not readable.
const char* DecodeRunMetrics(const char* text, RunMetrics* m);

}  // namespace scw::tuning
