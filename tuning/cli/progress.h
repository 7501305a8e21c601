// The progress line of the long-running commands (tune, evaluate, sweep, simulate) on stderr:
//
//   sweep  12/40 runs  elapsed 1 min 05 s  eta 2 min 31 s
//
// phase, work done / total, elapsed wall time, estimated time left (from the rate so far), and an
// optional detail (e.g. the best cost). `--progress auto` (default) shows it only when stderr is
// a terminal, redrawn in place; `always` also when stderr is a file or pipe, then as one line per
// update at most every few seconds (plus the first and the last); `never` prints nothing.
//
// The line only reports: nothing a command computes depends on it. Update may be called from
// several threads (calls are serialised); updates are rate-limited, so calling it often (every
// controller step of a simulation) is cheap.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <mutex>
#include <string>

namespace scw::cli {

enum class ProgressMode { kAuto, kAlways, kNever };

/// Adds `--progress auto|always|never` to a command.
CLI::Option* AddProgressOption(CLI::App* cmd, std::string* value);

/// "auto" (or anything else), "always", "never".
ProgressMode ParseProgressMode(const std::string& text);

/// "42 s", "3 min 05 s", "2 h 07 min" (rounded to what it means).
std::string FormatDuration(double seconds);

struct ProgressUpdate {
  std::string phase;   ///< short word: "sweep", "evaluate", "crs2", "simulate"
  double done = 0.0;   ///< units of work done (shown rounded to whole units)
  double total = 0.0;  ///< units of work in all
  std::string unit;    ///< "runs", "evals", "s simulated"
  std::string detail;  ///< appended as is, e.g. "best cost 12.345" (may be empty)
  /// Time left [s]; < 0: estimated from the rate since the phase started.
  double eta_s = -1.0;
};

class ProgressLine {
 public:
  explicit ProgressLine(ProgressMode mode);
  explicit ProgressLine(const std::string& mode) : ProgressLine(ParseProgressMode(mode)) {}
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  bool enabled() const { return enabled_; }
  /// Shows `u` (rate-limited unless it is the first update of its phase or completes the work).
  void Update(const ProgressUpdate& u);
  /// Prints the last state if it was not shown yet and ends the line (before other messages).
  void Finish();

 private:
  std::string Render(const ProgressUpdate& u, double now_s) const;
  void Print(const std::string& text);

  bool enabled_ = false;
  bool terminal_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
  double phase_start_s_ = 0.0;  ///< since start_
  double last_print_s_ = -1e300;
  double last_done_shown_ = 0.0;
  std::string phase_;
  ProgressUpdate pending_;      ///< the last update (shown or not)
  bool pending_shown_ = true;   ///< whether pending_ was printed
  bool line_open_ = false;      ///< a terminal line without its newline
  std::size_t last_width_ = 0;  ///< characters of the last terminal line
};

}  // namespace scw::cli
