// Monte-Carlo blocks of a scenario set: one base scenario, distributions and grids over its keys,
// a count and a seed, expanded deterministically into named scenarios (docs/scenarios.md,
// "Large sets from a compact description").
//
//   training:
//     - monte_carlo:
//         name: power_on          # the scenarios are power_on_000, power_on_001, ...
//         count: 32               # draws per grid point (default 1)
//         seed: 1                 # draw i uses only (seed, i): a larger count keeps the first ones
//         weight: 1.0             # of every drawn scenario (optional)
//         file: wet.yaml          # optional base scenario file, as an entry's `file`
//         set: [kind=critical, laps=1]          # base overrides, as an entry's `set`
//         vary:                                 # one draw per key, in the order written
//           events.throttle.corner: {choice: [1, 3, 5, 7, 8]}
//           events.throttle.value: {uniform: [0.8, 1.0], step: 0.01}
//           seed: {integer: [1, 1000]}
//         grid:                                 # every combination (first key slowest) × count
//           gg_scale: [1.0, 1.1]
//
// A value drawn for a list-valued key (the event and patch blocks) becomes a one-element list
// `[x]`. The block is described once, by the Visit functions below: the scenario set's strict
// loader (key paths like `training[2].monte_carlo.vary.seed.integer`), its writer, validation and
// the docs table (`scw params docs --kind scenario-set`) derive from them. Every key under `vary`
// and `grid` is checked against the scenario schema when the set is read.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "params/schema/field.h"
#include "tuning/sim/scenario_entry.h"

namespace scw::tuning {

/// The largest number of scenarios one block may expand to (a typo in a count must not fill the
/// memory).
inline constexpr std::size_t kMaxMonteCarloScenarios = 100000;

/// "" for a key of the scenario schema, else "unknown scenario key 'x'" (with a did-you-mean).
std::string CheckScenarioKey(const std::string& key);
inline constexpr params::TextRule kScenarioKeyRule{"a scenario key (parameters-scenario.md)",
                                                   &CheckScenarioKey};

/// One `vary` entry: exactly one of uniform, integer, choice.
struct MonteCarloDraw {
  std::optional<std::vector<double>> uniform;  ///< [low, high]
  std::optional<std::vector<double>> integer;  ///< [low, high], whole numbers
  std::optional<std::vector<std::string>> choice;
  std::optional<double> step;  ///< uniform only: rounded to a multiple of step

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.uniform, {.key = "uniform",
                        .doc = "[low, high]: a number drawn uniformly, printed as its shortest "
                               "text.",
                        .min_size = 0});
    v.Field(s.integer, {.key = "integer",
                        .doc = "[low, high]: a whole number drawn uniformly, both ends included "
                               "(|bound| <= 1e15).",
                        .min_size = 0});
    v.Field(s.choice, {.key = "choice", .doc = "The values, each equally likely, used verbatim."});
    v.Field(s.step,
            {.key = "step",
             .doc = "uniform only (> 0): the drawn number is rounded to a multiple of step, "
                    "printed as the short decimal."});
  }
  /// Exactly one kind; [low, high] with low <= high; whole-number integer bounds; a step > 0 and
  /// only for uniform.
  static void CrossCheck(const MonteCarloDraw& d, Problems& pr);
};

struct MonteCarloBlock {
  static constexpr params::Meta kBlock{
      .key = "monte_carlo",
      .doc =
          "A Monte-Carlo block: a base scenario, draws and grids over its keys, a count and "
          "a seed; it expands, when the set is read, into count × (grid sizes) named "
          "scenarios (scenarios.md)."};

  std::string name;
  int count = 1;
  std::int64_t seed = 1;
  double weight = 1.0;
  std::string file;
  std::vector<std::string> base;  ///< "key=value"
  std::optional<params::OrderedMap<MonteCarloDraw>> vary;
  std::optional<params::OrderedMap<std::vector<std::string>>> grid;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name",
                     .doc = "Prefix of the scenarios' names: power_on gives power_on_000, "
                            "power_on_001, … (the index zero-padded to a common width, at least "
                            "three digits).",
                     .rule = params::kNotEmpty});
    v.Field(s.count, {.key = "count",
                      .lo = 1,
                      .hi = static_cast<double>(kMaxMonteCarloScenarios),
                      .doc = "Draws per grid point.",
                      .optional = true});
    v.Field(s.seed, {.key = "seed",
                     .lo = 0,
                     .doc = "Scenario i draws from a stream that depends only on (seed, i): a "
                            "larger count keeps the first scenarios.",
                     .optional = true});
    v.Field(s.weight, {.key = "weight",
                       .lo = 0.0,
                       .doc = "Weight of each drawn scenario's cost.",
                       .optional = true});
    v.Field(s.file, {.key = "file",
                     .doc = "Base scenario file, as an entry's file.",
                     .optional = true,
                     .omit_default = true});
    v.Field(s.base, {.key = "set",
                     .doc = "Base overrides, as an entry's set; the drawn values follow them.",
                     .optional = true,
                     .min_size = 0,
                     .rule = kOverrideRule});
    v.Map(s.vary, {.key = "vary",
                   .doc = "One draw per scenario key, in the order written: {uniform: [low, "
                          "high], step: s}, {integer: [low, high]} or {choice: [values]}.",
                   .rule = kScenarioKeyRule});
    v.Map(s.grid, {.key = "grid",
                   .doc = "Values per scenario key (verbatim); every combination, first key "
                          "slowest, each with count draws.",
                   .rule = kScenarioKeyRule});
  }
  /// At most kMaxMonteCarloScenarios scenarios.
  static void CrossCheck(const MonteCarloBlock& b, Problems& pr);

  /// Number of scenarios: count × the product of the grid sizes.
  std::size_t Size() const;
  /// Name of scenario i: `<name>_<index>`, zero-padded to a common width (>= 3).
  std::string ScenarioName(std::size_t i) const;
  /// The scenarios in index order (none for a block that breaks its rules).
  std::vector<ScenarioEntry> Expand() const;
};

}  // namespace scw::tuning
