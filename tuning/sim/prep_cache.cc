#include "tuning/sim/prep_cache.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <nlopt.hpp>

#include "params/io/atomic_file.h"
#include "params/io/sha256.h"
#include "params/io/yaml_doc.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMagic = "scw-prep-cache 1";

std::string HexDouble(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

}  // namespace

const std::string& ProgramIdentity() {
  static const std::string identity = [] {
    std::ifstream exe("/proc/self/exe", std::ios::binary);
    if (!exe) return std::string();
    const std::string bytes((std::istreambuf_iterator<char>(exe)),
                            std::istreambuf_iterator<char>());
    if (bytes.empty()) return std::string();
    return io::Sha256Hex(bytes) + " nlopt " + std::to_string(nlopt::version_major()) + "." +
           std::to_string(nlopt::version_minor()) + "." + std::to_string(nlopt::version_bugfix());
  }();
  return identity;
}

std::string PrepCacheFolderFromEnvironment() {
  if (const char* dir = std::getenv("SCW_CACHE_DIR")) {
    const std::string d = dir;
    return d == "off" ? std::string() : d;
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return (fs::path(xdg) / "scw").string();
  if (const char* home = std::getenv("HOME"); home && *home)
    return (fs::path(home) / ".cache" / "scw").string();
  return "";
}

const PrepCache& PrepCache::Process() {
  static const PrepCache cache = [] {
    std::string folder = PrepCacheFolderFromEnvironment();
    std::string program = folder.empty() ? std::string() : ProgramIdentity();
    if (program.empty()) folder.clear();
    return PrepCache(std::move(folder), std::move(program));
  }();
  return cache;
}

PrepCache::PrepCache(std::string folder, std::string program)
    : folder_(std::move(folder)), program_(std::move(program)) {}

std::string PrepCache::PathOf(const std::string& kind, const std::string& key) const {
  const std::string digest = io::Sha256Hex(kind + "\n" + program_ + "\n" + key);
  return (fs::path(folder_) / (kind + "-" + digest + ".txt")).string();
}

std::optional<CachedArrays> PrepCache::Load(const std::string& kind, const std::string& key) const {
  if (!enabled()) return std::nullopt;
  std::ifstream in(PathOf(kind, key));
  if (!in) return std::nullopt;
  // Line 1: magic and kind; line 2: the number of arrays; then per array its length and its
  // values on one line; last line "end" (a whole file, not a torn one).
  std::string line;
  if (!std::getline(in, line) || line != std::string(kMagic) + " " + kind) return std::nullopt;
  std::size_t count = 0;
  if (!std::getline(in, line) || std::sscanf(line.c_str(), "%zu", &count) != 1 || count > 64)
    return std::nullopt;
  CachedArrays arrays(count);
  for (auto& a : arrays) {
    std::size_t n = 0;
    if (!std::getline(in, line) || std::sscanf(line.c_str(), "%zu", &n) != 1 || n > 10000000)
      return std::nullopt;
    if (!std::getline(in, line)) return std::nullopt;
    std::istringstream values(line);
    std::string word;
    a.reserve(n);
    while (values >> word) {
      double v = 0.0;
      if (!params::ParseDouble(word, &v)) return std::nullopt;  // strtod: %a reads back exactly
      a.push_back(v);
    }
    if (a.size() != n) return std::nullopt;
  }
  if (!std::getline(in, line) || line != "end") return std::nullopt;
  return arrays;
}

void PrepCache::Store(const std::string& kind, const std::string& key,
                      const CachedArrays& arrays) const {
  if (!enabled()) return;
  std::string text = std::string(kMagic) + " " + kind + "\n" + std::to_string(arrays.size()) + "\n";
  for (const auto& a : arrays) {
    text += std::to_string(a.size()) + "\n";
    for (std::size_t i = 0; i < a.size(); ++i) text += (i ? " " : "") + HexDouble(a[i]);
    text += "\n";
  }
  text += "end\n";
  try {
    std::error_code ec;
    fs::create_directories(folder_, ec);
    io::WriteFileAtomic(PathOf(kind, key), text);
  } catch (const std::exception&) {
    // Best effort: the value was computed and is used; only the next run computes it again.
  }
}

}  // namespace scw::tuning
