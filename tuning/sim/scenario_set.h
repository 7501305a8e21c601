// Scenario sets: the weighted training scenarios the tuner optimises on, the held-out scenarios
// used only for the final comparison, and the cost weights.
//
// File format (plain YAML):
//   name: default
//   cost: {sideslip_allowed_deg: 5.0, sideslip_weight: 2.0}        # optional, CostWeights keys
//   training:
//     - {name: nominal, weight: 1.0, set: [gg_scale=1.2, laps=2]}  # overrides of the default
//     - {name: wet, file: wet.yaml, set: [laps=2]}                 # or a scenario file (+
//     overrides)
//   held_out:
//     - {name: nominal_3laps, set: [gg_scale=1.1]}
#pragma once

#include <string>
#include <vector>

#include "params/schema/cost_params.h"
#include "params/schema/scenario_params.h"

namespace scw::tuning {

struct ScenarioEntry {
  std::string name;
  double weight = 1.0;
  std::string file;                    ///< "" = the built-in default scenario
  std::vector<std::string> overrides;  ///< "key=value"
};

struct ScenarioSet {
  std::string name = "default";
  params::CostWeights cost;
  std::vector<ScenarioEntry> training;
  std::vector<ScenarioEntry> held_out;
  std::string base_dir;  ///< folder of the set file (relative scenario files)

  /// The built-in default set (params/scenarios/default_set.yaml holds the same).
  static ScenarioSet Default();
  /// Throws ConfigError naming the file, the entry and the rule.
  static ScenarioSet FromYamlText(const std::string& text, const std::string& file);
  static ScenarioSet FromFile(const std::string& path);
  std::string ToYaml() const;
};

/// The scenario of one entry (file or default, then overrides; name from the entry).
params::ScenarioParams LoadEntry(const ScenarioEntry& e, const std::string& base_dir);

}  // namespace scw::tuning
