// Fuzz target: the car's ROS 2 stability params file — the strict loader (scw params validate,
// scw tune --base), the import mode (scw params import) and the rcl-rule checker
// (scw params check). Property: a file the strict loader accepts exports (ToRosYaml) to a file
// that passes the checker and loads back to identical values.
#include <cstdint>
#include <string>

#include "params/io/load.h"
#include "params/io/ros2_check.h"
#include "params/io/write.h"
#include "params/schema/stability_params.h"
#include "test/fuzz/fuzz_targets.h"
#include "test/fuzz/fuzz_util.h"

using scw::ConfigError;
namespace params = scw::params;

int scw::fuzz::FuzzStabilityParams(const std::uint8_t* data, std::size_t size) {
  const std::string text = scw::fuzz::AsText(data, size);
  static const auto declared = params::DeclaredParams<params::StabilityParams>();

  params::CheckOptions co;
  co.node_key = params::kStabilityNodeKey;
  const params::CheckReport check = params::CheckRosParamsText(text, declared, co);
  (void)check.Format("fuzz.yaml");

  params::LoadOptions lenient;
  lenient.layout = params::Layout::kRos2;
  lenient.node_key = params::kStabilityNodeKey;
  lenient.lenient = true;
  try {
    params::LoadReport rep;
    (void)params::LoadFromText<params::StabilityParams>(text, "fuzz.yaml", lenient, &rep);
  } catch (const ConfigError&) {
  }

  params::StabilityParams p;
  params::LoadReport rep;
  try {
    p = params::LoadRosText<params::StabilityParams>(text, "fuzz.yaml", params::kStabilityNodeKey,
                                                     &rep);
  } catch (const ConfigError&) {
    return 0;
  }
  const std::string out = params::ToRosYaml(p, params::kStabilityNodeKey, rep.present);
  const params::CheckReport out_check = params::CheckRosParamsText(out, declared, co);
  FUZZ_CHECK(out_check.ok(), out_check.Format("export") + "\n" + out);
  params::StabilityParams q;
  try {
    q = params::LoadRosText<params::StabilityParams>(out, "export.yaml", params::kStabilityNodeKey);
  } catch (const ConfigError& e) {
    FUZZ_CHECK(false, std::string("the export does not load back: ") + e.what());
  }
  FUZZ_CHECK(params::DifferingKeys(p, q).empty(), "the export changes values");
  return 0;
}

SCW_FUZZ_ENTRY(scw::fuzz::FuzzStabilityParams)
