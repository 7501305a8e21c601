// Robust in the small (scw tune --robust): the knife edges the neighbourhood check finds on the
// training scenarios join the objective, and the search continues from the exported point.
//
// One round (tune_study.h runs at most kRobustRounds, while a training knife edge remains):
//   active edges A = the set's own training knife edges found so far (a plant neighbour where the
//            base set aborts as well is the plant's, and stays out): (neighbour, scenario), a
//            neighbour being a key moved by ±h in the direction it was found in, or a plant unknown
//            at a bound (neighbourhood.h)
//   search   Subplex from the exported point over the dimensions that are not pinned, at the
//            vehicle's own step, `evaluations` evaluations (its own log when `log` is given), on
//                merit_A(u) = F(u) + Σ_{(n,s) ∈ A} J_s(u moved to n)
//            F the tune's merit on the training scenarios (objective.h), J_s the scenario's cost
//            (an abort costs 200-400: the search moves away from the edge). A point outside the
//            clean-lap budget also pays the start point's Σ_A, so it never ranks before a point
//            within the budget.
//   result   the best point (the start point if nothing beats it) and its merit_A.
// Deterministic: the same inputs give the same search, for any thread count.
#pragma once

#include <string>
#include <vector>

#include "controller/planning/reference_cache.h"
#include "params/schema/stability_params.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/neighbourhood.h"
#include "tuning/optim/objective.h"
#include "tuning/optim/space.h"
#include "tuning/optim/tuner.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {

/// One active knife edge: what moves and on which training scenario.
struct ActiveEdge {
  Neighbour neighbour;
  double sign = 0.0;         ///< key neighbours: -1 or +1 (the direction of the move)
  std::size_t scenario = 0;  ///< index into the training scenarios
};

/// The active edges of a check: its training knife edges that are the set's own (not a plant
/// neighbour where the base set aborts too; duplicates dropped), appended to `active`.
void AddActiveEdges(const NeighbourhoodResult& check, const BatchEvaluator& training,
                    const std::vector<double>& u, std::vector<ActiveEdge>* active);

struct RobustRoundInput {
  const ScenarioSet* scenarios = nullptr;
  const ParameterSpace* space = nullptr;  ///< the space without pins
  std::vector<int> pinned;                ///< kept at the base value (frozen and reverted)
  const params::StabilityParams* base = nullptr;
  std::vector<double> start;  ///< the exported point
  const BatchEvaluator* training = nullptr;
  const TuneObjective* objective = nullptr;  ///< at the vehicle's step
  std::vector<ActiveEdge> active;
  double step = kNeighbourhoodStep;  ///< h
  int evaluations = 120;
  unsigned long long seed = 1;
  std::string log;  ///< evaluation log of the round ("" = none)
  int threads = 0;
  controller::planning::ReferenceCache* cache = nullptr;
  std::shared_ptr<RunMemo> memo;  ///< the study's runs (evaluator.h), null: none
  const std::atomic<bool>* stop = nullptr;
  std::function<void(const Progress&)> on_progress;
};

struct RobustRoundResult {
  std::vector<double> best;                    ///< the round's best point (full space coordinates)
  double start_merit = 0.0, best_merit = 0.0;  ///< merit_A
  TuneResult search;
};

RobustRoundResult RunRobustRound(const RobustRoundInput& in);

}  // namespace scw::tuning
