// The function a tune's optimiser calls: points of the unit cube -> evaluations (cost, status,
// log columns) of the decoded sets on the training scenarios.
//
//   cost      the merit of the tune's objective (objective.h): kConstrained the stability cost
//             within the clean-lap budget, kSum the weighted sum of every scenario's cost; a
//             decoded set that breaks a schema rule is not run and costs invalid_cost(),
//               (P_abort + w_progress + T_lap_cap) · max(1, #scenarios)  [+ the base's merit for
//               kConstrained],
//             more than any set that runs
//   columns   after the point: the transform arguments (x:KEY), then per training scenario its
//             cost, status and mean lap time, then (kConstrained) the stability cost, the largest
//             clean-lap loss and the budget's violation
//
// Decode and Complete split one call in two, so that a caller can run the sets of several
// objectives as one batch (a front's points in lockstep); operator() is both in one.
// Immutable; the referenced space, base, evaluator and objective must outlive it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "params/schema/stability_params.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/objective.h"
#include "tuning/optim/space.h"
#include "tuning/optim/tuner.h"

namespace scw::tuning {

class TrainingObjective {
 public:
  /// `split`: the cost is the stability alone and the budget's violation goes into
  /// Evaluation::constraint (the constrained algorithm auglag); otherwise the cost is the merit.
  TrainingObjective(const ParameterSpace& space, const params::StabilityParams& base,
                    const BatchEvaluator& training, const TuneObjective& objective,
                    bool split = false);

  double invalid_cost() const { return invalid_cost_; }
  bool constrained() const { return objective_.kind() == ObjectiveKind::kConstrained; }
  std::vector<std::string> LogHeader() const;

  /// The points decoded: the sets to run (valid ones, in order) and the evaluations so far.
  struct Pending {
    std::vector<Evaluation> evaluations;  ///< one per point; invalid ones complete
    std::vector<params::StabilityParams> sets;
    std::vector<std::size_t> at;  ///< the point of each set
  };
  Pending Decode(const std::vector<std::vector<double>>& points) const;
  /// The evaluations, given the sets' results on the training scenarios (one per pending set).
  std::vector<Evaluation> Complete(Pending pending,
                                   const std::vector<SetEvaluation>& results) const;
  /// Several points at once: the valid sets run as one batch of (set × scenario) jobs.
  std::vector<Evaluation> operator()(const std::vector<std::vector<double>>& points) const;

 private:
  const ParameterSpace& space_;
  const params::StabilityParams& base_;
  const BatchEvaluator& training_;
  const TuneObjective& objective_;
  bool split_;
  double invalid_cost_;
};

/// The best evaluations of a search by cost (ties: the earlier one), kept as they are recorded.
struct TopPoint {
  int index = 0;
  double cost = 0.0;
  std::vector<double> u;  ///< full space coordinates
};
class TopPoints {
 public:
  explicit TopPoints(std::size_t keep) : keep_(keep) {}
  void Add(int index, const std::vector<double>& u, double cost);
  const std::vector<TopPoint>& entries() const { return entries_; }

 private:
  std::size_t keep_;
  std::vector<TopPoint> entries_;
};

}  // namespace scw::tuning
