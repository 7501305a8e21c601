// The trace of a closed-loop run (`scw simulate --trace`, sweep --trace-dir): one CSV row per
// logged control tick, described once. kTraceColumns lists every column in file order with its
// header name (the unit is part of the name: `vx_mps`, `p_req_fl_bar`), its unit, how its value
// is read from a TickRecord (tuning/sim/tick_record.h) and what it means. TraceHeader()
// (closed_loop.h) is the names of this table; WriteTraceRow writes one row from it, so the header
// and the rows cannot drift apart.
//
// Cell text: a real column goes through CsvWriter::Add(double) (shortest round-trip text, `nan`),
// an integer column through CsvWriter::Add(int); the overload is part of the format and fixed by
// the column. Angles are in degrees where the name says `_deg`, slips in percent (`_pct`),
// pressures in bar (`_bar`); everything else SI. Wheel order fl, fr, rl, rr.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

#include "tuning/sim/tick_record.h"

namespace scw::io {
class CsvWriter;
}  // namespace scw::io

namespace scw::tuning {

/// One column of the trace. Exactly one of `real` and `integer` is set; it decides the CsvWriter
/// overload, and so the text of the cell.
struct TraceColumn {
  std::string_view name;  ///< header name, unit suffix included
  std::string_view unit;  ///< unit of the value ("-" for counts and flags)
  /// Value of a real column; `wheel` is the column's wheel index (0 for whole-car signals).
  double (*real)(const TickRecord& r, std::size_t wheel) = nullptr;
  int (*integer)(const TickRecord& r) = nullptr;  ///< value of an integer column
  std::size_t wheel = 0;                          ///< wheel index of a per-wheel column
  std::string_view doc;
};

/// Every column of the trace, in file order (names unique).
extern const std::array<TraceColumn, 54> kTraceColumns;

/// Appends the cells of `r` in the order of kTraceColumns to `*w` and ends the row. Throws what
/// CsvWriter::EndRow throws (std::logic_error) when `w` was not opened with TraceHeader().
void WriteTraceRow(const TickRecord& r, io::CsvWriter* w);

/// The trace of one run: one row at every `every`-th control tick, starting with tick 0. The
/// writer's row buffer is reused, so recording allocates nothing per tick once the row has grown.
/// Not thread-safe (one recorder and one writer per run).
class TraceRecorder {
 public:
  /// `writer`: opened with TraceHeader(), or nullptr for no trace; it must outlive the recorder.
  /// `every` ≥ 1 [ticks].
  TraceRecorder(io::CsvWriter* writer, long every) noexcept : writer_(writer), every_(every) {}

  /// Writes `r` when there is a writer and `tick` (0-based) is a multiple of `every`. Throws as
  /// WriteTraceRow.
  void Record(long tick, const TickRecord& r) {
    if (writer_ && tick % every_ == 0) WriteTraceRow(r, writer_);
  }

 private:
  io::CsvWriter* writer_;
  long every_;
};

}  // namespace scw::tuning
