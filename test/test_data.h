// Shared helpers of the track/trajectory tests: public data paths (skip when absent) and tracks.
#pragma once

#include <filesystem>
#include <string>

namespace scw::test {

/// ../shared/data/<rel> if present, else empty (the test then skips with a message).
inline std::string SharedData(const std::string& rel) {
  const std::filesystem::path p = std::filesystem::path(SCW_SHARED_DIR) / "data" / rel;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

inline std::string SourcePath(const std::string& rel) {
  return (std::filesystem::path(SCW_SOURCE_DIR) / rel).string();
}

inline const char* kYasSmoothed = "tracks/yas_north/track_data_smoothed/yasnorth_3d_smoothed.csv";
inline const char* kMonza = "tracks/racetrack-database/tracks/Monza.csv";

}  // namespace scw::test
