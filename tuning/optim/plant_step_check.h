// The tune's search step: whether a coarser plant step may stand in for each vehicle's own step
// while the optimiser searches (docs/plant-step.md).
//
// The plant is about two thirds of a closed-loop run's time; at 2 ms instead of 1 ms a tuning
// evaluation costs about half. The optimiser only ranks candidates, and everything scw tune
// reports (the comparison, the verdicts, the sensitivity, the exported files' provenance) is run
// at the vehicle's own step, so a coarser search step can only make the search less precise, never
// the report less true. It is used only where it gives the same outcomes: before the search, the
// base set runs on every training scenario at both steps and every scenario must pass every rule
// of PlantStepTolerances; otherwise the search falls back to the vehicle's step and says why.
#pragma once

#include <string>
#include <vector>

#include "params/schema/stability_params.h"
#include "tuning/optim/evaluator.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {

/// The default search step of scw tune [s] (the vehicles' own step is 1 ms).
inline constexpr double kDefaultSearchPlantStep = 0.002;

/// What "the same outcome" means, per training scenario, base set at the search step against the
/// vehicle's own step. The scales are those of the cost and the abort rules: an abort costs
/// hundreds, a clean lap's time counts in seconds, the sideslip allowance is 5°. The closed loop at
/// the limit is sensitive to any perturbation (1 ms against 0.5 ms already moves lap times by
/// ~0.03 s, max |β| by up to ~0.5° and the abort rule that trips first in a spin); the bounds
/// below are twice such differences.
struct PlantStepTolerances {
  double lap_time_s = 0.1;    ///< |Δ mean lap time| of a completed run
  double progress = 0.02;     ///< |Δ fraction of the planned distance| of an aborted run
  double max_beta_deg = 1.0;  ///< |Δ max |β||
  double total_cost = 0.01;   ///< |Δ Σ weight·J| / Σ weight·J at the vehicle's step
};

/// Same class of outcome: completed; loss of control (sideslip, lateral error, off track); a wheel
/// locked or spinning; anything else (non-finite, timeout, invalid). Which rule trips first in a
/// spin is itself sensitive to rounding; the class is not.
int OutcomeClass(RunStatus status);

struct PlantStepScenarioCheck {
  std::string scenario;
  RunMetrics fine, coarse;            ///< the base set at the vehicle's step and at the search step
  std::vector<std::string> failures;  ///< the rules it breaks ("" when it passes)
};

struct PlantStepCheck {
  double step = 0.0;  ///< the search step asked for [s] (0: each vehicle's own step)
  bool ran = false;   ///< false: step 0, or every training scenario's vehicle has that step
  bool passed = false;
  double fine_total = 0.0, coarse_total = 0.0;  ///< Σ weight·J of the base set
  std::vector<PlantStepScenarioCheck> scenarios;
  /// The step the search used: `step` if passed, else 0 (the vehicles' own).
  double used() const { return ran && passed ? step : 0.0; }
  /// "passed", "failed", or "not run".
  std::string Verdict() const;
  /// Number of scenarios that pass.
  int Passing() const;
};

/// The entries with the scenario key plant_step = `step` appended to their overrides.
std::vector<ScenarioEntry> WithPlantStep(std::vector<ScenarioEntry> entries, double step);

/// True when some scenario of `fine` runs at a step other than `step`.
bool StepDiffers(const BatchEvaluator& fine, double step);

/// Compares the base set's runs at the vehicle's step (`fine`) and at the search step (`coarse`)
/// scenario by scenario (named by `scenarios`, in the runs' order) under `tol`.
PlantStepCheck ComparePlantSteps(double step, const std::vector<std::string>& scenarios,
                                 const SetEvaluation& fine, const SetEvaluation& coarse,
                                 const PlantStepTolerances& tol = {});

/// The check as a Markdown section (comparison.md) and as one line (the console).
std::string PlantStepCheckMarkdown(const PlantStepCheck& check);
std::string PlantStepCheckLine(const PlantStepCheck& check);

}  // namespace scw::tuning
