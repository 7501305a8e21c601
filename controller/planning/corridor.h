// The corridor of a reference: the room left and right of the path at each of its stations, from
// the track's widths, capped so that an MPC never plans towards an abort. The MPC motion
// controllers constrain their plans with it (controller/motion/mpc_common.h holds the same two
// lists). Built per motion controller, not per preparation: the cap follows the run's abort
// threshold, which a sweep may vary over one prepared reference.
#pragma once

#include <vector>

#include "controller/planning/path.h"

namespace scw::plant {
class Track;  // plant/track/track.h; only MakeCorridor needs it
}  // namespace scw::plant

namespace scw::controller::planning {

struct Corridor {
  std::vector<double> left;   ///< [m] ≥ 0, room to the left of the path, per path station
  std::vector<double> right;  ///< [m] ≥ 0, room to the right of the path, per path station
};

/// Per station of `path`: the distance from the station to the track's left and right edge
/// (the station projected onto `track`), each clamped to [0, cap] [m].
Corridor MakeCorridor(const plant::Track& track, const Path& path, double cap);

}  // namespace scw::controller::planning
