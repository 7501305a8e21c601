// Which parameters a scenario set can see: a one-at-a-time sensitivity of the cost around a point
// of the tuning space (`scw tune` after the optimisation, around the tuned point; `scw tune
// --check-set` around the base point).
//
// Perturbations. For every dimension i of the ParameterSpace, the transform argument x_i (the
// space's natural unit: the value for direct entries, the gap for offsets, the fraction for
// ratios, the factor for scale_array) is moved four ways, in increasing order of x:
//   -10 %    x − 0.1·|x|
//   -1 step  x − δ       δ = one schema resolution step of the parameter's value, in x units:
//   +1 step  x + δ           direct, offset: r; ratio: r / |reference|; scale_array: r / max_j|b_j|
//   +10 %    x + 0.1·|x|     (the largest base element moves by one step); × (1 + 1e-6) so that
//                            round-off cannot leave the value within the "one step of the base"
//                            window the decoder snaps back
// clamped to the entry's range [lo, hi], and decoded with ParameterSpace::Decode like any tuner
// point: relative entries that refer to the perturbed key move with it, every value is quantised
// to its resolution. A perturbation is not evaluated, and reported as such, when
//   kAtBound    x_i already sits at the bound it would move past (clamping leaves it at x_i, or
//               the clamped move quantises back to the centre value),
//   kNoOp       the decoded set equals the centre set bit for bit (a 10 % change of 0, a change
//               that quantises back to the centre value, a parameter without a resolution step),
//   kDuplicate  it decodes to a set already in the batch (then it shares that set's results),
//   kInfeasible the decoded set violates a schema rule (the tuner gives such a set a penalty
//               without running it; it says nothing about what the scenarios can see).
// The centre and all distinct perturbed sets run as ONE batch of the BatchEvaluator: the result
// is bit-identical for any thread count.
//
// Changes. ΔJ_s = J_s(perturbed) − J_s(centre) per scenario s (unweighted scenario cost [s]);
// per dimension and scenario the four signed changes (0 for a perturbation not evaluated) and
// max |ΔJ_s| over them.
//
// Scenario classes. Scenarios are grouped by how their CENTRE run ended: "completed" and
// "aborted". The two costs measure different things (the mean lap time and sideslip of a whole
// run, versus the abort penalty graded by the distance not driven), so an effect seen only in
// aborted runs means "fails earlier or later", not "drives better"; the same classes as the
// verdict of comparison.md (tuning/optim/comparison.h).
//
// Exercised. A dimension is exercised when some evaluated perturbation changes some scenario's
// cost OR any of its run metrics at all — tolerance 0, bit-level: J_s ≠ J_s(centre), or the run
// summary RunSummaryYaml (every RunMetrics field in shortest round-trip text) differs. A
// bit-level change is what the optimiser can see; whether it is large enough to matter on the car
// is the separate question the resolution of tuning/optim/comparison.h (kDefaultResolution,
// 0.02 s) answers, reported as `below_noise`. A dimension that is not exercised cannot reach the
// cost through this scenario set: its tuned value is wherever the optimiser happened to leave it.
//
// Subsystem. Keys under ESC., countersteer_system., SlipControl.ABS. and SlipControl.TC. belong
// to ESC, CS, ABS and TC; the activations of that subsystem in the centre runs (RunMetrics
// esc_count, cs_count, abs_count, tc_count) give the reason "ESC never acted" for a dimension
// that is not exercised.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "params/schema/stability_params.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/space.h"

namespace scw::tuning {

/// The four perturbations in increasing order of the argument.
inline constexpr int kSensitivityPerturbations = 4;
/// "-10 %", "-1 step", "+1 step", "+10 %" (k = 0..3).
const char* SensitivityPerturbationName(int k);

/// Relative size of the ±10 % perturbations.
inline constexpr double kSensitivityRelative = 0.10;

enum class PerturbationKind {
  kEvaluated,   ///< a set of its own in the batch
  kDuplicate,   ///< the same set as an earlier point in the batch (shares its results)
  kAtBound,     ///< the argument sits at (or within a quantisation step of) the bound
  kNoOp,        ///< decodes to the centre set bit for bit
  kInfeasible,  ///< the decoded set violates a schema rule (not run)
};
/// "evaluated", "duplicate", "at bound", "no-op", "infeasible".
const char* PerturbationKindName(PerturbationKind k);

/// One perturbed point of one dimension.
struct PerturbedPoint {
  double x = 0.0;      ///< transform argument after clamping to [lo, hi]
  double value = 0.0;  ///< the decoded value of the entry's own key (the factor for scale_array)
  PerturbationKind kind = PerturbationKind::kEvaluated;
  int set = 0;       ///< index of its set in the batch (0 = the centre; kEvaluated/kDuplicate)
  std::string note;  ///< kDuplicate: which point it duplicates; kInfeasible: the first problem
};

/// Which perturbations a plan makes.
enum class SensitivityMode {
  kLocal,  ///< the four local moves above (±10 %, ±1 step): what the tuned point is sensitive to
  /// Reach: the argument moved to each end of its range (points 0 and 3; points 1 and 2 are
  /// kNoOp); an end whose set breaks a schema rule is approached, halving the move (up to 8
  /// times) until the set is valid. A dimension no training run notices at either end cannot be
  /// exercised by the scenario set from this point on its own: `scw tune` freezes it at the base
  /// value before the search.
  kRange,
};

/// The plan: the centre and the distinct perturbed sets, in batch order.
struct SensitivityPlan {
  SensitivityMode mode = SensitivityMode::kLocal;
  std::vector<params::StabilityParams> sets;  ///< [0] = the centre
  std::vector<std::string> labels;            ///< per dimension, SpaceEntry::Label()
  std::vector<double> x_centre;               ///< per dimension, the centre's argument
  std::vector<double> value_centre;           ///< per dimension, as PerturbedPoint::value
  std::vector<double> step;                   ///< per dimension, δ in argument units (0: none)
  std::vector<std::array<PerturbedPoint, kSensitivityPerturbations>> points;  ///< per dimension
};

/// Perturbs `u_centre` (a point of `space`, decoded against `base` as the tuner does) one
/// dimension at a time as described above. Deterministic; runs nothing.
SensitivityPlan PlanSensitivity(const ParameterSpace& space, const std::vector<double>& u_centre,
                                const params::StabilityParams& base,
                                SensitivityMode mode = SensitivityMode::kLocal);

/// One dimension's result.
struct DimensionSensitivity {
  std::string label;  ///< SpaceEntry::Label()
  Transform transform = Transform::kDirect;
  std::string subsystem;  ///< "ESC", "CS", "ABS", "TC" or "" (another key)
  /// Activations of that subsystem summed over the centre runs (-1: no subsystem).
  int subsystem_activations = -1;
  double x_centre = 0.0, value_centre = 0.0, step = 0.0;  ///< as in SensitivityPlan
  std::array<PerturbedPoint, kSensitivityPerturbations> points;
  /// [scenario][perturbation]: J_s(perturbed) − J_s(centre); 0 where not evaluated.
  std::vector<std::array<double, kSensitivityPerturbations>> delta;
  std::vector<double> max_abs_delta;     ///< per scenario, max |ΔJ_s| over the perturbations
  std::vector<bool> changed;             ///< per scenario: cost or a run metric changed (bit-level)
  double max_abs_delta_completed = 0.0;  ///< over the scenarios whose centre run completed
  double max_abs_delta_aborted = 0.0;    ///< over the scenarios whose centre run aborted
  bool exercised = false;  ///< some perturbation changes some scenario (see the header comment)
  /// Exercised, but no |ΔJ_s| reaches kDefaultResolution.
  bool below_noise = false;
  /// Not exercised: why, as far as is known ("ESC never acted in the centre runs", "no
  /// perturbation changes the set", "no run changes, although ESC acts", "no run changes").
  std::string reason;
};

struct SensitivityResult {
  std::vector<std::string> scenarios;
  std::vector<RunMetrics> centre_runs;  ///< per scenario
  std::vector<double> centre_costs;     ///< per scenario J_s
  std::vector<DimensionSensitivity> dimensions;
  int sets = 0;  ///< sets in the batch (centre included); runs = sets × scenarios
  int completed = 0, aborted = 0;  ///< scenario classes (by the centre run)

  /// Labels of the dimensions that are not exercised, in space order.
  std::vector<std::string> NotExercised() const;
};

/// Plans, evaluates the centre and every distinct perturbed set on every scenario of `ev` as one
/// batch (`progress` counts its runs), and returns the changes. Deterministic for any thread
/// count of `ev`.
SensitivityResult ComputeSensitivity(const BatchEvaluator& ev, const ParameterSpace& space,
                                     const std::vector<double>& u_centre,
                                     const params::StabilityParams& base,
                                     const BatchProgress& progress = {},
                                     SensitivityMode mode = SensitivityMode::kLocal);

/// The same for a plan made by PlanSensitivity with the same `space` (the plan's sets are the
/// batch; `progress` counts its runs: plan.sets.size() × scenarios).
SensitivityResult EvaluateSensitivity(const BatchEvaluator& ev, const ParameterSpace& space,
                                      const SensitivityPlan& plan,
                                      const BatchProgress& progress = {});

/// Markdown section "## Parameter sensitivity" (heading level `level`, 2 = "##"): what the point
/// is (`point`, e.g. "the tuned set"), one row per parameter (name, centre value, the perturbed
/// values used, the subsystem's activations, max |ΔJ| per scenario class, verdict "exercised" or
/// "not exercised by this scenario set" with the reason), the list of parameters not exercised,
/// then max |ΔJ| per scenario.
std::string SensitivityMarkdown(const SensitivityResult& r, const std::string& point,
                                int level = 2);

/// Long CSV: one row per dimension × perturbation × scenario with the argument, the value, the
/// kind and the signed ΔJ_s, "nan" for a perturbation not evaluated (header: dimension,
/// perturbation,kind,x,value,scenario,class,delta_cost,exercised).
std::string SensitivityCsv(const SensitivityResult& r);

}  // namespace scw::tuning
