// A training scenario of the built-in default set by name (the critical-situation tests).
#pragma once

#include <stdexcept>
#include <string>

#include "tuning/sim/scenario_set.h"

namespace scw::tuning {

inline const ScenarioEntry& DefaultTraining(const std::string& name) {
  static const ScenarioSet set = ScenarioSet::Default();
  for (const auto& e : set.training)
    if (e.name == name) return e;
  throw std::runtime_error("no training scenario " + name);
}

}  // namespace scw::tuning
