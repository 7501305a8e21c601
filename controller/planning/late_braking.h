// The late-braking reference (a scenario's events.late_braking, params/schema/event_params.h):
// the planned reference with brake points moved later, so that the motion controller brakes too
// late and the stability controller has to catch the car. Applied once, at preparation time
// (PrepareReference, controller/planning/reference.h).
//
// Places on the track: an event's place is `s` itself (corner 0) or the apex of corner k
// (plant/track/corners.h, 1-based, as `scw track info` lists them) plus `s`, wrapped into [0, L);
// the closed loop's timed events (tuning/sim/events.h) use the same rule.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "controller/planning/path.h"
#include "params/schema/event_params.h"
#include "plant/track/corners.h"
#include "plant/track/track.h"

namespace scw::controller::planning {

/// Arc length on the track of an event place (see above). Throws ConfigError naming
/// `key`.corner and element `index` when the track has fewer corners.
double EventPlace(const plant::Track& track, double corner, double s, const std::string& key,
                  std::size_t index);

/// EventPlace with the track's corners already found (one scan for many places).
double PlaceOn(const plant::Track& track, const std::vector<plant::Corner>& corners, double corner,
               double s, const std::string& key, std::size_t index);

/// The reference with every late-braking event applied: for each, the braking zone (a run of
/// decreasing target speed) whose slowest point lies nearest to the event's place; its brake
/// point moves later by min(distance, 0.8 × zone length), the speed stays at the zone's entry
/// speed until then, and the original speed curve is compressed into the remaining distance (same
/// speed at the slowest point, more deceleration). a_x is recomputed from v over the zone. Throws
/// ConfigError as EventPlace.
Path LateBrakingPath(const Path& path, const params::LateBraking& late, const plant::Track& track);

}  // namespace scw::controller::planning
