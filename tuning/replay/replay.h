// Open-loop replay of a controller log (controller_log.h) through the stability controller
// (issue 10, `scw replay`; docs/replay.md).
//
// One StabilityController::Step per log row, the State carried from row to row, starting from the
// default (initial) State, exactly as the controller ran inside the closed loop: a log written by
// ControllerLogWriter during a run replays to bit-identical outputs. The controller's options
// (StabilityOptions::release_compat: long_fx ignored) are part of the controller object.
//
// Streaming: the log is read and the output written one row at a time; memory does not grow with
// the log length. The output file is written atomically (temporary file, renamed at the end): a
// bad log leaves no partial output behind.
//
// Output columns (one row per input row), named with their units like the trace of
// `scw simulate --trace` (the same name means the same quantity; the trace's slip_*_pct and
// alpha_*_rad are the plant's, the replay's the controller's estimates): t_s; steer_out_rad;
// p_out_fl_bar..rr; throttle_out [0..1]; esc_active, cs_active, slip_control_active (0/1);
// abs_state_fl..rr, tc_state_fl..rr (0 inactive, 1 reduce, 2 hold, 3 increase); yaw_moment_Nm;
// slip_est_fl_pct..rr; alpha_est_fl_rad..rr (the controller's estimates; the trace's
// slip_fl_pct and alpha_fl_rad are the plant's true values).
//
// Interventions: a subsystem intervenes while its flag is set (ESC: esc_active, countersteer:
// cs_active, ABS: any wheel's ABS phase ≠ inactive, TC: any wheel's TC phase ≠ inactive). An
// intervention is a maximal run of consecutive rows with the flag set; the active time sums
// t[k+1] − t[k] over the active rows k (the last row of the log counts one controller period tS).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>

#include "controller/stability/stability_controller.h"
#include "params/io/atomic_file.h"
#include "tuning/replay/controller_log.h"

namespace scw::tuning::replay {

struct OutputColumn {
  std::string_view name;
  std::string_view unit;
  std::string_view doc;
};

/// Output columns in file order, and the value of column `i` of an output row (flags 0/1, phases
/// 0..3, everything else as computed; column 0 is t, not part of the output: NaN).
extern const std::array<OutputColumn, 27> kOutputColumns;
double OutputValue(const controller::StabilityOutput& out, std::size_t column) noexcept;

/// Writes the replay output file, one row per controller step (streaming, atomic, like
/// ControllerLogWriter).
class ReplayOutputWriter {
 public:
  explicit ReplayOutputWriter(const std::string& path);  ///< throws std::runtime_error
  void Write(double t, const controller::StabilityOutput& out);
  void Commit();  ///< throws std::runtime_error; without it the destructor removes the temp file
  std::int64_t rows() const noexcept { return rows_; }

 private:
  io::AtomicWriter file_;
  std::string row_;
  std::int64_t rows_ = 0;
};

inline constexpr double kNever = std::numeric_limits<double>::quiet_NaN();

/// Activity of one subsystem over a log.
struct SubsystemActivity {
  std::int64_t interventions = 0;  ///< number of episodes (rising edges)
  double active_time = 0.0;        ///< [s]
  std::int64_t active_rows = 0;
  double first_active_t = kNever;  ///< t of the first active row [s] (NaN: never)
};

enum class Subsystem : std::size_t { kEsc = 0, kCountersteer = 1, kAbs = 2, kTc = 3 };
inline constexpr std::size_t kNumSubsystems = 4;
inline constexpr std::array<std::string_view, kNumSubsystems> kSubsystemNames = {
    "ESC", "countersteer", "ABS", "TC"};

/// Whether `s` is intervening in this output.
bool IsActive(Subsystem s, const controller::StabilityOutput& out) noexcept;

struct ReplaySummary {
  std::string log;                ///< log path
  std::int64_t rows = 0;          ///< data rows
  double t_first = kNever;        ///< [s]
  double t_last = kNever;         ///< [s]
  std::int64_t valid_rows = 0;    ///< rows with every essential signal (controller ran)
  std::int64_t invalid_rows = 0;  ///< pass-through rows (essential signal missing/implausible)
  std::int64_t no_slip_rows = 0;  ///< valid rows without all four wheel speeds (no ABS/TC)
  std::array<SubsystemActivity, kNumSubsystems> activity{};  ///< indexed by Subsystem

  const SubsystemActivity& operator[](Subsystem s) const {
    return activity[static_cast<std::size_t>(s)];
  }
  double duration() const { return rows > 0 ? t_last - t_first : 0.0; }  ///< [s]
};

/// Accumulates a ReplaySummary one step at a time (used by ReplayLog and CompareOnLog; usable by
/// any other loop that steps the controller).
class ReplaySummaryBuilder {
 public:
  explicit ReplaySummaryBuilder(std::string log, double sample_time);
  void Add(double t, const controller::StabilityOutput& out);
  /// The summary so far (the last row counted with one period of active time).
  ReplaySummary Finish() const;

 private:
  ReplaySummary s_;
  double tS_;
  std::array<bool, kNumSubsystems> prev_active_{};
};

/// How the log's rows are fed to the controller.
struct ReplayInputOptions {
  /// Ignore the log's vertical loads (`fz_*` columns): the controller estimates its own from
  /// its vehicle constants. A log of `scw simulate` holds the loads its controller used, so
  /// without this option a parameter set with other vehicle constants (CoG height, aero) still
  /// sees the recorded run's loads.
  bool estimate_loads = false;
};

/// Replays `log_path` through `controller`. With a non-empty `output_path` the outputs are
/// written there (atomically). Throws LogFormatError for a bad log (no output is written then),
/// std::runtime_error when the output cannot be written.
ReplaySummary ReplayLog(const std::string& log_path,
                        const controller::StabilityController& controller,
                        const std::string& output_path = "", const ReplayInputOptions& input = {});

/// The largest |difference| of one output between two parameter sets, and where it happened.
struct MaxDifference {
  double value = 0.0;  ///< max |a − b| (0: identical)
  double t = kNever;   ///< t of the first row reaching it [s]
};

/// Two parameter sets (A, B) on the same log.
struct ComparisonSummary {
  ReplaySummary a, b;      ///< per-set summaries (interventions and active times per subsystem)
  MaxDifference steering;  ///< [rad]
  PerWheel<MaxDifference> pressure_bar{};  ///< [bar]
  MaxDifference throttle;                  ///< [0..1]
  MaxDifference yaw_moment;                ///< [N·m]
  std::int64_t differing_rows = 0;         ///< rows where any output column differs
  bool diverged = false;
  double first_divergence_t = kNever;      ///< [s]
  std::int64_t first_divergence_line = 0;  ///< log line (1 = header)
  std::string first_divergence_column;     ///< first output column that differs there
};

/// Steps both controllers over one pass of the log (same rows, each with its own State). With a
/// non-empty `output_path`, A's outputs are written there. Throws like ReplayLog.
ComparisonSummary CompareOnLog(const std::string& log_path,
                               const controller::StabilityController& a,
                               const controller::StabilityController& b,
                               const std::string& output_path = "",
                               const ReplayInputOptions& input = {});

/// Markdown tables of the input and output columns (docs/replay.md, `scw replay --columns`).
std::string ColumnsMarkdown();

/// One-screen text reports.
std::string FormatSummary(const ReplaySummary& s);
std::string FormatComparison(const ComparisonSummary& c, std::string_view name_a,
                             std::string_view name_b);

}  // namespace scw::tuning::replay
