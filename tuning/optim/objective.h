// The tune's objectives, after the paper's own tuning goal: "minimize performance degradation
// from unnecessary interventions while ensuring sufficient stability in critical situations".
//
//   performance  on the clean scenarios (kind: clean, what a set costs when nothing goes wrong):
//                per scenario c the lap-time loss against the base set
//                  ΔT_c = T_c − T_c,base  [s per lap]  (T = mean completed lap, cost.h)
//                and the activations n_{c,k} of each subsystem k ∈ {ESC, CS, ABS, TC}
//   stability    on every other scenario (critical, maneuver: what it saves when something goes
//                wrong): S = Σ weight_s · J_s (cost.h: aborts and the distance lost, sideslip above
//                the allowed angle, the largest sideslip and lateral error, the event lap's time)
//
// The clean-lap budget (ObjectiveKind::kConstrained): for every clean scenario c the base set
// completes,
//   the set completes it;   ΔT_c ≤ b (CleanLapBudget::lap_s);   n_{c,k} ≤ n_{c,k,base} for every k
//   (CleanLapBudget::interventions).
// A clean scenario the base set does not complete constrains nothing (there is no lap to keep).
// The violation, in seconds:
//   V = Σ_c [ max(0, ΔT_c − b) + (aborted ? lap_time_cap : 0) + 0.1 s · Σ_k max(0, n_{c,k} −
//   n_{c,k,base}) ]
//
// The merit, what the optimiser minimises:
//   kConstrained   F = S                       where V = 0
//                  F = S + S_base + 100 · V    where V > 0
//     The base set meets its own budget (V = 0, F = S_base) and S ≥ 0, so every set that breaks the
//     budget ranks behind the base and the best point of a search is always within the budget (an
//     exact penalty: the constrained optimum is the merit's optimum); the slope of 100 per second
//     of excess leads a search that starts outside back in.
//   kSum           F = J = Σ_s weight_s · J_s over every scenario: the weighted sum of the earlier
//                  tunes, where survival in a critical scenario is bought with lap time in every
//                  clean one (kept for comparison and for logs written with it).
//
// Everything here is a pure function of evaluated sets: deterministic, no run.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "params/schema/cost_params.h"
#include "tuning/optim/evaluator.h"

namespace scw::tuning {

enum class ObjectiveKind { kConstrained, kSum };
/// "constrained", "sum".
const char* ObjectiveKindName(ObjectiveKind k);
/// Throws std::invalid_argument naming the choices for any other name.
ObjectiveKind ObjectiveKindFromName(const std::string& name);

/// The default clean-lap budget [s per lap] of scw tune (--lap-budget).
inline constexpr double kDefaultLapBudget = 0.05;
/// Violation charged per extra activation on a clean lap [s].
inline constexpr double kActivationViolation = 0.1;
/// Merit slope per second of violation.
inline constexpr double kViolationSlope = 100.0;

struct CleanLapBudget {
  /// b [s per lap]: the most a clean lap may lose against the base set (+inf: no lap constraint).
  double lap_s = kDefaultLapBudget;
  /// No clean scenario may see more activations of a subsystem than the base set has there.
  bool interventions = true;
};

/// "ESC", "CS", "ABS", "TC" (k = 0..3), the order of Activations().
inline constexpr std::array<const char*, 4> kSubsystemNames = {"ESC", "CS", "ABS", "TC"};
/// A run's activations per subsystem (RunMetrics esc_count, cs_count, abs_count, tc_count).
std::array<int, 4> Activations(const RunMetrics& m);

/// One clean scenario under the budget.
struct CleanLapCheck {
  std::string scenario;
  bool base_completed = false, completed = false;
  double base_lap = std::numeric_limits<double>::quiet_NaN();  ///< [s] mean lap, NaN: none
  double lap = std::numeric_limits<double>::quiet_NaN();
  /// ΔT [s per lap] where both completed, else NaN.
  double lap_loss = std::numeric_limits<double>::quiet_NaN();
  std::array<int, 4> activations{}, base_activations{};
  double violation = 0.0;  ///< this scenario's share of V [s]
  /// "" within the budget, else what breaks it ("+0.31 s a lap over 0.05; TC 7 > 0").
  std::string breach;
};

/// A set's objectives on an evaluator's scenarios, against the base set's evaluation.
struct ObjectiveValue {
  double stability = 0.0;  ///< S
  double total = 0.0;      ///< J (SetEvaluation::total)
  /// max ΔT_c over the clean scenarios both sets complete [s per lap], negative when every clean
  /// lap is faster (0 without any); +inf when the set aborts a clean scenario the base completes.
  double lap_loss = 0.0;
  int extra_activations = 0;  ///< Σ_{c,k} max(0, n − n_base)
  double violation = 0.0;     ///< V [s]
  double merit = 0.0;         ///< F
  std::vector<CleanLapCheck> clean;
  bool within_budget() const { return violation == 0.0; }
};

/// The objective of one tune: its kind, budget and the base set's evaluation on the same scenarios.
class TuneObjective {
 public:
  /// `kinds` and `weights` per scenario (ResolvedScenario spec.kind, BatchEvaluator::weights());
  /// `base` the base set's evaluation on them.
  TuneObjective(ObjectiveKind kind, CleanLapBudget budget, std::vector<std::string> names,
                std::vector<std::string> kinds, std::vector<double> weights,
                params::CostWeights cost, SetEvaluation base);
  /// The same for the scenarios of an evaluator.
  static TuneObjective For(const BatchEvaluator& ev, ObjectiveKind kind, CleanLapBudget budget,
                           SetEvaluation base);

  /// The objectives of a set evaluated on the same scenarios (an invalid set: merit = its total).
  ObjectiveValue Of(const SetEvaluation& e) const;
  /// The same objective with another budget (fronts).
  TuneObjective WithBudget(CleanLapBudget budget) const;

  ObjectiveKind kind() const { return kind_; }
  const CleanLapBudget& budget() const { return budget_; }
  const SetEvaluation& base() const { return base_; }
  const ObjectiveValue& base_value() const { return base_value_; }
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<std::string>& kinds() const { return kinds_; }
  bool has_clean() const;
  /// One line: "stability cost on the critical scenarios, subject to: no clean lap slower than the
  /// base by more than 0.05 s, no more activations than the base on a clean lap".
  std::string Describe() const;

 private:
  ObjectiveKind kind_;
  CleanLapBudget budget_;
  std::vector<std::string> names_, kinds_;
  std::vector<double> weights_;
  params::CostWeights cost_;
  SetEvaluation base_;
  ObjectiveValue base_value_;
};

/// "0.05 s" / "none" for a budget's lap part.
std::string LapBudgetText(double lap_s);

/// Markdown: the clean laps against the base (scenario, base lap, lap, ΔT, activations base ->
/// set, within the budget?), under a heading of level `level`.
std::string CleanLapMarkdown(const ObjectiveValue& v, const CleanLapBudget& budget,
                             const std::string& set_label, int level = 3);

}  // namespace scw::tuning
