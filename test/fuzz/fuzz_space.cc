// Fuzz target: search-space files (scw tune --space, scw space show). Properties of an accepted
// space: decoding the corners and the centre of the cube and encoding the defaults do not crash
// and give finite arguments; ToYaml round-trips (documented in tuning/optim/space.h).
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "test/fuzz/fuzz_targets.h"
#include "test/fuzz/fuzz_util.h"
#include "tuning/optim/space.h"

using scw::ConfigError;

int scw::fuzz::FuzzSpace(const std::uint8_t* data, std::size_t size) {
  const std::string text = scw::fuzz::AsText(data, size);
  std::unique_ptr<scw::tuning::ParameterSpace> space;
  try {
    space = std::make_unique<scw::tuning::ParameterSpace>(
        scw::tuning::ParameterSpace::FromYamlText(text, "fuzz_space.yaml"));
  } catch (const ConfigError&) {
    return 0;
  }
  const std::size_t n = static_cast<std::size_t>(space->size());
  const scw::params::StabilityParams base;
  for (double u : {0.0, 0.5, 1.0}) {
    const std::vector<double> x(n, u);
    scw::Problems pr;
    (void)space->Decode(x, base, &pr);
    for (double a : space->Arguments(x)) FUZZ_CHECK(std::isfinite(a), "non-finite argument");
  }
  for (double u : space->Encode(base))
    FUZZ_CHECK(u >= 0.0 && u <= 1.0, "Encode left the unit cube: " + std::to_string(u));
  const std::string yaml = space->ToYaml();
  try {
    const auto again = scw::tuning::ParameterSpace::FromYamlText(yaml, "printed.yaml");
    FUZZ_CHECK(again.ToYaml() == yaml, "ToYaml does not round-trip:\n" + yaml);
  } catch (const ConfigError& e) {
    FUZZ_CHECK(false, std::string("ToYaml output does not load: ") + e.what() + "\n" + yaml);
  }
  return 0;
}

SCW_FUZZ_ENTRY(scw::fuzz::FuzzSpace)
