// Reverting, jointly, what a search changed but no training run needs (phase "revert" of scw
// tune, after the sensitivity).
//
// A one-parameter-at-a-time sensitivity cannot judge parameters that only act together: four ESC
// activation thresholds raised together keep ESC off where it made a car lock a wheel, yet each
// moved alone changes no run (one raised threshold is enough to keep ESC off), so reverting each
// "unexercised" one brings the abort back. Here every revert is judged on the whole set:
//
//   current = the point u with the dimensions `pinned` at the base value (its evaluation given)
//   for each candidate dimension d, in the order given:
//     trial = current with d also pinned; skipped when that decodes to the current set (the
//             search left d at the base value) or breaks a schema rule (said so)
//     evaluate trial on every scenario of the evaluator, as a whole
//     keep the revert when
//       - no run the current set completes aborts with the trial,
//       - the trial is within the objective's clean-lap budget wherever the current set is, and
//       - its merit rises by at most `tolerance` (the clean-lap budget, in the merit's seconds);
//     else undo it, with the reason ("aborts power_on_c1", "+0.31 s merit, over 0.05 s",
//     "breaks the clean-lap budget: clean_gg1.1 +0.12 s a lap over 0.05 s").
//
// The last kept trial's evaluation is the exported set's: a reverted file is always evaluated as a
// whole before it is written. One evaluation per candidate that changes the set; deterministic.
#pragma once

#include <string>
#include <vector>

#include "params/schema/stability_params.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/objective.h"
#include "tuning/optim/space.h"

namespace scw::tuning {

struct RevertDecision {
  int dim = -1;
  std::string label;      ///< SpaceEntry::Label()
  bool reverted = false;  ///< kept at the base value
  /// Reverted: why it was a candidate (the sensitivity's reason); kept: why the revert was undone.
  std::string reason;
  double merit_change = 0.0;  ///< merit(trial) − merit(current) (0 where not evaluated)
};

struct RevertResult {
  std::vector<int> pinned;                ///< the input's pinned dimensions plus the reverted ones
  std::vector<RevertDecision> decisions;  ///< one per candidate that changed the set
  SetEvaluation evaluation;               ///< the final set's (as exported)
  ObjectiveValue value;                   ///< its objectives
  int evaluations = 0;                    ///< trials evaluated
};

/// `candidates`: (dimension, the reason it is one) in the order to try. `current` is the
/// evaluation of u with `pinned` on `ev`. `progress` counts the trials (done, candidates).
RevertResult RevertJointly(const BatchEvaluator& ev, const ParameterSpace& space,
                           const params::StabilityParams& base, const std::vector<double>& u,
                           std::vector<int> pinned,
                           const std::vector<std::pair<int, std::string>>& candidates,
                           const TuneObjective& objective, SetEvaluation current, double tolerance,
                           const BatchProgress& progress = {});

/// Markdown list items ("  - label (reason)") of the reverted and of the kept candidates.
std::vector<std::string> RevertedItems(const RevertResult& r);
std::vector<std::string> KeptItems(const RevertResult& r);

}  // namespace scw::tuning
