// Derivative-free tuning loop over the unit cube with NLopt 2.7.1 (ecosystem spec §2).
//
// * Algorithms by name: crs2 (GN_CRS2_LM), isres, esch, direct_l, mlsl (G_MLSL_LDS with Subplex
//   as its local search), sbplx (LN_SBPLX), neldermead, bobyqa, cobyla, auglag (AUGLAG around
//   Subplex: minimises the cost subject to Evaluation::constraint <= 0, the best is the best
//   point that meets it; the log gains a `constraint` column), and lhs (a batched Latin-hypercube
//   design, below); "A+B" runs A on a share of the budget (global phase) and
//   polishes with B from the best point. Default: "sbplx" (Subplex from the start point: on the
//   real problem it ends where the best global methods end, and draws no random numbers;
//   docs/tuning-benchmark.md).
// * The objective never throws into NLopt and never returns NaN/inf: exceptions and non-finite
//   values become a finite penalty and are logged with their reason.
// * Evaluation 0 is always the start point u0 itself (phase "start"), whatever the algorithm, so
//   the log's first row is the starting (base) set and the best is never worse than it.
// * A point the optimiser asks for again (Subplex re-evaluates its start point, CRS2 its x0) reuses
//   the logged cost: the objective must be deterministic; the point is neither re-evaluated nor
//   logged again.
// * Our own best-so-far record (NLopt's COBYLA may return its last point, not its best).
// * Seeded: nlopt::srand(seed) right before every optimize() (its RNG is thread-local).
//   Same inputs + seed + evaluation budget → identical evaluation sequence and result.
// * Budget by evaluations (deterministic) and by wall time (a guard; stops are then
//   speed-dependent).
// * Every evaluation is appended to a CSV log as it happens (flushed per row, shortest
//   round-trip numbers), so memory stays flat and an interrupted run keeps its log.
// * Stop flag (Ctrl-C): the current evaluation finishes, NLopt is stopped, the best is kept.
// * Resume: the evaluations of an earlier log are replayed in order without being recomputed —
//   the optimiser is deterministic, so it asks for exactly the logged points — and the run goes on
//   from there; the result equals that of an uninterrupted run. The log is append-only: resuming
//   into the log itself appends the new rows after the logged ones and never rewrites a byte of
//   them (resuming into another file copies the logged rows first). A run with verify_resume
//   writes nothing: it replays the whole resume log and stops where it ends, so a caller can find
//   a log that diverges (ResumeMismatch) before anything is written.
// * Batches (algorithm "lhs" or "lhs+B", TunerOptions::batch = K): a Latin-hypercube design of
//   the global share of the budget, evaluated K points per objective call, then K local searches
//   B (one nlopt::opt and thread each) from the K best points so far, in lockstep: every round
//   each running search asks for one point and the round is evaluated as one batch, in search
//   order (search i seeds NLopt's thread-local generator with seed + 1 + i in its own thread).
//   The log order and the result depend on (inputs, seed, K) only, never on the threads of the
//   objective. The remaining budget is shared: a search that converges leaves its rounds to
//   the others; when fewer evaluations remain than searches ask, the lower search indices get
//   them. A batch is checked against the stop flag and the time limit before it is evaluated, so
//   it is logged whole or not at all; only the budget can cut the last one, the same way on replay.
//   The design does not depend on K ("lhs" alone gives the same log for any batch).
//   The NLopt algorithms ask for one point at a time: batch > 1 needs "lhs" or "lhs+B".
#pragma once

#include <atomic>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace scw::tuning {

/// One evaluation's outcome as the objective reports it.
struct Evaluation {
  double cost = 0.0;
  std::string status = "ok";         ///< "ok" or a short failure reason
  std::vector<std::string> columns;  ///< extra log fields (must match the extra header)
  /// "auglag" only: the inequality constraint g(u) <= 0 (the clean-lap budget's violation).
  double constraint = 0.0;
};

using Objective = std::function<Evaluation(const std::vector<double>& u)>;
/// Several points at once (one result per point, in order); used by the batched algorithms.
using BatchObjective =
    std::function<std::vector<Evaluation>(const std::vector<std::vector<double>>& points)>;

struct Progress {
  int evals = 0;
  int max_evals = 0;
  double best_cost = 0.0;
  double elapsed_s = 0.0;
  std::string phase;
};

struct TunerOptions {
  std::string algorithm = "sbplx";
  int max_evals = 300;
  double max_time_s = 0.0;  ///< 0: no wall-time limit
  unsigned long long seed = 1;
  double initial_step = 0.15;  ///< in unit-cube coordinates
  double global_share = 0.6;   ///< budget share of the first phase of "A+B"
  int population = 0;          ///< CRS2/ISRES population (0: 5·(n+1))
  int batch = 1;               ///< candidates evaluated at once ("lhs" algorithms; >= 1)
  double xtol_abs = 1e-4;
  double failure_cost = 1e6;  ///< cost of an evaluation that threw or returned NaN/inf
  std::string log_path;       ///< CSV evaluation log ("" = none)
  std::vector<std::string> log_extra_header;
  std::vector<std::string> dimension_names;  ///< header names of u (default u0, u1, …)
  std::string resume_path;                   ///< earlier log to replay first ("" = none)
  /// Only replay the resume log (no objective call, no log written) and stop where it ends: Tune()
  /// then returns with stop reason "verified", or throws ResumeMismatch.
  bool verify_resume = false;
  const std::atomic<bool>* stop = nullptr;
  std::function<void(const Progress&)> on_progress;
  /// Called for every evaluation as it is recorded, replayed ones included, in log order: its
  /// number, point and outcome. Must not throw.
  std::function<void(int index, const std::vector<double>& u, const Evaluation& ev)> on_record;
};

/// Relative size of an improvement of the best cost that counts for the convergence verdict.
inline constexpr double kSignificantImprovement = 0.005;

struct TuneResult {
  std::vector<double> best_u;
  double best_cost = std::numeric_limits<double>::infinity();
  int best_eval = -1;
  /// The last evaluation that lowered the best cost by more than kSignificantImprovement of it
  /// (evaluation 0 counts: it sets the first best).
  int last_improvement_eval = -1;
  double start_cost = std::numeric_limits<double>::quiet_NaN();  ///< cost of u0 (evaluation 0)
  int evals = 0;
  int replayed = 0;         ///< evaluations taken from the resume log
  std::string stop_reason;  ///< "max_evals", "max_time", "converged", "interrupted", …
};

/// The resume log does not belong to this run: another header, a point that differs from the one
/// this run asks for, more rows than this run makes, or a last row without its line break.
class ResumeMismatch : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Minimises f over [0,1]^n starting from u0. Throws std::invalid_argument for bad options
/// (unknown algorithm, n = 0), ResumeMismatch for a resume log that does not match this problem
/// and std::runtime_error if the log cannot be written.
TuneResult Tune(const std::vector<double>& u0, const Objective& f, const TunerOptions& options);
/// The same with a batch objective for the batched algorithms (empty: `f` point by point).
TuneResult Tune(const std::vector<double>& u0, const Objective& f, const BatchObjective& batch_f,
                const TunerOptions& options);

/// Names accepted in TunerOptions::algorithm.
std::vector<std::string> TunerAlgorithms();
/// Throws std::invalid_argument (naming the known algorithms) unless `spec` is an algorithm name
/// or A+B of two ("lhs" only as A); Tune() applies the same rule.
void CheckTunerAlgorithm(const std::string& spec);
/// Throws std::invalid_argument unless `batch` >= 1 and, for batch > 1, `spec` is batched ("lhs"
/// or "lhs+B"); Tune() applies the same rule.
void CheckTunerBatch(const std::string& spec, int batch);

/// `points` points of a Latin hypercube in [0,1)^dims from `seed`: in every dimension each of the
/// `points` equal strata holds exactly one point. Drawn with its own generator (SplitMix64), so
/// the same on every platform and standard library.
std::vector<std::vector<double>> LatinHypercube(int points, int dims, unsigned long long seed);

}  // namespace scw::tuning
