#pragma once

#include <filesystem>
#include <string>

namespace scw::test {

/// ../shared/data/<rel> if present, else empty (tests then skip with a message).
inline std::string SharedData(const std::string& rel) {
  const std::filesystem::path p = std::filesystem::path(SCW_SHARED_DIR) / "data" / rel;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

/// The repository's own files (params/…, docs/…).
inline std::string SourcePath(const std::string& rel) {
  return (std::filesystem::path(SCW_SOURCE_DIR) / rel).string();
}

}  // namespace scw::test
