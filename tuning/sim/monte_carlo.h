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
// `[x]`. Every key is checked against the scenario schema when the set is read.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "params/io/yaml_doc.h"
#include "params/schema/field.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {

struct MonteCarloDraw {
  enum class Kind { kUniform, kInteger, kChoice };
  std::string key;
  Kind kind = Kind::kUniform;
  double lo = 0.0, hi = 0.0;         ///< uniform / integer bounds (inclusive)
  double step = 0.0;                 ///< uniform: rounded to a multiple of step (0 = exact)
  std::vector<std::string> choices;  ///< choice: the values, verbatim
};

struct MonteCarloGrid {
  std::string key;
  std::vector<std::string> values;  ///< verbatim
};

struct MonteCarloBlock {
  std::string name;
  int count = 1;
  std::uint64_t seed = 1;
  double weight = 1.0;
  std::string file;
  std::vector<std::string> base;  ///< "key=value"
  std::vector<MonteCarloDraw> vary;
  std::vector<MonteCarloGrid> grid;

  /// Number of scenarios: count × the product of the grid sizes.
  std::size_t Size() const;
  /// The scenarios in index order, names `<name>_<index>` zero-padded to a common width (>= 3).
  std::vector<ScenarioEntry> Expand() const;
};

/// Reads the map under `monte_carlo:`; problems are added under `where` (e.g. training[2]).
MonteCarloBlock ReadMonteCarloBlock(const params::YamlNode& node, const std::string& where,
                                    Problems* pr);

/// The largest number of scenarios one block may expand to (a typo in a count must not fill the
/// memory).
inline constexpr std::size_t kMaxMonteCarloScenarios = 100000;

}  // namespace scw::tuning
