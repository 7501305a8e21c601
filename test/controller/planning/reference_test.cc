// PrepareReference and its cache: the reference of a small oval for the default car, each result
// computed once per input in one cache, kept through the store between caches bit for bit, and a
// changed input never served an old result.
#include "controller/planning/reference.h"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <utility>

#include "params/schema/track_params.h"

namespace scw::controller::planning {
namespace {

/// A store in memory that counts what goes through it.
class MemoryStore : public ReferenceStore {
 public:
  std::optional<Arrays> Load(const std::string& kind, const std::string& key) const override {
    ++loads;
    const auto it = items.find(kind + "\n" + key);
    if (it == items.end()) return std::nullopt;
    ++hits;
    return it->second;
  }
  void Store(const std::string& kind, const std::string& key, const Arrays& a) const override {
    items[kind + "\n" + key] = a;
  }
  mutable std::map<std::string, Arrays> items;
  mutable int loads = 0, hits = 0;
};

const plant::Track& Oval() {
  static const plant::Track t = plant::Track::FromDefinition(params::TrackParams{}, "oval");
  return t;
}

bool SamePath(const Path& a, const Path& b) {
  return a.length() == b.length() && a.points() == b.points();
}

TEST(PrepareReference, ComputesEachStepOncePerInputAndKeepsItThroughTheStore) {
  const params::VehicleParams car;
  ReferenceOptions o;
  o.limit_scale = 0.9;
  MemoryStore store;
  ReferenceCache cache(&store);
  const PreparedReference a = PrepareReference(Oval(), car, o, cache);
  ASSERT_TRUE(a.path && a.line && a.ggv);
  EXPECT_NE(a.line->x(), Oval().x());             // the optimised line, not the centre line
  EXPECT_GT(a.ideal_lap_time, a.limit_lap_time);  // 90 % of the limits is slower
  EXPECT_EQ(store.items.size(), 3u);  // the line's offsets, the table, the limit lap time
  // The same inputs: the same objects, nothing loaded again.
  const int loads = store.loads;
  const PreparedReference b = PrepareReference(Oval(), car, o, cache);
  EXPECT_EQ(b.ggv.get(), a.ggv.get());
  EXPECT_EQ(b.line.get(), a.line.get());
  EXPECT_EQ(store.loads, loads);
  // A new cache over the same store: all three come from the store, bit for bit.
  ReferenceCache second(&store);
  const PreparedReference c = PrepareReference(Oval(), car, o, second);
  EXPECT_EQ(store.hits, 3);
  EXPECT_TRUE(*c.ggv == *a.ggv);
  EXPECT_TRUE(SamePath(*c.path, *a.path));
  EXPECT_EQ(c.ideal_lap_time, a.ideal_lap_time);
  EXPECT_EQ(c.limit_lap_time, a.limit_lap_time);
  // And without any cache content the same result.
  ReferenceCache fresh;
  const PreparedReference d = PrepareReference(Oval(), car, o, fresh);
  EXPECT_TRUE(*d.ggv == *a.ggv);
  EXPECT_TRUE(SamePath(*d.path, *a.path));
}

TEST(PrepareReference, AnotherInputIsAnotherEntry) {
  const params::VehicleParams car;
  ReferenceOptions o;
  ReferenceCache cache;
  const PreparedReference a = PrepareReference(Oval(), car, o, cache);
  // Sensor noise does not change the plant's envelope: the same table.
  params::VehicleParams noisy = car;
  noisy.sensors.noise = true;
  EXPECT_EQ(PrepareReference(Oval(), noisy, o, cache).ggv.get(), a.ggv.get());
  // Any value the envelope reads does.
  params::VehicleParams heavy = car;
  heavy.chassis.mass += 1.0;
  EXPECT_NE(PrepareReference(Oval(), heavy, o, cache).ggv.get(), a.ggv.get());
  ReferenceOptions bias = o;
  bias.brake_bias_front += 0.01;
  EXPECT_NE(PrepareReference(Oval(), car, bias, cache).ggv.get(), a.ggv.get());
  // The margin changes the line; the centre line is the track itself.
  ReferenceOptions margin = o;
  margin.line_margin += 0.5;
  EXPECT_NE(PrepareReference(Oval(), car, margin, cache).line.get(), a.line.get());
  ReferenceOptions centre = o;
  centre.line = LineKind::kCentreLine;
  EXPECT_EQ(PrepareReference(Oval(), car, centre, cache).line->x(), Oval().x());
  // A track with other numbers is another track.
  params::TrackParams wider;
  for (double& w : wider.width_left) w += 1.0;
  const plant::Track other = plant::Track::FromDefinition(wider, "oval");
  EXPECT_NE(ReferenceCache::TrackKey(other), ReferenceCache::TrackKey(Oval()));
  EXPECT_NE(PrepareReference(other, car, o, cache).line.get(), a.line.get());
}

TEST(PrepareReference, ALateBrakingCornerTheTrackLacksNamesTheSource) {
  ReferenceOptions o;
  o.line = LineKind::kCentreLine;
  o.late_braking = params::LateBraking{{42.0}, {0.0}, {20.0}};
  o.source = "late.yaml";
  ReferenceCache cache;
  try {
    PrepareReference(Oval(), params::VehicleParams{}, o, cache);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("late.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("events.late_braking.corner"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace scw::controller::planning
