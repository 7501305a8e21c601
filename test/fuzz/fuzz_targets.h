// The fuzz targets as plain functions, so that the normal test suite (test/hardening) can run the
// committed corpus and every input that once failed through exactly the code the fuzzers run.
// Each returns 0; a refused input is a caught scw::ConfigError, anything else escapes (an
// unexpected exception type, or scw::fuzz::PropertyViolation from FUZZ_CHECK).
#pragma once

#include <cstddef>
#include <cstdint>

namespace scw::fuzz {

int FuzzStabilityParams(const std::uint8_t* data, std::size_t size);
int FuzzPlainYaml(const std::uint8_t* data, std::size_t size);
int FuzzScenarioSet(const std::uint8_t* data, std::size_t size);
int FuzzSpace(const std::uint8_t* data, std::size_t size);
int FuzzTrackCsv(const std::uint8_t* data, std::size_t size);
int FuzzReplayLog(const std::uint8_t* data, std::size_t size);

struct FuzzTarget {
  const char* name;  ///< corpus folder test/fuzz/corpus/<name>, executable fuzz_<name>
  int (*run)(const std::uint8_t*, std::size_t);
};

inline constexpr FuzzTarget kFuzzTargets[] = {
    {"stability_params", &FuzzStabilityParams},
    {"plain_yaml", &FuzzPlainYaml},
    {"scenario_set", &FuzzScenarioSet},
    {"space", &FuzzSpace},
    {"track_csv", &FuzzTrackCsv},
    {"replay_log", &FuzzReplayLog},
};

}  // namespace scw::fuzz
