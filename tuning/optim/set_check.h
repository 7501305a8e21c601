// Which subsystem a scenario set can see (`scw tune --check-set`): the base set is run on every
// scenario as it is and once with each subsystem (ESC, CS, ABS, TC) switched off. A subsystem
// *acts* in a scenario when it activated at least once; it *decides* the scenario when switching
// it off turns a completed run into an abort (or the reverse) or changes the scenario's cost by at
// least `decide_fraction` (5 %). A tuner can only tune the parameters of a subsystem that acts in
// its training scenarios, and tunes them for what they matter only where the subsystem decides.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "params/schema/stability_params.h"
#include "tuning/optim/evaluator.h"

namespace scw::tuning {

/// Short names in table order: ESC, countersteer, ABS, TC.
inline constexpr std::array<const char*, 4> kCheckedSubsystems = {"ESC", "CS", "ABS", "TC"};

struct ScenarioCheck {
  std::string name;
  RunMetrics base;  ///< the base set as it is
  double base_cost = 0.0;
  std::array<int, 4> activations{};  ///< ESC, CS, ABS, TC activations with the base set
  std::array<bool, 4> decides{};     ///< switching it off changes the outcome or cost ≥ 5 %
  std::array<double, 4> cost_off{};  ///< the scenario's cost with that subsystem off
  std::array<std::string, 4> status_off;
};

struct SetCheck {
  std::vector<ScenarioCheck> scenarios;
  /// Scenarios in which each subsystem acts / decides.
  std::array<int, 4> acting{}, deciding{};
};

/// `base` with subsystem k (0..3 = ESC, CS, ABS, TC) switched off.
params::StabilityParams WithoutSubsystem(params::StabilityParams base, std::size_t k);

/// Runs the base set and the four "one subsystem off" sets on every scenario of `ev` (one batch,
/// deterministic for any thread count).
SetCheck CheckSet(const BatchEvaluator& ev, const params::StabilityParams& base,
                  double decide_fraction = 0.05, const BatchProgress& progress = {});

/// A Markdown section: one row per scenario, then per subsystem how many scenarios it acts in and
/// decides, and a warning line for each subsystem that never acts (its parameters cannot reach the
/// cost) or acts but decides nothing.
std::string SetCheckMarkdown(const std::string& group, const SetCheck& c, bool training);

}  // namespace scw::tuning
