// The wrapper the model-predictive motion controllers (point-mass tube MPC, single-track NMPC)
// share: the planner's acceleration limits, the drivable corridor around the reference path, the
// solve-time statistics, and the rules around a solve (MpcController, MpcState): a solve that
// fails or throws keeps the previous plan (shifted in time) while it lasts; once it has run out
// each controller's fallback law drives until a solve succeeds. Both are counted.
//
// Acceleration limits (GgTable): the velocity planner's own table and law (controller/planning/
// ggv.h: drive and brake exponents per speed), already scaled (limit_fraction × GG × the plant's
// combined envelope), so the MPCs use exactly the limits the reference was planned with.
//
// Corridor: for every station of the reference Path the admissible lateral offset n [m] of the
// CoG from the path (n > 0 left, as PathProjection::lateral_error): −right(s) ≤ n ≤ left(s), both
// ≥ 0, built by the caller from the track widths (tuning/sim/motion_factory.cc).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "controller/motion/motion_controller.h"
#include "controller/motion/path.h"
#include "controller/planning/corridor.h"
#include "controller/planning/ggv.h"
#include "params/schema/field.h"

namespace scw::controller::motion {

/// The planner's g-g-v table (controller/planning/ggv.h), already scaled by the caller.
using GgTable = planning::GgvTable;

/// Lateral bounds around the path, one entry per Path station (see the file comment).
using Corridor = planning::Corridor;

/// The constructor checks both MPCs share: a path is given (key "path"), the limits are valid
/// (GgvTable::Validate, keys under "limits."), the corridor has one entry per path station (keys
/// "corridor.left", "corridor.right").
Problems ValidateMpcInputs(const Path* path, const GgTable& limits, const Corridor& corridor);

/// Linear interpolation of per-station values of `path` at s (wrapped). Allocation-free.
double InterpolateStations(const Path& path, const std::vector<double>& values, double s) noexcept;

/// Solve-time statistics over a run: every solve's wall time in a ring buffer preallocated at
/// construction (the newest `capacity` solves are kept for the median; count and max cover all).
/// Wall-clock time is used for statistics only, never for control outputs.
class SolveStats {
 public:
  explicit SolveStats(std::size_t capacity = 1 << 16) : times_(capacity, 0.0) {}
  void Add(double seconds) noexcept;
  std::int64_t count() const noexcept { return count_; }
  double max() const noexcept { return max_; }
  double mean() const noexcept { return count_ > 0 ? sum_ / static_cast<double>(count_) : 0.0; }
  /// Median of the kept samples [s] (0 without samples). Allocates a copy: call outside Step.
  double Median() const;
  /// Quantile q in [0, 1] of the kept samples [s].
  double Quantile(double q) const;

 private:
  std::vector<double> times_;
  std::int64_t count_ = 0;
  double max_ = 0.0;
  double sum_ = 0.0;
};

/// Measures the wall time of a scope into a SolveStats (statistics only).
class ScopedSolveTimer {
 public:
  explicit ScopedSolveTimer(SolveStats* stats) noexcept
      : stats_(stats), start_(std::chrono::steady_clock::now()) {}
  ~ScopedSolveTimer() {
    stats_->Add(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedSolveTimer(const ScopedSolveTimer&) = delete;
  ScopedSolveTimer& operator=(const ScopedSolveTimer&) = delete;

 private:
  SolveStats* stats_;
  std::chrono::steady_clock::time_point start_;
};

/// What every MPC state reports (solver health and timing).
struct MpcDiagnostics {
  SolveStats solve_time;            ///< per solver call [s]
  std::int64_t solves = 0;          ///< solver calls
  std::int64_t failures = 0;        ///< calls whose result was not used (plan shifted instead)
  std::int64_t fallback_steps = 0;  ///< steps driven by the fallback law (no usable plan left)
  std::int64_t iterations = 0;      ///< solver iterations, summed
  int last_status = 0;              ///< last Ipopt ApplicationReturnStatus
};

class NlpSolver;
class SparseNlp;

/// The state both MPCs share: the plan in use, the scratch plan (its shifted warm start) and the
/// diagnostics. `Plan` has the members `t0` (time of node 0 [s]), `valid` and `Resize(n)` (sized
/// for n intervals, not valid).
template <class Plan>
struct MpcState : MotionState {
  explicit MpcState(int horizon_steps) {
    plan.Resize(horizon_steps);
    scratch.Resize(horizon_steps);
  }
  Plan plan;     ///< the plan in use
  Plan scratch;  ///< the shifted warm start / linearisation trajectory
  MpcDiagnostics diagnostics;
};

/// Mean curvature of `path` between the stations s0 ≤ s1 [1/m] (heading change over arc length;
/// the curvature at s0 below 0.5 m).
double MeanCurvature(const Path& path, double s0, double s1) noexcept;

/// The wrapper both MPCs derive from: it holds the path, the planner's limits and the corridor,
/// and runs the solve / hold-previous-plan / fallback rule around each controller's own solve.
class MpcController : public MotionController {
 public:
  const GgTable& limits() const noexcept { return limits_; }
  const Path& path() const noexcept { return *path_; }
  /// Lateral room [m] left (> 0) and right (> 0) of the path at s (untightened).
  double CorridorLeft(double s) const noexcept;
  double CorridorRight(double s) const noexcept;

 protected:
  /// Stores the inputs; the derived constructor checks them with ValidateInputs (and its own).
  MpcController(GgTable limits, Corridor corridor, std::shared_ptr<const Path> path);
  /// ValidateMpcInputs of the stored inputs.
  Problems ValidateInputs() const { return ValidateMpcInputs(path_.get(), limits_, corridor_); }

  /// Bounds lo ≤ n ≤ up [m] of the lateral offset at s keeping `margin` off the corridor's edges
  /// (both at the middle where the corridor is narrower than 2·margin).
  void CorridorBounds(double s, double margin, double* lo, double* up) const noexcept;

  /// Matches the vehicle on the path (MatchOnPath), samples the reference there into *ref and sets
  /// out->v_target.
  PathProjection Locate(const MotionInput& in, double window, MotionState* st, MotionOutput* out,
                        PathPoint* ref) const noexcept;

  /// One timed solver call on `nlp`, counted in d (solve time, solves, iterations, last status).
  /// Returns whether the result is usable.
  static bool TimedSolve(NlpSolver* solver, SparseNlp* nlp, MpcDiagnostics* d);

  /// Runs `solve` (bool(), replaces the plan when it returns true). False or a throw counts as a
  /// failure and keeps the previous plan, shifted in time by construction, until `hold` [s] after
  /// its node 0; then the plan is dropped.
  template <class Plan, class Solve>
  static void SolveOrHold(double t, double hold, Plan* plan, MpcDiagnostics* d,
                          Solve&& solve) noexcept {
    bool ok = false;
    try {
      ok = solve();
    } catch (...) {
      ok = false;
    }
    if (ok) return;
    ++d->failures;
    if (plan->valid && t - plan->t0 >= hold) plan->valid = false;
  }

  /// Whether the plan drives this step; otherwise the fallback law does and the step is counted.
  template <class Plan>
  static bool FollowPlan(const Plan& plan, MpcDiagnostics* d) noexcept {
    if (!plan.valid) ++d->fallback_steps;
    return plan.valid;
  }

 private:
  GgTable limits_;
  Corridor corridor_;
  std::shared_ptr<const Path> path_;
};

}  // namespace scw::controller::motion
