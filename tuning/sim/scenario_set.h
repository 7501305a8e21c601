// Scenario sets: the weighted training scenarios the tuner optimises on, the held-out scenarios
// used only for the final comparison, and the cost weights.
//
// File format (plain YAML, described once by ScenarioSetFile below: the strict loader, the writer,
// validation and the docs table, `scw params docs --kind scenario-set`, derive from it):
//   name: default
//   cost: {sideslip_allowed_deg: 5.0, ...}          # optional; when given, every CostWeights key
//   training:
//     - {name: nominal, weight: 1.0, set: [gg_scale=1.2, laps=2]}  # overrides of the default
//     - {name: wet, file: wet.yaml, set: [laps=2]}  # or of a scenario file
//     - monte_carlo: {name: mc, count: 8, ...}      # or a Monte-Carlo block (monte_carlo.h)
//   held_out:                                       # optional
//     - {name: nominal_3laps, set: [gg_scale=1.1]}
#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "params/schema/cost_params.h"
#include "params/schema/scenario_params.h"
#include "tuning/sim/monte_carlo.h"
#include "tuning/sim/scenario_entry.h"

namespace scw::tuning {

/// An entry of a set file: one scenario, or a Monte-Carlo block `{monte_carlo: {...}}`.
using SetEntry = std::variant<ScenarioEntry, MonteCarloBlock>;

/// A scenario-set file as written: Monte-Carlo blocks not yet expanded.
struct ScenarioSetFile {
  std::string name = "default";
  std::optional<params::CostWeights> cost;
  std::vector<SetEntry> training;
  std::optional<std::vector<SetEntry>> held_out;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name", .doc = "Name of the set (logs, reports).", .optional = true});
    v.Nested("cost", s.cost);
    v.List(s.training, {.key = "training",
                        .doc = "The scenarios the tuner optimises on: each a scenario or a "
                               "Monte-Carlo block."});
    v.List(s.held_out,
           {.key = "held_out", .doc = "Scenarios for the final comparison only, never tuned on."});
  }
  /// Scenario names are unique across training and held_out (Monte-Carlo blocks expanded).
  static void CrossCheck(const ScenarioSetFile& f, Problems& pr);
};

struct ScenarioSet {
  std::string name = "default";
  params::CostWeights cost;
  std::vector<ScenarioEntry> training;
  std::vector<ScenarioEntry> held_out;
  std::string base_dir;  ///< folder of the set file (relative scenario files)

  /// The built-in default set (params/scenarios/default_set.yaml holds the same).
  static ScenarioSet Default();
  /// The built-in robust set: params/scenarios/robust_set.yaml (embedded at build time):
  /// Monte-Carlo blocks of the critical situations and clean laps that also draw the plant
  /// values we do not know (brake dead time, steering delay, the rear tyre beyond its peak, grip,
  /// yaw inertia) within stated ranges.
  static ScenarioSet Robust();
  /// A built-in set by name ("default", "robust"), else the file at `name_or_path`.
  static ScenarioSet FromNameOrFile(const std::string& name_or_path);
  /// Throws ConfigError naming the file, the key path (`training[2].monte_carlo.count`), the rule
  /// and the line.
  static ScenarioSet FromYamlText(const std::string& text, const std::string& file);
  static ScenarioSet FromFile(const std::string& path);
  /// The set with every Monte-Carlo block expanded (scw tune --print-scenarios); reads back to
  /// the same set.
  std::string ToYaml() const;
  /// The file form of this set (no Monte-Carlo blocks: they are expanded).
  ScenarioSetFile ToFile() const;
};

/// The scenario of one entry (file or default, then overrides; name from the entry).
params::ScenarioParams LoadEntry(const ScenarioEntry& e, const std::string& base_dir);

}  // namespace scw::tuning
