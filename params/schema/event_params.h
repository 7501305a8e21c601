// Critical situations of a scenario: faults of the motion controller, grip events and gusts that
// happen to the simulated car at a given place (and lap), so that a scenario can put the car into
// the moments its stability control exists for (issue 16 §2). Every block is a set of equally long
// lists, one element per event, like friction patches; all lists empty = no event (the default).
//
// Where an event happens, for every block:
//   corner[i] = 0: s[i] is the arc length along the track's centre line [m];
//   corner[i] = k ≥ 1: s[i] is an offset [m] from the apex (smallest radius) of corner k, as
//   numbered by `scw track info` (plant/track/corners.h); > 0 after the apex. A power-on fault at
//   the exit of corner 3 is {corner: [3], s: [60]}.
//   lap[i] (timed events) = the lap on which it happens (1 = the first lap after the flying start),
//   0 = on every lap.
// A timed event begins when the car's centre of gravity passes that place and lasts `duration`
// seconds of simulated time. Only the simulated car (and for faults the request path) is affected;
// the planner and the motion controller do not know the event is coming.
#pragma once

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

namespace detail {

/// The place fields every event block shares (corner, s and, for timed events, lap).
template <class List, class V>
void VisitEventPlace(List& corner, List& s, V& v) {
  v.Field(corner, {.key = "corner",
                   .unit = "-",
                   .lo = 0.0,
                   .hi = 1000.0,
                   .doc = "Per event: 0 = `s` is an arc length on the centre line; k >= 1 = `s` "
                          "is an offset from the apex of corner k (numbering of `scw track "
                          "info`), > 0 after the apex.",
                   .optional = true,
                   .min_size = 0});
  v.Field(s, {.key = "s",
              .unit = "m",
              .lo = -1e5,
              .hi = 1e5,
              .doc = "Per event: arc length [m] (corner 0) or offset from the corner's apex.",
              .optional = true,
              .min_size = 0});
}

template <class List, class V>
void VisitEventLap(List& lap, V& v) {
  v.Field(lap, {.key = "lap",
                .unit = "-",
                .lo = 0.0,
                .hi = 100.0,
                .doc = "Per event: the lap it happens on (1 = the first lap after the flying "
                       "start); 0 = every lap.",
                .optional = true,
                .min_size = 0});
}

template <class List, class V>
void VisitEventDuration(List& duration, V& v) {
  v.Field(duration, {.key = "duration",
                     .unit = "s",
                     .lo = 0.001,
                     .hi = 1000.0,
                     .doc = "Per event: how long it lasts once the car passes the place.",
                     .optional = true,
                     .min_size = 0});
}

/// Rules shared by every block: one value per event in every list, whole corner and lap numbers.
inline void CheckEventLists(
    const std::vector<double>& corner, const std::vector<double>& s,
    const std::vector<std::pair<const char*, const std::vector<double>*>>& others,
    const std::vector<double>* lap, Problems& pr) {
  const std::size_t n = s.size();
  auto same = [&](const std::vector<double>& a, const char* key) {
    if (a.size() != n)
      pr.Add(key, "needs one value per event (" + std::to_string(n) + " as in s), has " +
                      std::to_string(a.size()));
  };
  same(corner, "corner");
  for (const auto& [key, list] : others) same(*list, key);
  if (lap) same(*lap, "lap");
  auto whole = [&](const std::vector<double>& a, const char* key) {
    for (std::size_t i = 0; i < a.size(); ++i)
      if (std::isfinite(a[i]) && a[i] != std::floor(a[i]))
        pr.Add(key, "element [" + std::to_string(i) + "] must be a whole number");
  };
  whole(corner, "corner");
  if (lap) whole(*lap, "lap");
}

}  // namespace detail

/// A timed event with one magnitude per event (the kinds below say which): place, lap, duration
/// and `value`, whose key, unit, bounds and meaning come from Kind::kValue.
template <class Kind>
struct TimedEvents {
  std::vector<double> corner{}, s{}, lap{}, duration{}, value{};
  template <class Self, class V>
  static void Visit(Self& x, V& v) {
    detail::VisitEventPlace(x.corner, x.s, v);
    detail::VisitEventLap(x.lap, v);
    detail::VisitEventDuration(x.duration, v);
    v.Field(x.value, Kind::kValue);
  }
  static void CrossCheck(const TimedEvents& p, Problems& pr) {
    detail::CheckEventLists(p.corner, p.s,
                            {{"duration", &p.duration}, {Kind::kValue.key.data(), &p.value}},
                            &p.lap, pr);
  }
};

/// The motion controller's throttle request overridden (the paper's real-car event: too much
/// throttle out of a corner): throttle = value, brake pressures 0, and the longitudinal force
/// request the stability controller sees = the drive force of that throttle in the engaged gear.
struct ThrottleFault {
  static constexpr Meta kValue{.key = "value",
                               .unit = "-",
                               .lo = 0.0,
                               .hi = 1.0,
                               .doc = "Per event: the throttle request while it lasts (0..1).",
                               .optional = true,
                               .min_size = 0};
};
using ThrottleFaults = TimedEvents<ThrottleFault>;

/// A steering-request offset added to the motion controller's output: a spike (short duration)
/// or a bias (long duration).
struct SteerFault {
  static constexpr Meta kValue{.key = "value",
                               .unit = "rad",
                               .lo = -0.5,
                               .hi = 0.5,
                               .doc = "Per event: offset added to the steering request (> 0 left).",
                               .optional = true,
                               .min_size = 0};
};
using SteerFaults = TimedEvents<SteerFault>;

/// Sudden loss of rear grip (cold or worn rear tyres): both rear tyres' friction multiplied by
/// `factor` (the member `value`) while the event lasts.
struct RearGripLoss {
  static constexpr Meta kValue{
      .key = "factor",
      .unit = "-",
      .lo = 0.05,
      .hi = 2.0,
      .doc = "Per event: friction factor of both rear tyres while it lasts.",
      .optional = true,
      .min_size = 0};
};
using RearGripEvents = TimedEvents<RearGripLoss>;

/// Late braking: the reference speed profile's brake point moved later by `distance`, the speed
/// before the corner reached over the shorter remaining distance (the motion controller asks for
/// more deceleration than planned). Applies on every lap to the braking zone whose slowest point
/// lies nearest to the place.
struct LateBraking {
  std::vector<double> corner{}, s{}, distance{};
  template <class Self, class V>
  static void Visit(Self& x, V& v) {
    detail::VisitEventPlace(x.corner, x.s, v);
    v.Field(x.distance, {.key = "distance",
                         .unit = "m",
                         .lo = 0.0,
                         .hi = 500.0,
                         .doc = "Per event: how much later the braking begins (at most 80 % of "
                                "the braking zone's length).",
                         .optional = true,
                         .min_size = 0});
  }
  static void CrossCheck(const LateBraking& p, Problems& pr) {
    detail::CheckEventLists(p.corner, p.s, {{"distance", &p.distance}}, nullptr, pr);
  }
};

/// A gust of wind: speed over the ground rising and falling as 1 − cos over `duration`, blowing
/// from `from_deg` relative to the track's direction at the place (0 = headwind, 90 = from the
/// left, pushing the car to the right, −90 = from the right).
struct Gusts {
  std::vector<double> corner{}, s{}, lap{}, duration{}, speed{}, from_deg{};
  template <class Self, class V>
  static void Visit(Self& x, V& v) {
    detail::VisitEventPlace(x.corner, x.s, v);
    detail::VisitEventLap(x.lap, v);
    detail::VisitEventDuration(x.duration, v);
    v.Field(x.speed, {.key = "speed",
                      .unit = "m/s",
                      .lo = 0.0,
                      .hi = 80.0,
                      .doc = "Per gust: peak wind speed over the ground.",
                      .optional = true,
                      .min_size = 0});
    v.Field(x.from_deg, {.key = "from_deg",
                         .unit = "deg",
                         .lo = -180.0,
                         .hi = 180.0,
                         .doc = "Per gust: where it comes from, relative to the track's "
                                "direction (0 headwind, 90 from the left, -90 from the right).",
                         .optional = true,
                         .min_size = 0});
  }
  static void CrossCheck(const Gusts& p, Problems& pr) {
    detail::CheckEventLists(
        p.corner, p.s, {{"duration", &p.duration}, {"speed", &p.speed}, {"from_deg", &p.from_deg}},
        &p.lap, pr);
  }
};

struct ScenarioEvents {
  ThrottleFaults throttle{};
  SteerFaults steer{};
  LateBraking late_braking{};
  RearGripEvents rear_grip{};
  Gusts gust{};

  bool empty() const {
    return throttle.s.empty() && steer.s.empty() && late_braking.s.empty() && rear_grip.s.empty() &&
           gust.s.empty();
  }

  template <class Self, class V>
  static void Visit(Self& x, V& v) {
    v.Nested("throttle", x.throttle, true);
    v.Nested("steer", x.steer, true);
    v.Nested("late_braking", x.late_braking, true);
    v.Nested("rear_grip", x.rear_grip, true);
    v.Nested("gust", x.gust, true);
  }
};

}  // namespace scw::params
