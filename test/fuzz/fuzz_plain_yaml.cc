// Fuzz target: plain workspace YAML files through the strict loader — scenario files
// (params/scenarios/*.yaml, scw simulate --scenario) and vehicle files (params/vehicles/*.yaml).
// Every input goes through both schemas. Property: an accepted file written back with
// ToPlainYaml loads again to identical values.
#include <cstdint>
#include <string>

#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/scenario_params.h"
#include "params/schema/vehicle_params.h"
#include "test/fuzz/fuzz_targets.h"
#include "test/fuzz/fuzz_util.h"

using scw::ConfigError;
namespace params = scw::params;

namespace {

template <class P>
void RoundTrip(const std::string& text, const char* what) {
  P p;
  try {
    p = params::LoadPlainText<P>(text, "fuzz.yaml");
  } catch (const ConfigError&) {
    return;
  }
  const std::string out = params::ToPlainYaml(p);
  P q;
  try {
    q = params::LoadPlainText<P>(out, "written.yaml");
  } catch (const ConfigError& e) {
    FUZZ_CHECK(false, std::string(what) + " written back does not load: " + e.what() + "\n" + out);
  }
  FUZZ_CHECK(params::DifferingKeys(p, q).empty(), std::string(what) + " round trip changes values");
}

}  // namespace

int scw::fuzz::FuzzPlainYaml(const std::uint8_t* data, std::size_t size) {
  const std::string text = scw::fuzz::AsText(data, size);
  RoundTrip<params::ScenarioParams>(text, "scenario");
  RoundTrip<params::VehicleParams>(text, "vehicle");
  return 0;
}

SCW_FUZZ_ENTRY(scw::fuzz::FuzzPlainYaml)
