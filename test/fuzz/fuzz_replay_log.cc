// Fuzz target: controller logs (scw replay LOG): header and every row through
// ControllerLogReader, as the replay reads them. Properties of accepted rows: t is finite and
// never decreases.
#include <cmath>
#include <cstdint>
#include <string>

#include "test/fuzz/fuzz_targets.h"
#include "test/fuzz/fuzz_util.h"
#include "tuning/replay/controller_log.h"

using scw::ConfigError;

int scw::fuzz::FuzzReplayLog(const std::uint8_t* data, std::size_t size) {
  static scw::fuzz::MemFile file;
  const std::string& path = file.Write(data, size);
  try {
    scw::tuning::replay::ControllerLogReader reader(path);
    scw::controller::StabilityInput in;
    double last_t = -INFINITY;
    while (reader.Next(&in)) {
      FUZZ_CHECK(std::isfinite(in.t) && in.t >= last_t, "t not finite or going backwards");
      last_t = in.t;
    }
  } catch (const ConfigError&) {
  }
  return 0;
}

SCW_FUZZ_ENTRY(scw::fuzz::FuzzReplayLog)
