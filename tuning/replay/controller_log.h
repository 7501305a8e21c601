// The controller log: the recorded inputs of the stability controller, one CSV row per controller
// step (issue 10; format reference docs/replay.md). Written by the closed-loop simulation
// (`scw simulate --controller-log FILE`) and by the car's recording tools, read by `scw replay`.
//
// Format:
//  * UTF-8/ASCII text, comma separated, '\n' (or "\r\n") line ends, one header row with the column
//    names, then one row per controller step. Column order is free; every name at most once.
//  * Column names carry their unit as the trace of `scw simulate --trace` does (`vx_mps`,
//    `p_req_fl_bar`, `fz_fl_N`); the names without units of the first version (`vx`, `p_req_fl`)
//    are still read (LogColumn::alias), so older logs stay readable.
//  * Cells are numbers. Real cells are decimal or scientific text (`0.01`, `-3.5e-05`, `inf`);
//    `nan` (any case) or an empty cell = signal not available. Integer columns (`gear_req`,
//    `gear`) hold integer literals and can not be unavailable.
//  * Required columns must be in the header (their cells may still be `nan`: the controller then
//    treats the signal as missing, and a missing essential signal makes the step a pass-through).
//    Optional columns may be left out entirely (= not available in every row).
//  * `t_s` must be finite in every row and never decrease. It is the controller time stamp [s]
//    (durations inside the controller are measured with it; filters assume the period tS).
//  * Written numbers use shortest round-trip formatting (std::to_chars), so reading a log back
//    gives bit-identical doubles and a replay reproduces the recorded run exactly.
//
// Columns (SI units; `_bar` = bar; wheel order fl, fr, rl, rr): see kInputColumns below.
// `long_fx_N` is read always; with StabilityOptions::release_compat the controller ignores it.
// `brake_temp_*_degC` are an optional extension of the column list so that a log written
// from a simulation that feeds brake temperatures is lossless. The closed loop writes the vertical
// loads its controller used (its own estimate) into `fz_*_N` (ControllerLogWriter::Write with the
// output), and what else the controller used besides its params file (the vehicle constants, the
// scenario's subsystem switches) into a setup file next to the log (log_setup.h).
#pragma once

#include <array>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "controller/stability/stability_controller.h"
#include "params/io/atomic_file.h"
#include "params/schema/field.h"

namespace scw::tuning::replay {

/// One column of the controller log and where its value lives in controller::StabilityInput.
/// Exactly one of `real`, `wheel` (with `wheel_index`) and `integer` is set.
struct LogColumn {
  std::string_view name;  ///< header name
  std::string_view unit;
  bool required = true;  ///< must be in the header (cells may still be nan unless integer)
  double controller::StabilityInput::*real = nullptr;
  PerWheel<double> controller::StabilityInput::*wheel = nullptr;
  std::size_t wheel_index = 0;
  int controller::StabilityInput::*integer = nullptr;
  std::string_view doc;
  /// Older name of the column, still accepted by the reader (empty: none). Never written.
  std::string_view alias;
};

/// Every column of the log, in the order ControllerLogWriter writes them.
extern const std::array<LogColumn, 36> kInputColumns;

/// A log that cannot be read: names the file, the line (1 = header) and the column. It is a
/// ConfigError (bad input: `scw` exits with 2). what() reads `FILE: line N, column C: message`.
class LogFormatError : public ConfigError {
 public:
  LogFormatError(const std::string& file, std::int64_t line, std::string column,
                 const std::string& message);
  /// Several header problems at once (line 1).
  LogFormatError(const std::string& file, std::vector<Problem> header_problems,
                 std::string first_column);

  std::int64_t line() const noexcept { return line_; }
  /// Name of the offending column; empty when the problem concerns the whole row or file.
  const std::string& column() const noexcept { return column_; }

 private:
  std::int64_t line_ = 0;
  std::string column_;
};

/// Writes a controller log row by row (streaming: memory stays flat however long the run).
///
/// The rows go to a temporary file next to `path` (same folder, so the final rename is atomic);
/// Commit() makes the log appear under `path` at once. Destroying the writer without Commit()
/// (an exception, an aborted run, Ctrl-C) removes the temporary file and leaves `path`
/// untouched. A symlink's target is written the same way; a FIFO, a character device or `-`
/// (standard output) is written directly (params/io/atomic_file.h). Every column of
/// kInputColumns is written, unavailable signals as `nan`.
///
/// Usage (closed loop):
///   ControllerLogWriter log(path);             // throws std::runtime_error: cannot create
///   for (each step) { log.Write(input); controller.Step(input, &state); ... }
///   log.Commit();                              // throws std::runtime_error: I/O failure
///
/// Not thread-safe (one writer per run). Movable, not copyable.
class ControllerLogWriter {
 public:
  explicit ControllerLogWriter(const std::string& path);
  ~ControllerLogWriter();
  ControllerLogWriter(ControllerLogWriter&&) noexcept;
  ControllerLogWriter& operator=(ControllerLogWriter&&) noexcept;
  ControllerLogWriter(const ControllerLogWriter&) = delete;
  ControllerLogWriter& operator=(const ControllerLogWriter&) = delete;

  /// Appends one row. Throws std::invalid_argument for a row the reader would refuse (t not
  /// finite, or t smaller than the previous row's), std::runtime_error on a write error. Must not
  /// be called after Commit().
  void Write(const controller::StabilityInput& in);

  /// Appends the row of one controller step with the vertical loads the controller used
  /// (`out.fz`, its own estimate unless the input brought valid loads) in the `fz_*` columns, so
  /// that the log is complete: replaying it uses these loads, bit for bit the same. For a
  /// pass-through step (`!out.valid`) the input's loads are written as they are. Throws like
  /// Write(in).
  void Write(const controller::StabilityInput& in, const controller::StabilityOutput& out);

  /// Flushes, closes and renames the temporary file onto the target. Throws std::runtime_error
  /// naming the path on failure (the target is then unchanged and the temporary file removed).
  void Commit();

  const std::string& path() const noexcept;
  std::int64_t rows() const noexcept;
  /// Bytes written so far (header included).
  std::int64_t bytes() const noexcept;
  /// Whether the log goes to a file that can have a setup file next to it (a regular file or a
  /// symlink's target; not `-`, a FIFO or a character device).
  bool is_file() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads a controller log row by row, validating as it goes: the header at construction
/// (unknown, duplicate or missing required column; empty file), each row in Next() (wrong number
/// of cells, non-numeric cell, non-integer gear, t missing or going backwards) and the end of the
/// file (no data row). Every problem throws LogFormatError with the line and the column (spelled
/// as in the file's header: a column read through its old name is named so). Only one line is
/// held in memory.
class ControllerLogReader {
 public:
  /// Opens `path` and reads the header. Throws LogFormatError (also when the file cannot be
  /// opened).
  explicit ControllerLogReader(const std::string& path);

  /// Reads the next row into `*in` (columns absent from the header: not available). Returns
  /// false at the end of the file.
  bool Next(controller::StabilityInput* in);

  /// 1-based line number of the row returned last (1 = header).
  std::int64_t line() const noexcept { return line_no_; }
  /// Number of data rows read so far.
  std::int64_t rows() const noexcept { return rows_; }
  const std::string& path() const noexcept { return path_; }
  /// Header names in file order.
  const std::vector<std::string>& header() const noexcept { return header_; }

 private:
  [[noreturn]] void Fail(const std::string& column, const std::string& message) const;

  std::string path_;
  std::ifstream file_;
  std::string buffer_;
  std::vector<std::string> header_;
  std::vector<int> column_of_cell_;  ///< header position → index into kInputColumns
  std::string t_column_ = "t_s";     ///< the time column as spelled in the header
  std::int64_t line_no_ = 0;
  std::int64_t rows_ = 0;
  double last_t_ = 0.0;
};

namespace detail {

/// Appends the shortest round-trip text of x (`nan` for any NaN, `inf`/`-inf`).
void AppendNumber(std::string* out, double x);
void AppendInteger(std::string* out, long long x);

}  // namespace detail

}  // namespace scw::tuning::replay
