#include "tuning/sim/events.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "controller/planning/late_braking.h"
#include "params/schema/field.h"
#include "plant/track/corners.h"

namespace scw::tuning {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// Forward distance from a to b on a loop of length L, in [0, L).
double Ahead(double a, double b, double length) {
  double d = std::fmod(b - a, length);
  if (d < 0.0) d += length;
  return d;
}

}  // namespace

EventSchedule::EventSchedule(const params::ScenarioEvents& ev, const plant::Track& track)
    : length_(track.length()) {
  const std::vector<plant::Corner> corners =
      ev.empty() ? std::vector<plant::Corner>{} : plant::FindCorners(track);
  // One event per list element of a block; `value` is the block's magnitude list.
  auto add = [&](Type type, const auto& block, const std::vector<double>& value, const char* name) {
    for (std::size_t i = 0; i < block.s.size(); ++i) {
      Event e;
      e.type = type;
      e.s = controller::planning::PlaceOn(track, corners, block.corner[i], block.s[i],
                                          std::string("events.") + name, i);
      e.lap = static_cast<int>(block.lap[i]);
      e.duration = block.duration[i];
      e.value = value[i];
      events_.push_back(e);
    }
  };
  add(Type::kThrottle, ev.throttle, ev.throttle.value, "throttle");
  add(Type::kSteer, ev.steer, ev.steer.value, "steer");
  add(Type::kRearGrip, ev.rear_grip, ev.rear_grip.value, "rear_grip");
  const std::size_t first_gust = events_.size();
  add(Type::kGust, ev.gust, ev.gust.speed, "gust");
  for (std::size_t i = 0; i < ev.gust.s.size(); ++i) {
    Event& e = events_[first_gust + i];
    // The wind comes from (track direction + from_deg) and blows the opposite way.
    const double from = track.PoseAt(e.s).heading + ev.gust.from_deg[i] * kDegToRad;
    e.wind_dir_x = -std::cos(from);
    e.wind_dir_y = -std::sin(from);
  }
}

EventSchedule::State EventSchedule::MakeState() const {
  State st;
  st.t_start.assign(events_.size(), -std::numeric_limits<double>::infinity());
  st.fired_lap.assign(events_.size(), 0);
  return st;
}

void EventSchedule::Update(double s_prev, double s, int lap, double t, State* st) const {
  const double moved = Ahead(s_prev, s, length_);
  if (moved <= 0.0 || moved > 0.5 * length_) return;
  for (std::size_t i = 0; i < events_.size(); ++i) {
    const Event& e = events_[i];
    if (e.lap != 0 && e.lap != lap) continue;
    if (st->fired_lap[i] == lap) continue;
    const double to_place = Ahead(s_prev, e.s, length_);
    if (to_place > 0.0 && to_place <= moved) {
      st->t_start[i] = t;
      st->fired_lap[i] = lap;
    }
  }
}

EventSchedule::Active EventSchedule::At(double t, const State& st) const {
  Active a;
  for (std::size_t i = 0; i < events_.size(); ++i) {
    const Event& e = events_[i];
    const double tau = t - st.t_start[i];
    if (!(tau >= 0.0 && tau < e.duration)) continue;
    switch (e.type) {
      case Type::kThrottle:
        a.throttle = e.value;
        a.throttle_fault = true;
        a.mask |= 1u;
        break;
      case Type::kSteer:
        a.steer_offset += e.value;
        a.mask |= 2u;
        break;
      case Type::kRearGrip:
        a.rear_grip *= e.value;
        a.mask |= 4u;
        break;
      case Type::kGust: {
        const double w = e.value * 0.5 * (1.0 - std::cos(2.0 * M_PI * tau / e.duration));
        a.wind_x += w * e.wind_dir_x;
        a.wind_y += w * e.wind_dir_y;
        a.mask |= 8u;
        break;
      }
    }
  }
  return a;
}

}  // namespace scw::tuning
