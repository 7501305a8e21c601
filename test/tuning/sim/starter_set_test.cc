// The starter scenario set of a track (tuning/sim/starter_set.h): every scenario loads, each event
// sits at the corners its rule ranks first, held-out scenarios use other corners, and the file's
// text reads back to the same set.
#include "tuning/sim/starter_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "params/schema/field.h"
#include "plant/track/corners.h"
#include "plant/track/yas_north.h"

namespace scw::tuning {
namespace {

StarterSetOptions Options() {
  StarterSetOptions o;
  o.name = "yas_starter";
  o.track_ref = "yas_north";
  return o;
}

/// The corner numbers of the scenarios of one event in a list ("power_on_c3" -> 3).
std::vector<int> CornersOf(const std::vector<ScenarioEntry>& list, const std::string& event) {
  std::vector<int> out;
  for (const auto& e : list)
    if (e.name.rfind(event + "_c", 0) == 0)
      out.push_back(std::stoi(e.name.substr(event.size() + 2)));
  return out;
}

const StarterEventPlaces& Places(const StarterSet& s, const std::string& event) {
  for (const auto& p : s.places)
    if (p.event == event) return p;
  throw std::runtime_error("no event " + event);
}

/// A stadium: two straights joined by two half circles of radius r (anticlockwise), 1 m spacing.
plant::Track Stadium(double r, double straight) {
  std::vector<double> x, y;
  for (int k = 0; k < static_cast<int>(straight); ++k) x.push_back(k), y.push_back(0.0);
  const int arc = static_cast<int>(M_PI * r);
  for (int k = 0; k < arc; ++k) {
    const double a = -M_PI / 2 + M_PI * k / arc;
    x.push_back(straight + r * std::cos(a));
    y.push_back(r + r * std::sin(a));
  }
  for (int k = 0; k < static_cast<int>(straight); ++k)
    x.push_back(straight - k), y.push_back(2 * r);
  for (int k = 0; k < arc; ++k) {
    const double a = M_PI / 2 + M_PI * k / arc;
    x.push_back(r * std::cos(a));
    y.push_back(r + r * std::sin(a));
  }
  const std::vector<double> w(x.size(), 6.0);
  return plant::Track::FromPoints(x, y, w, w, {}, {}, "stadium", "test");
}

TEST(StarterSetTest, EveryScenarioOfTheYasSetLoads) {
  const plant::Track track = plant::YasNorthTrack();
  const StarterSet s = MakeStarterSet(track, Options());
  EXPECT_EQ(s.set.training.size(), 2u + 3u * 2u);
  EXPECT_EQ(s.set.held_out.size(), 1u + 3u * 1u);
  for (const auto* list : {&s.set.training, &s.set.held_out})
    for (const ScenarioEntry& e : *list) {
      SCOPED_TRACE(e.name);
      const params::ScenarioParams p = LoadEntry(e, "");
      EXPECT_EQ(p.track, "yas_north");
      EXPECT_EQ(p.laps, 1);
      EXPECT_TRUE(p.kind == "clean" || p.kind == "critical");
    }
}

TEST(StarterSetTest, EachEventSitsAtTheCornersItsRuleRanksFirst) {
  const plant::Track track = plant::YasNorthTrack();
  const StarterSet s = MakeStarterSet(track, Options());
  std::vector<plant::Corner> eligible;
  for (const auto& c : s.corners)
    if (!plant::IsShortCorner(c, track) && !plant::IsKink(c)) eligible.push_back(c);
  ASSERT_GE(eligible.size(), 4u);
  auto radius = [&](int n) { return s.corners[static_cast<std::size_t>(n - 1)].min_radius; };
  // Power-on: no corner left out is slower than a chosen one; rear grip: none is faster.
  const auto& power = Places(s, "power_on");
  const auto& grip = Places(s, "rear_grip_loss");
  for (const auto& c : eligible) {
    const bool in_power = std::count(power.training.begin(), power.training.end(), c.number) > 0;
    const bool in_grip = std::count(grip.training.begin(), grip.training.end(), c.number) > 0;
    for (int t : power.training)
      EXPECT_TRUE(in_power || c.min_radius >= radius(t)) << "corner " << c.number;
    for (int t : grip.training)
      EXPECT_TRUE(in_grip || c.min_radius <= radius(t)) << "corner " << c.number;
  }
  // The scenarios are where the places say.
  for (const auto& p : s.places) {
    EXPECT_EQ(CornersOf(s.set.training, p.event), p.training) << p.event;
    EXPECT_EQ(CornersOf(s.set.held_out, p.event), p.held_out) << p.event;
  }
}

TEST(StarterSetTest, HeldOutScenariosUseOtherCornersAndOtherMagnitudes) {
  const StarterSet s = MakeStarterSet(plant::YasNorthTrack(), Options());
  for (const auto& p : s.places) {
    ASSERT_EQ(p.held_out.size(), 1u) << p.event;
    for (int c : p.held_out)
      EXPECT_EQ(std::count(p.training.begin(), p.training.end(), c), 0) << p.event;
  }
  const ScenarioEntry& held = s.set.held_out[1];  // the first held-out event scenario
  const ScenarioEntry& trained = s.set.training[2];
  ASSERT_EQ(held.name.substr(0, 8), "power_on");
  ASSERT_EQ(trained.name.substr(0, 8), "power_on");
  EXPECT_NE(LoadEntry(held, "").events.throttle.value,
            LoadEntry(trained, "").events.throttle.value);
}

TEST(StarterSetTest, TheFileReadsBackToTheSameSet) {
  const plant::Track track = plant::YasNorthTrack();
  const StarterSet s = MakeStarterSet(track, Options());
  const std::string text = StarterSetYaml(s, track);
  EXPECT_EQ(text.rfind("# Starter scenario set for", 0), 0u);
  const ScenarioSet back = ScenarioSet::FromYamlText(text, "set.yaml");
  EXPECT_EQ(back.name, "yas_starter");
  ASSERT_EQ(back.training.size(), s.set.training.size());
  ASSERT_EQ(back.held_out.size(), s.set.held_out.size());
  for (std::size_t i = 0; i < back.training.size(); ++i) {
    EXPECT_EQ(back.training[i].name, s.set.training[i].name);
    EXPECT_EQ(back.training[i].overrides, s.set.training[i].overrides);
  }
  EXPECT_EQ(back.ToYaml(), s.set.ToYaml());
}

TEST(StarterSetTest, AVehicleFileIsNamedInEveryScenario) {
  StarterSetOptions o = Options();
  o.vehicle_ref = "car.yaml";
  const StarterSet s = MakeStarterSet(plant::YasNorthTrack(), o);
  for (const auto* list : {&s.set.training, &s.set.held_out})
    for (const ScenarioEntry& e : *list)
      EXPECT_EQ(std::count(e.overrides.begin(), e.overrides.end(), "vehicle=car.yaml"), 1)
          << e.name;
}

TEST(StarterSetTest, ATrackWithTwoCornersSaysWhatItCouldNotHoldOut) {
  const plant::Track track = Stadium(60.0, 300.0);
  ASSERT_EQ(plant::FindCorners(track).size(), 2u);
  StarterSetOptions o = Options();
  o.track_ref = "stadium.csv";
  const StarterSet two = MakeStarterSet(track, o);
  for (const auto& p : two.places) {
    EXPECT_EQ(p.training.size(), 2u) << p.event;
    EXPECT_TRUE(p.held_out.empty()) << p.event;
    ASSERT_EQ(p.note.size(), 1u) << p.event;
    EXPECT_EQ(p.note[0], "no other corner left to hold out");
  }
  EXPECT_NE(StarterSetYaml(two, track).find("no other corner left to hold out"), std::string::npos);
  o.training_corners = 1;
  const StarterSet one = MakeStarterSet(track, o);
  for (const auto& p : one.places) {
    ASSERT_EQ(p.training.size(), 1u) << p.event;
    ASSERT_EQ(p.held_out.size(), 1u) << p.event;
    EXPECT_NE(p.training[0], p.held_out[0]) << p.event;
  }
}

TEST(StarterSetTest, ATrackWithoutCornersOrBadOptionsIsRefused) {
  // A circle of radius 400 m: curved everywhere, but never below the 250 m of a corner.
  std::vector<double> x, y;
  for (int k = 0; k < 2513; ++k) {
    const double a = 2 * M_PI * k / 2513.0;
    x.push_back(400 * std::cos(a));
    y.push_back(400 * std::sin(a));
  }
  const std::vector<double> w(x.size(), 6.0);
  const plant::Track circle = plant::Track::FromPoints(x, y, w, w, {}, {}, "circle", "test");
  EXPECT_THROW(MakeStarterSet(circle, Options()), ConfigError);
  StarterSetOptions o = Options();
  o.training_corners = 0;
  EXPECT_THROW(MakeStarterSet(plant::YasNorthTrack(), o), ConfigError);
  o = Options();
  o.held_out_corners = -1;
  EXPECT_THROW(MakeStarterSet(plant::YasNorthTrack(), o), ConfigError);
}

}  // namespace
}  // namespace scw::tuning
