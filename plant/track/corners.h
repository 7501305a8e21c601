// The corners of a track, numbered as a driver reads the lap: runs of curvature |κ| > 1/250 m⁻¹
// (radius below 250 m) of one sign, joined across gaps of less than 20 m, numbered from the first
// corner after the start line (the scan begins on a straight node, so no corner is split at s = 0).
// `scw track info` prints them; scenario events name a corner by its number (tuning/sim/events.h).
#pragma once

#include <vector>

#include "plant/track/track.h"

namespace scw::plant {

struct Corner {
  int number = 0;           ///< 1-based, in driving order from the start line
  bool left = true;         ///< turning direction (κ > 0)
  double s_from = 0.0;      ///< [m] first node above the curvature threshold
  double s_to = 0.0;        ///< [m] last node above it
  double min_radius = 0.0;  ///< [m]
  double s_apex = 0.0;      ///< [m] node of the smallest radius
};

/// Corners of `track` (pure; a straight-free track without any run returns an empty list).
std::vector<Corner> FindCorners(const Track& track);

}  // namespace scw::plant
