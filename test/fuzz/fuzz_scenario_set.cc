// Fuzz target: scenario-set files (scw tune/evaluate --scenarios) and the `set: [key=value]`
// overrides of their built-in entries (the same code as `--set`). Property: an accepted set
// printed with ToYaml (scw tune --print-scenarios) reads back to the same set.
#include <cstdint>
#include <string>

#include "test/fuzz/fuzz_targets.h"
#include "test/fuzz/fuzz_util.h"
#include "tuning/sim/scenario_set.h"

using scw::ConfigError;

int scw::fuzz::FuzzScenarioSet(const std::uint8_t* data, std::size_t size) {
  const std::string text = scw::fuzz::AsText(data, size);
  scw::tuning::ScenarioSet set;
  try {
    set = scw::tuning::ScenarioSet::FromYamlText(text, "fuzz_set.yaml");
  } catch (const ConfigError&) {
    return 0;
  }
  for (const auto* group : {&set.training, &set.held_out})
    for (const auto& e : *group) {
      if (!e.file.empty()) continue;  // no file access from the fuzzer
      try {
        (void)scw::tuning::LoadEntry(e, "");
      } catch (const ConfigError&) {
      }
    }
  const std::string yaml = set.ToYaml();
  scw::tuning::ScenarioSet again;
  try {
    again = scw::tuning::ScenarioSet::FromYamlText(yaml, "printed.yaml");
  } catch (const ConfigError& e) {
    FUZZ_CHECK(false, std::string("the printed set does not load: ") + e.what() + "\n" + yaml);
  }
  FUZZ_CHECK(again.ToYaml() == yaml, "the printed set changes when read back:\n" + yaml +
                                         "\nread back:\n" + again.ToYaml());
  return 0;
}

SCW_FUZZ_ENTRY(scw::fuzz::FuzzScenarioSet)
