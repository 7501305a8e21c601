// A scenario's critical situations (params/schema/event_params.h) resolved against its track, and
// what they do during a closed-loop run.
//
// Timed events (throttle, steer, rear grip, gust) fire when the car's centre of gravity passes
// their place on their lap (the control tick at which the projected arc length crosses it) and
// last `duration` seconds. While active:
//   throttle   the motion controller's throttle request = value, its brake pressures 0, its
//              long_fx = the model's drive force of that throttle (overlapping: the last wins)
//   steer      steering request += value (overlapping: summed)
//   rear grip  both rear wheels' friction factor ×= factor (overlapping: multiplied)
//   gust       wind over the ground += speed · ½(1 − cos 2πτ/duration) from `from_deg` relative to
//              the track's direction at the place (overlapping: summed)
// Late braking acts before the run, on the reference (controller/planning/late_braking.h, which
// also places events: EventPlace).
//
// An EventSchedule is immutable after construction; the per-run State holds the firing times.
#pragma once

#include <string>
#include <vector>

#include "params/schema/event_params.h"
#include "plant/track/track.h"

namespace scw::tuning {

class EventSchedule {
 public:
  enum class Type { kThrottle, kSteer, kRearGrip, kGust };
  struct Event {
    Type type = Type::kThrottle;
    double s = 0.0;         ///< [m] place on the track
    int lap = 0;            ///< 1-based, 0 = every lap
    double duration = 0.0;  ///< [s]
    double value = 0.0;     ///< throttle, steer offset [rad], grip factor, gust speed [m/s]
    double wind_dir_x = 0.0, wind_dir_y = 0.0;  ///< gust: unit vector the wind blows towards
  };
  struct State {
    std::vector<double> t_start;  ///< per event: time it last fired, or −inf
    std::vector<int> fired_lap;   ///< per event: lap it last fired on (0 = never)
  };

  /// Throws ConfigError (key path events.<block>.<field>) for a corner the track does not have.
  EventSchedule(const params::ScenarioEvents& events, const plant::Track& track);

  bool empty() const { return events_.empty(); }
  const std::vector<Event>& events() const { return events_; }
  State MakeState() const;

  /// Fires the events whose place lies in (s_prev, s] (track arc lengths, wrapping; a move of
  /// more than half the track fires nothing) on `lap` (1-based) at time t.
  void Update(double s_prev, double s, int lap, double t, State* st) const;

  /// What is active at time t (see the header comment); `throttle` counts only with
  /// `throttle_fault`.
  struct Active {
    double throttle = 0.0;
    bool throttle_fault = false;
    double steer_offset = 0.0;
    double rear_grip = 1.0;
    double wind_x = 0.0, wind_y = 0.0;
    unsigned mask = 0;  ///< bit 0 throttle, 1 steer, 2 rear grip, 3 gust
  };
  Active At(double t, const State& st) const;

 private:
  std::vector<Event> events_;
  double length_ = 0.0;
};

}  // namespace scw::tuning
