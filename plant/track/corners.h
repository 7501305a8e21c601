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

/// A corner's length [m]: its nodes plus the node spacing after the last one (a corner of one node
/// is one spacing long), measured forward across s = 0 for a corner over the start line.
double CornerLength(const Corner& corner, const Track& track);

/// Corners the rule counts although a driver may not call them corners: shorter than
/// kShortCornerLength (a few nodes just below the radius threshold) or with a smallest radius
/// above kKinkRadius (a bend far gentler than the others). `scw track info` flags them; they keep
/// their numbers, since scenario files name corners by number.
inline constexpr double kShortCornerLength = 10.0;  // [m]
inline constexpr double kKinkRadius = 150.0;        // [m]
bool IsShortCorner(const Corner& corner, const Track& track);
inline bool IsKink(const Corner& corner) { return corner.min_radius > kKinkRadius; }

}  // namespace scw::plant
