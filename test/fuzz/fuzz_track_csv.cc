// Fuzz target: track CSV files (scenario `track: *.csv`, scw track info --track): the generic
// column reader and the centre-line loader in both public formats. Property of an accepted
// track: finite length and geometry, and projecting its own nodes gives finite coordinates.
#include <cmath>
#include <cstdint>
#include <string>

#include "params/io/csv.h"
#include "test/fuzz/fuzz_targets.h"
#include "test/fuzz/fuzz_util.h"
#include "tuning/sim/track_csv.h"

using scw::ConfigError;

int scw::fuzz::FuzzTrackCsv(const std::uint8_t* data, std::size_t size) {
  static scw::fuzz::MemFile file;
  const std::string& path = file.Write(data, size);
  try {
    (void)scw::io::ReadCsvTable(path, {"x_m", "y_m"}, {"friction_scale"});
  } catch (const ConfigError&) {
  }
  try {
    const scw::plant::Track t = scw::tuning::LoadTrackCsv(path);
    FUZZ_CHECK(std::isfinite(t.length()) && t.length() > 0.0, "bad length");
    for (std::size_t i = 0; i < t.size(); i += 1 + t.size() / 16) {
      FUZZ_CHECK(std::isfinite(t.x()[i]) && std::isfinite(t.y()[i]) &&
                     std::isfinite(t.curvature()[i]) && std::isfinite(t.heading()[i]),
                 "non-finite node " + std::to_string(i));
      const auto pr = t.Project(t.x()[i], t.y()[i], t.heading()[i]);
      FUZZ_CHECK(std::isfinite(pr.s) && std::isfinite(pr.n), "non-finite projection");
    }
  } catch (const ConfigError&) {
  }
  return 0;
}

SCW_FUZZ_ENTRY(scw::fuzz::FuzzTrackCsv)
