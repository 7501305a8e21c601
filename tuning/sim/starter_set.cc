#include "tuning/sim/starter_set.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <utility>

#include "params/io/write.h"

namespace scw::tuning {
namespace {

/// One kind of critical event: its ranking of the corners and its overrides.
struct EventKind {
  const char* name;
  const char* rule;
  /// Larger = earlier in the ranking.
  std::function<double(const plant::Corner&)> score;
  /// The overrides of one scenario at corner `c` (training or held out).
  std::function<std::vector<std::string>(int c, bool held_out)> overrides;
};

std::string List(int value) { return "[" + std::to_string(value) + "]"; }

/// Distance from the end of the corner before corner i to its start [m]: the straight a car
/// brakes on into it (the rest of the lap when the track has one corner).
double StraightBefore(const std::vector<plant::Corner>& corners, std::size_t i,
                      const plant::Track& track) {
  if (corners.size() == 1) return track.length() - plant::CornerLength(corners[i], track);
  const plant::Corner& prev = corners[(i + corners.size() - 1) % corners.size()];
  double d = std::fmod(corners[i].s_from - (prev.s_to + track.step()), track.length());
  if (d < 0.0) d += track.length();
  return d;
}

std::string Join(const std::vector<int>& corners) {
  std::string out;
  for (int c : corners) out += (out.empty() ? "c" : ", c") + std::to_string(c);
  return out.empty() ? "none" : out;
}

}  // namespace

StarterSet MakeStarterSet(const plant::Track& track, const StarterSetOptions& o) {
  Problems pr;
  if (o.training_corners < 1 || o.training_corners > 20)
    pr.Add("training corners", std::to_string(o.training_corners) + " is outside [1, 20]");
  if (o.held_out_corners < 0 || o.held_out_corners > 20)
    pr.Add("held-out corners", std::to_string(o.held_out_corners) + " is outside [0, 20]");
  if (!pr.empty()) throw ConfigError("starter set", pr.items());

  StarterSet out;
  out.corners = plant::FindCorners(track);
  if (out.corners.empty())
    throw ConfigError(track.name(), "corners",
                      "no corner (a radius below 250 m) on this track: a starter set places its "
                      "events at corners; write the set by hand (docs/parameters-scenario-set.md)");
  // Minor corners only when nothing else is left.
  std::vector<std::size_t> eligible;
  for (std::size_t i = 0; i < out.corners.size(); ++i) {
    const plant::Corner& c = out.corners[i];
    if (plant::IsShortCorner(c, track) || plant::IsKink(c))
      out.minor.push_back(c.number);
    else
      eligible.push_back(i);
  }
  if (eligible.empty())
    for (std::size_t i = 0; i < out.corners.size(); ++i) eligible.push_back(i);

  std::vector<double> straight(out.corners.size());
  for (std::size_t i = 0; i < out.corners.size(); ++i)
    straight[i] = StraightBefore(out.corners, i, track);

  auto common = [&](const char* kind) {
    std::vector<std::string> s = {"track=" + o.track_ref};
    if (!o.vehicle_ref.empty()) s.push_back("vehicle=" + o.vehicle_ref);
    s.push_back(std::string("kind=") + kind);
    s.push_back("laps=1");
    return s;
  };
  const std::vector<EventKind> kinds = {
      {"power_on", "smallest radius first (slow exits)",
       [](const plant::Corner& c) { return -c.min_radius; },
       [](int c, bool held_out) {
         return std::vector<std::string>{
             "events.throttle.corner=" + List(c),
             held_out ? "events.throttle.s=[10]" : "events.throttle.s=[20]",
             "events.throttle.lap=[1]",
             held_out ? "events.throttle.duration=[0.8]" : "events.throttle.duration=[1.0]",
             held_out ? "events.throttle.value=[0.9]" : "events.throttle.value=[1.0]"};
       }},
      {"late_braking", "longest straight before the corner first (highest entry speed)",
       [&](const plant::Corner& c) { return straight[static_cast<std::size_t>(c.number - 1)]; },
       [](int c, bool held_out) {
         return std::vector<std::string>{
             "events.late_braking.corner=" + List(c), "events.late_braking.s=[0]",
             held_out ? "events.late_braking.distance=[15]" : "events.late_braking.distance=[20]"};
       }},
      {"rear_grip_loss", "largest radius first (fast corners)",
       [](const plant::Corner& c) { return c.min_radius; },
       [](int c, bool held_out) {
         return std::vector<std::string>{
             "events.rear_grip.corner=" + List(c), "events.rear_grip.s=[0]",
             "events.rear_grip.lap=[1]", "events.rear_grip.duration=[1.5]",
             held_out ? "events.rear_grip.factor=[0.7]" : "events.rear_grip.factor=[0.65]"};
       }},
  };

  ScenarioSet& set = out.set;
  set.name = o.name;
  set.cost = ScenarioSet::Default().cost;  // the built-in set's weights
  auto clean = [&](const std::string& gg) {
    ScenarioEntry e;
    e.name = "clean_gg" + gg;
    e.overrides = common("clean");
    e.overrides.push_back("gg_scale=" + gg);
    return e;
  };
  set.training.push_back(clean("1.1"));
  set.training.push_back(clean("1.2"));
  set.held_out.push_back(clean("1.15"));

  for (const EventKind& k : kinds) {
    std::vector<std::size_t> ranked = eligible;
    std::stable_sort(ranked.begin(), ranked.end(), [&](std::size_t a, std::size_t b) {
      return k.score(out.corners[a]) > k.score(out.corners[b]);
    });
    StarterEventPlaces places;
    places.event = k.name;
    places.rule = k.rule;
    const std::size_t n_train = std::min<std::size_t>(o.training_corners, ranked.size());
    for (std::size_t r = 0; r < ranked.size(); ++r) {
      const int c = out.corners[ranked[r]].number;
      if (r < n_train)
        places.training.push_back(c);
      else if (static_cast<int>(places.held_out.size()) < o.held_out_corners)
        places.held_out.push_back(c);
    }
    if (n_train < static_cast<std::size_t>(o.training_corners))
      places.note.push_back("only " + std::to_string(n_train) + " corner(s) to train on");
    if (static_cast<int>(places.held_out.size()) < o.held_out_corners)
      places.note.push_back(places.held_out.empty()
                                ? "no other corner left to hold out"
                                : "only " + std::to_string(places.held_out.size()) +
                                      " other corner(s) left to hold out");
    auto entry = [&](int c, bool held_out) {
      ScenarioEntry e;
      e.name = std::string(k.name) + "_c" + std::to_string(c);
      e.overrides = common("critical");
      e.overrides.push_back("abort.max_lateral_error=10");
      for (auto& s : k.overrides(c, held_out)) e.overrides.push_back(std::move(s));
      return e;
    };
    for (int c : places.training) set.training.push_back(entry(c, false));
    for (int c : places.held_out) set.held_out.push_back(entry(c, true));
    out.places.push_back(std::move(places));
  }
  return out;
}

std::string StarterSetYaml(const StarterSet& starter, const plant::Track& track) {
  std::ostringstream h;
  h << "# Starter scenario set for " << track.name() << " ("
    << params::FormatNumber(std::round(track.length() * 10.0) / 10.0) << " m, "
    << starter.corners.size() << " corners), written by scw scenarios init.\n"
    << "# Corners as scw track info numbers them; events name them (events.*.corner).\n";
  if (!starter.minor.empty())
    h << "# Left out as short or kink corners: " << Join(starter.minor) << ".\n";
  for (const StarterEventPlaces& p : starter.places) {
    h << "#   " << p.event << ": " << p.rule << "; training " << Join(p.training) << ", held out "
      << Join(p.held_out);
    for (const auto& n : p.note) h << "; " << n;
    h << ".\n";
  }
  h << "# Held-out scenarios (other corners, other magnitudes) are never tuned on. Edit freely;\n"
    << "# check which subsystem each scenario exercises before a long tune:\n"
    << "#   scw tune --scenarios THIS_FILE --check-set\n"
    << "# Format: docs/parameters-scenario-set.md; events: docs/scenarios.md.\n";
  return h.str() + starter.set.ToYaml();
}

}  // namespace scw::tuning
