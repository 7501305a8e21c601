// Knife edges of a set that goes on the car (phase "neighbourhood" of scw tune): the exported set
// moved a little, on the training and the held-out scenarios; a run the set completes that aborts
// after the small move is a knife edge.
//
// The neighbours:
//   each changed key alone   u_d ± h in the search space's own coordinate (h = 10 % of the key's
//                            range: of its value for a linear key, of its logarithm for a log
//                            one), clamped to the range and decoded as the tuner decodes (pinned
//                            keys stay, relative keys follow); a move that decodes to the set
//                            itself or breaks a schema rule is not a neighbour
//   the plant's unknowns     at the bounds the built-in robust set draws them from
//                            (params/scenarios/robust_set.yaml; docs/plant-calibration.md):
//                              plant.brake_dead_time   0.040 / 0.116 s (at the car's 150 ms total)
//                              plant.steering_delay    0 / 0.060 s
//                              grip.mu                 × 0.9 / × 1.1 (the car only: the scenario is
//                                                      planned with the grip it had)
//                              plant.rear_tire_falloff 0.5 / 1.5
//                              plant.yaw_inertia_scale 0.8 / 1.2
//                            each as a scenario override on every scenario; grip is left out (said
//                            so) for a scenario that plans with reduced grip, where the override
//                            would change its plan too.
// Deterministic for any thread count: the key neighbours run as one batch per group, each plant
// neighbour as one batch per group.
#pragma once

#include <string>
#include <vector>

#include "controller/planning/reference_cache.h"
#include "params/schema/stability_params.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/space.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {

/// Default key step h (fraction of the range in the search coordinate).
inline constexpr double kNeighbourhoodStep = 0.10;

struct Neighbour {
  bool plant = false;  ///< a plant unknown (else a key of the set)
  std::string key;  ///< "countersteer_system.steering_factor", "plant.brake_dead_time", "grip.mu"
  std::string change;  ///< "-10 % of range", "0.116 s", "x 0.9"
  std::string value;   ///< the key's value there ("0.45"; for grip "x 0.9")
  int dim = -1;        ///< key neighbours: the space dimension
  double u = 0.0;      ///< key neighbours: its coordinate
  /// Plant neighbours: the scenario override ("plant.steering_delay=0.06"); empty for grip, whose
  /// override is per scenario (its mu × the factor).
  std::vector<std::string> overrides;
};

struct KnifeEdge {
  int neighbour = 0;  ///< index into NeighbourhoodResult::neighbours
  std::string group;  ///< "training" or "held-out"
  std::string scenario;
  RunMetrics centre, moved;  ///< the set's run and the run at the neighbour
  /// Plant neighbours: the base set's run at the same neighbour (an abort there too means the
  /// plant change, not the tuned set, loses the car); key neighbours: not run.
  bool base_run = false;
  RunMetrics base_moved;
  bool base_also_aborts() const { return base_run && base_moved.aborted(); }
};

struct NeighbourhoodResult {
  double step = kNeighbourhoodStep;
  std::vector<Neighbour> neighbours;
  std::vector<KnifeEdge> edges;
  int runs = 0;                    ///< runs made
  std::vector<std::string> notes;  ///< neighbours left out and why
  /// Per neighbour: runs the set completes that it also completes (for the table's "holds" count).
  std::vector<int> held;
  /// The distinct changed keys and plant unknowns with a knife edge, in neighbour order.
  std::vector<std::string> EdgeKeys() const;
};

/// The input: the exported point of the space with `pinned`, and the evaluators and evaluations
/// of the set on the training and held-out scenarios (held-out may be empty: `held_out` null).
struct NeighbourhoodInput {
  const ScenarioSet* scenarios = nullptr;
  const ParameterSpace* space = nullptr;  ///< the space (without the pins)
  std::vector<int> pinned;
  const params::StabilityParams* base = nullptr;
  /// The set the plant neighbours are compared with (the base set of the tune; null: none).
  const params::StabilityParams* reference = nullptr;
  std::vector<double> u;
  const BatchEvaluator* training = nullptr;
  const BatchEvaluator* held_out = nullptr;
  const SetEvaluation* training_centre = nullptr;
  const SetEvaluation* held_out_centre = nullptr;
  double step = kNeighbourhoodStep;
  bool plant = true;  ///< also the plant's unknowns
  int threads = 0;
  controller::planning::ReferenceCache* cache = nullptr;
  std::shared_ptr<RunMemo> memo;  ///< the study's runs (evaluator.h), null: none
};

/// The neighbours of the input's set (no run).
std::vector<Neighbour> PlanNeighbourhood(const NeighbourhoodInput& in,
                                         std::vector<std::string>* notes);

/// Runs every neighbour on both groups; `progress` counts the runs.
NeighbourhoodResult CheckNeighbourhood(const NeighbourhoodInput& in,
                                       const BatchProgress& progress = {});

/// Markdown section "Knife edges" (heading level `level`): what was moved, a table of every knife
/// edge (what moved, scenario, the set's run, the run after the move), or the statement that none
/// was found.
std::string NeighbourhoodMarkdown(const NeighbourhoodResult& r, int level = 2);

/// Knife edges where the reference set completes the same plant neighbour (or a key neighbour):
/// the tuned set's own.
int OwnEdges(const NeighbourhoodResult& r);

/// The console's warning lines ("" when there is no knife edge).
std::string NeighbourhoodWarning(const NeighbourhoodResult& r);

}  // namespace scw::tuning
