// One scenario of a scenario set (tuning/sim/scenario_set.h): a name, a weight in the cost, and the
// scenario itself as a base (the built-in default scenario or a scenario file) plus `key=value`
// overrides of scenario keys (docs/parameters-scenario.md), the same as `scw simulate --set`.
//
//   - {name: wet, weight: 2.0, file: wet.yaml, set: [laps=2, gg_scale=1.1]}
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::tuning {

inline std::string CheckOverride(const std::string& text) {
  return text.find('=') == std::string::npos ? "must look like key=value, got '" + text + "'" : "";
}
/// An override of a scenario key. Only its form is checked when the set is read; the key and the
/// value are checked when the scenario is prepared (LoadEntry), naming the override.
inline constexpr params::TextRule kOverrideRule{"key=value", &CheckOverride};

struct ScenarioEntry {
  std::string name;
  double weight = 1.0;
  std::string file;                    ///< "" = the built-in default scenario
  std::vector<std::string> overrides;  ///< "key=value"

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name",
                     .doc = "Name of the scenario in every report and log; unique in the set "
                            "(training and held_out together).",
                     .rule = params::kNotEmpty});
    v.Field(s.weight, {.key = "weight",
                       .lo = 0.0,
                       .doc = "Weight of the scenario's cost in the set's total.",
                       .optional = true});
    v.Field(s.file, {.key = "file",
                     .doc = "Scenario file the scenario starts from, relative to the set file's "
                            "folder; not given: the built-in default scenario.",
                     .optional = true,
                     .omit_default = true});
    v.Field(s.overrides, {.key = "set",
                          .doc = "Overrides of scenario keys, applied in order after the base "
                                 "(as `scw simulate --set`).",
                          .optional = true,
                          .min_size = 0,
                          .rule = kOverrideRule});
  }
};

}  // namespace scw::tuning
