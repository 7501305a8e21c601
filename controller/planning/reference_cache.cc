#include "controller/planning/reference_cache.h"

#include <exception>
#include <utility>

#include "controller/planning/envelope.h"
#include "controller/planning/racing_line.h"
#include "controller/planning/velocity_profile.h"
#include "params/schema/fingerprint.h"

namespace scw::controller::planning {
namespace {

/// The store's arrays of a g-g-v table: its columns in the order of GgvTable::Visit.
ReferenceStore::Arrays GgvToArrays(const GgvTable& t) {
  ReferenceStore::Arrays a;
  params::ForEachField(t, [&](const std::string&, const std::vector<double>& column,
                              const params::Meta&) { a.push_back(column); });
  return a;
}

/// A g-g-v table from the store's arrays (GgvToArrays), if valid.
std::optional<GgvTable> GgvFromArrays(const ReferenceStore::Arrays& a) {
  GgvTable t;
  std::size_t i = 0;
  bool complete = true;
  params::ForEachField(t,
                       [&](const std::string&, std::vector<double>& column, const params::Meta&) {
                         if (i < a.size())
                           column = a[i++];
                         else
                           complete = false;
                       });
  if (!complete || i != a.size()) return std::nullopt;
  try {
    t.Validate("cache");
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return t;
}

void AppendNumbers(const char* name, const std::vector<double>& xs, std::string* out) {
  *out += name;
  *out += "#" + std::to_string(xs.size()) + ":";
  for (double x : xs) *out += " " + params::FormatNumber(x);
  *out += "\n";
}

}  // namespace

template <class T>
std::shared_ptr<const T> ReferenceCache::Memo<T>::Get(const std::string& key,
                                                      const std::function<T()>& make) {
  std::promise<std::shared_ptr<const T>> promise;
  std::shared_future<std::shared_ptr<const T>> result;
  bool first = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto [it, inserted] = items_.try_emplace(key);
    if (inserted) {
      it->second = promise.get_future().share();
      first = true;
    }
    result = it->second;
  }
  if (first) {
    try {
      promise.set_value(std::make_shared<const T>(make()));
    } catch (...) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        items_.erase(key);
      }
      promise.set_exception(std::current_exception());  // waiters see the same error
    }
  }
  return result.get();
}

std::string ReferenceCache::TrackKey(const plant::Track& t) {
  std::string key = "track " + std::to_string(t.name().size()) + ":" + t.name() + "\nlength " +
                    params::FormatNumber(t.length()) + "\n";
  AppendNumbers("s", t.s(), &key);
  AppendNumbers("x", t.x(), &key);
  AppendNumbers("y", t.y(), &key);
  AppendNumbers("heading", t.heading(), &key);
  AppendNumbers("curvature", t.curvature(), &key);
  AppendNumbers("width_left", t.width_left(), &key);
  AppendNumbers("width_right", t.width_right(), &key);
  AppendNumbers("friction", t.friction(), &key);
  return key;
}

std::shared_ptr<const plant::Track> ReferenceCache::Track(
    const std::string& key, const std::function<plant::Track()>& make) {
  return tracks_.Get(key, make);
}

std::shared_ptr<const plant::Track> ReferenceCache::OptimalLine(const plant::Track& track,
                                                                double margin) {
  RacingLineOptions ro;
  ro.margin = margin;
  const std::string key = TrackKey(track) + "margin " + params::FormatNumber(margin) + "\n";
  return lines_.Get(key, [&]() -> plant::Track {
    if (store_ != nullptr) {
      if (const auto hit = store_->Load("line", key); hit && hit->size() == 1) {
        RacingLineOptions known = ro;
        known.known_offset = &hit->front();
        RacingLine line = MinimumCurvatureLine(track, known);
        if (line.status == "known") return std::move(line.line);
      }
    }
    RacingLine line = MinimumCurvatureLine(track, ro);
    if (store_ != nullptr) store_->Store("line", key, {line.offset});
    return std::move(line.line);
  });
}

std::shared_ptr<const GgvTable> ReferenceCache::PlantGgv(const params::VehicleParams& vehicle,
                                                         double brake_bias_front) {
  params::VehicleParams v = vehicle;
  v.sensors.noise = false;  // PlantEnvelope switches noise off itself
  const std::string key = params::Fingerprint(v, "vehicle") +
                          "brake_bias_front=" + params::FormatNumber(brake_bias_front) + "\n";
  return ggv_.Get(key, [&] {
    if (store_ != nullptr)
      if (const auto hit = store_->Load("ggv", key))
        if (auto table = GgvFromArrays(*hit)) return *std::move(table);
    GgvTable table = PlantEnvelope(v, brake_bias_front);
    if (store_ != nullptr) store_->Store("ggv", key, GgvToArrays(table));
    return table;
  });
}

double ReferenceCache::LimitLapTime(const plant::Track& line, const GgvTable& ggv) {
  const std::string key = TrackKey(line) + params::Fingerprint(ggv, "ggv");
  return *limit_laps_.Get(key, [&] {
    // Kept between processes too: a one-shot evaluation would otherwise compute this full
    // velocity profile again in every process, beside the scenario's own.
    if (store_ != nullptr)
      if (const auto hit = store_->Load("limit", key);
          hit && hit->size() == 1 && (*hit)[0].size() == 1)
        return (*hit)[0][0];
    const double t = ComputeVelocityProfile(line, ggv, VelocityProfileOptions{}).lap_time;
    if (store_ != nullptr) store_->Store("limit", key, {{t}});
    return t;
  });
}

}  // namespace scw::controller::planning
