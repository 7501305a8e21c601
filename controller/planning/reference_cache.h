// The preparation cache: one object, owned by whoever prepares many references (the batch
// evaluator, a sweep, a test), that keeps the results of the expensive, pure preparation steps so
// that each is computed once per distinct input:
//   tracks    a loaded track or given raceline per caller key (the loader's: built-in name, file
//             content); building Yas Marina North from its clothoids is a quarter of a preparation
//   lines     the minimum-curvature line per track geometry and line options (~1 s)
//   ggv       the plant's g-g-v table per planned vehicle and front brake bias (~1.5 s)
//   limit     the full-limit lap time per line and table (through the store too)
// Keys are exact and derived from the inputs themselves, never from a file format: a vehicle by
// its schema's fingerprint (params/schema/fingerprint.h, noise switch off: the envelope ignores
// it), a track by every number of its nodes. Results are bit for bit those computed without the
// cache.
//
// Thread-safe and single-flight: the first caller of a key computes it outside the lock,
// concurrent callers of that key wait for its result (the cache starts no thread); values are
// immutable once stored; a failed computation is not kept (the next caller tries again, waiters
// get the same error).
//
// Between processes: an optional ReferenceStore (the disk cache, tuning/sim/prep_cache.h) keeps
// the line's optimised offsets and the g-g-v table's columns under the same keys. Planning opens
// no files itself; the store is the caller's.
#pragma once

#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "controller/planning/ggv.h"
#include "params/schema/vehicle_params.h"
#include "plant/track/track.h"

namespace scw::controller::planning {

/// Arrays of doubles kept between processes under (kind, key); see tuning/sim/prep_cache.h.
class ReferenceStore {
 public:
  using Arrays = std::vector<std::vector<double>>;
  virtual ~ReferenceStore() = default;
  /// The arrays stored under (kind, key), or nothing (absent, unreadable: a miss, never an error).
  virtual std::optional<Arrays> Load(const std::string& kind, const std::string& key) const = 0;
  /// Stores the arrays under (kind, key); failures are ignored.
  virtual void Store(const std::string& kind, const std::string& key,
                     const Arrays& arrays) const = 0;
};

class ReferenceCache {
 public:
  /// `store` (may be null: nothing kept between processes) must outlive the cache.
  explicit ReferenceCache(const ReferenceStore* store = nullptr) : store_(store) {}
  ReferenceCache(const ReferenceCache&) = delete;
  ReferenceCache& operator=(const ReferenceCache&) = delete;

  const ReferenceStore* store() const { return store_; }

  /// The track (or given line) under the caller's `key`, made by `make` on the first call.
  std::shared_ptr<const plant::Track> Track(const std::string& key,
                                            const std::function<plant::Track()>& make);
  /// The minimum-curvature line of `track` with `margin` [m] from its edges
  /// (MinimumCurvatureLine's defaults otherwise); its offsets go through the store.
  std::shared_ptr<const plant::Track> OptimalLine(const plant::Track& track, double margin);
  /// The plant's g-g-v table (PlantEnvelope) of `vehicle` with `brake_bias_front` [-]; its columns
  /// go through the store.
  std::shared_ptr<const GgvTable> PlantGgv(const params::VehicleParams& vehicle,
                                           double brake_bias_front);
  /// The lap time [s] of the velocity profile at the table's full limits on `line`; it goes
  /// through the store.
  double LimitLapTime(const plant::Track& line, const GgvTable& ggv);

  /// The exact key of a track: its name and every node's numbers.
  static std::string TrackKey(const plant::Track& track);

 private:
  template <class T>
  class Memo {
   public:
    std::shared_ptr<const T> Get(const std::string& key, const std::function<T()>& make);

   private:
    std::mutex mutex_;
    std::map<std::string, std::shared_future<std::shared_ptr<const T>>> items_;
  };

  const ReferenceStore* store_;
  Memo<plant::Track> tracks_, lines_;
  Memo<GgvTable> ggv_;
  Memo<double> limit_laps_;
};

}  // namespace scw::controller::planning
