// scw tune --front N: the trade-off between what a set costs on clean laps and what it saves in
// critical situations, as N tuned sets an engineer picks from.
//
// Point k = 0..N-1 is a constrained tune (objective.h) at its own clean-lap budget:
//   k = 0        b = 0 and no activation the base set does not have: the base set's lap time
//   0 < k < N-1  b_k = L · (k / (N-1))², activations free (they cost lap time, which b prices)
//   k = N-1      no budget: whatever it takes to survive (the stability cost alone)
// L = FrontSpan(the largest clean-lap loss of point N-1's best set after its search): the budgets
// span the range the trade-off has, densest near "no loss", where an engineer decides. L is at
// least kFrontMinSpan: an unbudgeted search that bought nothing with lap time (its best set as
// fast as the base) does not collapse the inner points onto "no loss"; they still search the
// budgets an engineer weighs (0.025, 0.1, 0.225 s a lap for N = 5).
//
// The searches (each Subplex; FrontPointEvals: the ends `max_evals` evaluations from the study's
// options, the inner points twice that):
//   stage 1   the two ends, from the base point, in lockstep: each round every running search
//             asks for one point and the round runs as ONE batch of (set × scenario) jobs over
//             the execution layer (threads or MPI ranks), in point order
//   stage 2   the inner points in lockstep, each warm-started from the best set among every
//             evaluation so far that lies in its own band (a clean-lap loss above the tighter
//             neighbour's budget, within its own), else the best within its budget: two points
//             whose budgets both bind nowhere would otherwise run the same search
//   result    each point's set is the best within its budget over ALL the front's evaluations, so
//             a looser budget never ranks a point worse (the front is monotone); a front searched
//             at a coarser plant step (--search-plant-step) runs the point's eight best sets
//             within its budget at the vehicle's step and exports the best there, as a single
//             tune's select phase does
//   export    point by point, tightest first; the export phases (the joint revert, and with
//             --robust the robust rounds, whose objective holds each point's own knife edges) can
//             leave a point's set worse than its tighter neighbour's exported one. A point whose
//             exported set the tighter neighbour's dominates (TighterSetDominates) takes that set
//             instead, exported again under its own budget without sensitivity and robust rounds,
//             so the exported front stays monotone too.
// Deterministic: the rounds, the batches and the archive order depend on the inputs and the seed
// only, never on the threads or ranks.
//
// Each point then goes through the tune's export phases (TuneStudy::Finish: sensitivity, joint
// revert, comparison, knife edges, the params files) in its folder point_<k>/.
//
// Quality: the 2-D hypervolume of the training front (clean-lap loss [s/lap], stability cost),
// both minimised, against the reference point (1.1 · L_max, S_base): the area the front
// dominates. Comparing it with that of a front from a much larger budget (same reference point)
// measures how close the front is to converged (FrontQuality; experiments/front_quality.py).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tuning/optim/tune_study.h"

namespace scw::tuning {

struct FrontPoint {
  int index = 0;
  CleanLapBudget budget;
  std::string label;   ///< "no loss", "+0.025 s", "no budget"
  std::string folder;  ///< point_<k> (relative to the front's folder)
  TuneReport report;   ///< the point's tune, exported
  /// The tighter point whose exported set this point took (its own export ended on a set that
  /// one dominates; TighterSetDominates), or -1.
  int adopted_from = -1;
};

/// Watches a front. Empty defaults; called from the thread that runs the front.
class FrontObserver {
 public:
  virtual ~FrontObserver() = default;
  /// A search stage begins (1: the ends, 2: the inner points) with `points` searches.
  virtual void OnStage(int /*stage*/, int /*points*/, int /*max_evals*/) {}
  /// After every round of a stage: evaluations so far in the stage (all its searches).
  virtual void OnRound(int /*evaluations*/, int /*total*/) {}
  /// A point's export phases begin.
  virtual void OnPointBegin(int /*k*/, int /*n*/) {}
  /// A point is exported: its report's outputs are complete (the caller writes them).
  virtual void OnPoint(const FrontPoint& /*point*/) {}
};

/// The smallest span L of the inner budgets [s/lap].
inline constexpr double kFrontMinSpan = 0.4;

/// L from the unbudgeted end's clean-lap loss [s/lap] (see the header comment).
double FrontSpan(double unbudgeted_loss);

struct FrontResult {
  std::vector<FrontPoint> points;
  double loss_span = 0.0;   ///< L [s/lap]
  double loss_found = 0.0;  ///< the unbudgeted end's clean-lap loss after its search [s/lap]
  int evaluations = 0;      ///< of all searches
  /// The hypervolume of the training front and its reference point (loss [s/lap], stability).
  double hypervolume = 0.0;
  std::pair<double, double> reference{0.0, 0.0};
  /// Runs made by the front's evaluators, and runs their shared memo answered instead.
  long runs_made = 0, runs_reused = 0;
  std::string csv;       ///< front.csv
  std::string markdown;  ///< front.md (without the figure)
};

/// The options of point k's study: the front's with the point's budget, the constrained objective,
/// no resume, its folder `folder` below the front's run folder (and its log there).
TuneStudyOptions FrontPointOptions(const TuneStudyOptions& o, const CleanLapBudget& b,
                                   const std::string& folder);

/// The evaluations of point k's search: `max_evals` for the ends, which start from the base point
/// (on the built-in set the unbudgeted search needs about 210 to find the set that trades lap time
/// for stability), twice that for the inner points, which start from the best set for their budget
/// found so far and hold the constrained optima the front is judged by (in a 4x reference front
/// the search of the budget 0.025 s reached its best region after 334 evaluations;
/// experiments/front_budget_criterion.md).
int FrontPointEvals(int k, int n, int max_evals);
/// The clean-lap budget of point k of n, given L (see the header comment).
CleanLapBudget FrontBudget(int k, int n, double loss_span);

/// Whether the tighter neighbour's exported set (`tighter`) dominates a point's own (`looser`,
/// exported under `looser_budget`): `tighter`'s set is another set, within that budget on the
/// training clean laps, its training stability cost no higher and its own knife edges no more (when
/// both were checked), and one of the two strictly lower.
bool TighterSetDominates(const TuneReport& tighter, const TuneReport& looser,
                         const CleanLapBudget& looser_budget);

/// Runs the front of `study` (its options: the search settings per point; the budget options are
/// replaced per point; its evaluation_log names the front's folder's log, point k writes
/// point_<k>/evaluations.csv beside it; resume is refused). `n` >= 2. Throws what the phases
/// throw, std::invalid_argument for n < 2 or a resume.
FrontResult RunFront(const TuneStudy& study, int n, TuneObserver& observer,
                     FrontObserver& front_observer);

/// The 2-D hypervolume (both coordinates minimised) dominated by `points` within the box up to
/// `reference`: points beyond the reference in either coordinate add nothing.
double Hypervolume2D(std::vector<std::pair<double, double>> points,
                     std::pair<double, double> reference);

}  // namespace scw::tuning
