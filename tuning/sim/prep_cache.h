// The preparation cache on disk: results of the expensive, pure steps of scenario preparation
// (the plant's g-g-v table, the racing line's optimised offsets) kept between runs and shared by
// the processes of an MPI run, so that a second tune, sweep or rank does not compute them again.
//
// Content-keyed: an entry's name is the SHA-256 of its kind, the exact text of every input (the
// reference cache's keys, controller/planning/reference_cache.h: the vehicle's schema
// fingerprint, the track's node numbers, the options)
// and the identity of the program (the SHA-256 of the running executable and the NLopt version),
// so a rebuilt scw or another input never reads an older result. Values are arrays of doubles
// stored exactly (hexadecimal floating point), so a result read from the cache is bit for bit the
// one computed: outputs do not depend on whether the cache was warm.
//
// Where: $SCW_CACHE_DIR if set ("off" or empty: no cache), else $XDG_CACHE_HOME/scw, else
// $HOME/.cache/scw. Best effort: a folder that cannot be made, a file that cannot be written, read
// or parsed (truncated, foreign, another version) is treated as a miss and never an error; files
// are written atomically (a reader sees a whole entry or none), so concurrent processes may write
// the same entry. Entries are small (a table: a few kB; a line: ~50 kB); nothing removes them
// (delete the folder to reclaim the space).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "controller/planning/reference_cache.h"

namespace scw::tuning {

using CachedArrays = controller::planning::ReferenceStore::Arrays;

/// The running program's identity: the SHA-256 of its executable (/proc/self/exe) and the NLopt
/// version; "" when the executable cannot be read. Computed once per process.
const std::string& ProgramIdentity();

class PrepCache : public controller::planning::ReferenceStore {
 public:
  /// The process's cache, configured from the environment on first use.
  static const PrepCache& Process();
  /// A cache in `folder` ("" = disabled) with `program` as the program identity.
  PrepCache(std::string folder, std::string program);

  bool enabled() const { return !folder_.empty(); }
  const std::string& folder() const { return folder_; }

  /// The arrays stored under (kind, key), or nothing (disabled, absent, unreadable, malformed).
  std::optional<CachedArrays> Load(const std::string& kind, const std::string& key) const override;
  /// Stores the arrays under (kind, key); failures are ignored.
  void Store(const std::string& kind, const std::string& key,
             const CachedArrays& arrays) const override;

  /// The file an entry lives in (for tests and docs).
  std::string PathOf(const std::string& kind, const std::string& key) const;

 private:
  std::string folder_;
  std::string program_;
};

/// The cache folder the environment asks for ("" = none); see the header comment.
std::string PrepCacheFolderFromEnvironment();

}  // namespace scw::tuning
